"""The web page: ``/`` (upload, follow, read and download a check) and ``/checks/{id}`` (the
same page on one check, a link to share), its static files, and
``POST /v1/root-candidates`` (the candidate root files of an upload, for the page's picker).

The page itself only calls the public HTTP API, so it works the same whatever runs the checks.
"""

from __future__ import annotations

import secrets
from pathlib import Path
from typing import Any

from fastapi import APIRouter, Depends, HTTPException, Request
from fastapi.responses import FileResponse, HTMLResponse, JSONResponse, Response
from fastapi.templating import Jinja2Templates
from starlette.concurrency import run_in_threadpool

from api.checks.options import RawOptions
from api.errors import Overloaded, UploadError
from api.http.auth import require_token
from api.http.deps import SettingsDep
from api.http.handlers import error_response
from api.http.schemas import ErrorOut
from api.settings import Settings
from api.uploads.body import SUPPORTED_TYPES, discard, media_type, read_upload
from api.uploads.layout import choose_root
from api.uploads.roots import root_candidates
from api.uploads.tree import UploadLimits, UploadTree
from api.web.forms import option_defaults, option_fields
from geomcheck import __version__

WEB = Path(__file__).resolve().parent.parent / "web"
STATIC = {"app.js": "text/javascript", "archive.js": "text/javascript", "app.css": "text/css"}
templates = Jinja2Templates(directory=WEB / "templates")
MAX_INSPECTING = 4  # uploads unpacked at once by POST /v1/root-candidates, each up to the unpacked-size limit

pages = APIRouter(include_in_schema=False)
router = APIRouter(tags=["web"], dependencies=[Depends(require_token)])


def _page(request: Request, settings: Settings, check_id: str | None) -> HTMLResponse:
    fields = option_fields(request.app.openapi(), option_defaults(settings.max_samples))
    context = {
        "base": request.scope.get("root_path", ""),
        "check_id": check_id or "",
        "fields": [f for f in fields if not f.advanced],
        "advanced": [f for f in fields if f.advanced],
        "settings": settings,
        "version": __version__,
    }
    return templates.TemplateResponse(request, "index.html", context)


@pages.get("/", response_class=HTMLResponse)
def index(request: Request, settings: SettingsDep) -> HTMLResponse:
    return _page(request, settings, None)


@pages.get("/checks/{check_id}", response_class=HTMLResponse)
def check_page(request: Request, check_id: str, settings: SettingsDep) -> HTMLResponse:
    return _page(request, settings, check_id)


@pages.get("/web/static/{name}")
def static(name: str) -> Response:
    if name not in STATIC:
        raise HTTPException(404, f"no static file {name!r}")
    # the version in the page's URLs changes with every release, so a day of caching is safe
    return FileResponse(WEB / "static" / name, media_type=STATIC[name], headers={"Cache-Control": "max-age=86400"})


@router.post(
    "/v1/root-candidates",
    summary="The candidate root files of an upload",
    responses={
        200: {
            "description": "`candidates`: files holding a robot description, likely root first (`path`, "
            "`robot`, `included`, `pulls_in`, `instantiates`, `referenced`, `missing`); `chosen`: the root a "
            "check with no `root` reads (`path`, `reason`, `alternatives`), or null with `why` when several "
            "robots are equally likely and the request must name one"
        },
        400: {"model": ErrorOut, "description": "bad archive entry, path or form field"},
        413: {"model": ErrorOut, "description": "file count or unpacked size over its limit"},
        415: {"model": ErrorOut, "description": "unsupported Content-Type"},
        503: {"model": ErrorOut, "description": "too many uploads being inspected; retry later"},
    },
)
async def list_root_candidates(request: Request, settings: SettingsDep) -> Response:
    """Unpack an upload (any body ``POST /v1/checks`` takes, under the same limits and checks)
    and list the files in it that hold a robot description (URDF and xacro ``<robot>``,
    MJCF ``<mujoco>``, SDFormat ``<sdf>``); nothing is kept."""
    if getattr(request.app.state, "inspecting", 0) >= MAX_INSPECTING:
        raise Overloaded(f"{MAX_INSPECTING} uploads are being inspected, the most at once; retry later")
    if media_type(request) not in SUPPORTED_TYPES:
        shown = media_type(request) or "none"
        return error_response(415, f"unsupported Content-Type {shown!r}; use one of {', '.join(SUPPORTED_TYPES)}")
    folder = settings.work_dir / f"candidates-{secrets.token_urlsafe(12)}"
    # counted on the event loop's thread only, so a plain integer is enough
    request.app.state.inspecting = getattr(request.app.state, "inspecting", 0) + 1
    try:
        folder.mkdir(parents=True)
        limits = UploadLimits(
            settings.max_files, settings.max_unpacked_bytes, settings.max_ratio, settings.max_path_length
        )
        upload = await read_upload(request, UploadTree(folder / "tree", limits), RawOptions(), None)
        found = await run_in_threadpool(root_candidates, upload.tree.root)
        try:
            chosen: dict[str, Any] | None = (
                await run_in_threadpool(choose_root, upload.tree.root, None, 4096)
            ).to_dict()
            why = None
        except UploadError as err:
            chosen, why = None, str(err)
    finally:
        request.app.state.inspecting -= 1
        await run_in_threadpool(discard, folder)
    items: list[dict[str, Any]] = [c.to_dict() for c in found]
    return JSONResponse({"candidates": items, "chosen": chosen, "why": why})
