"""``/v1/checks``: submit a description, follow the check, download its report."""

from __future__ import annotations

import asyncio
import json
import time
from typing import Annotated, Any, Literal, get_args

from fastapi import APIRouter, Depends, HTTPException, Query, Request
from fastapi.responses import JSONResponse, Response
from starlette.concurrency import run_in_threadpool

from api.checks.job import FIXES_VERIFYING
from api.checks.options import REQUEST_ONLY
from api.checks.submission import Submission
from api.http.auth import Client, require_token
from api.http.deps import DrainedDep, ServiceDep
from api.http.handlers import error_response
from api.http.openapi import CHECK_REQUEST_BODY, OPTION_PARAMETERS
from api.http.schemas import CheckOut, CheckPage, ErrorOut, ReportOut
from api.results.html import download_name, report_html
from api.results.srdf import matrix_srdf
from api.routers.answers import Answers, answers_for, check_out, record_or_404, report_or_409
from api.store import STATUSES, Shared
from api.uploads.body import SUPPORTED_TYPES, media_type
from geomcheck.report import Report, render

__all__ = ["REQUEST_ONLY", "create_check", "router"]

AnswersDep = Annotated[Answers, Depends(answers_for)]
router = APIRouter(prefix="/v1/checks", tags=["checks"], dependencies=[Depends(require_token)])

StatusName = Literal["queued", "running", "succeeded", "failed", "cancelled"]  # an enum in the OpenAPI document
assert get_args(StatusName) == STATUSES
ERRORS: dict[int | str, dict[str, Any]] = {
    400: {"model": ErrorOut, "description": "bad option, parameter, form field, archive entry or path"},
    401: {"model": ErrorOut, "description": "missing or invalid bearer token (when tokens are configured)"},
    413: {
        "model": ErrorOut,
        "description": "body, file count, unpacked size or compression ratio over a limit, "
        "or a description over a loading limit (macro nesting or calls, expanded size)",
    },
    408: {"model": ErrorOut, "description": "the body did not arrive within the body timeout (a stalled upload)"},
    415: {"model": ErrorOut, "description": f"Content-Type not one of {', '.join(SUPPORTED_TYPES)}"},
    422: {
        "model": ErrorOut,
        "description": "the description cannot be read (malformed XML, xacro error, access outside the upload) "
        "or the check exceeded its CPU, memory or time limit",
    },
    503: {"model": ErrorOut, "description": "too many checks queued; retry later"},
}
LOCATION = {"Location": {"description": "path of the check: /v1/checks/{id}", "schema": {"type": "string"}}}
NOT_FOUND: dict[int | str, dict[str, Any]] = {404: {"model": ErrorOut, "description": "no check with this id"}}
NOT_READY: dict[int | str, dict[str, Any]] = {
    409: {"model": ErrorOut, "description": "the check has no report (queued, running or failed)"}
}


PATCH_POLL_S = 0.25  # how often a patch asked for while the fixes are verified looks whether they are [s]


@router.post(
    "",
    status_code=201,
    response_model=CheckOut,
    summary="Check a robot description",
    responses={
        201: {"description": "the check ran; the body holds its report", "headers": LOCATION},
        202: {
            "model": CheckOut,
            "description": "with ?wait=false: queued; poll the Location (the status URL)",
            "headers": LOCATION,
        },
        **ERRORS,
    },
    openapi_extra={"requestBody": CHECK_REQUEST_BODY, "parameters": OPTION_PARAMETERS},
)
async def create_check(
    request: Request,
    service: ServiceDep,
    answer: AnswersDep,
    root: str | None = Query(None, description="root file, as a path in the upload (archives, form files)"),
    wait: bool = Query(True, description="false: answer 202 at once and run the check in the background"),
    cache: bool = Query(
        True, description="false: run the check even when an identical one was checked before (also a form field)"
    ),
    verify_fixes: bool = Query(
        True,
        description="false: do not verify the offered fixes after the report (fixes.patch then serves the planned "
        "patches, marked unverified)",
    ),
    # the options' query parameters (api.http.openapi.OPTION_PARAMETERS) are read from the query
    # string by RawOptions, not by FastAPI: one parse, the same validation as the form fields
    client: Client = Depends(require_token),
) -> Response:
    """Submit a URDF or xacro document, a multipart form of package files, or an archive of the
    package tree. Answers 201 with the report, or 202 with a status URL when ``wait=false``."""
    submission = Submission.from_query(service, request.query_params, root, cache, verify_fixes, client.name)
    if media_type(request) not in SUPPORTED_TYPES:
        shown = media_type(request) or "none"
        return error_response(415, f"unsupported Content-Type {shown!r}; use one of {', '.join(SUPPORTED_TYPES)}")
    outcome = await submission.submit(request)
    if isinstance(outcome, Shared):
        return await answer.shared(outcome, wait, client)
    if not wait:
        return await answer.queued(outcome.check_id, client)
    return await answer.finished(outcome.check_id, outcome.future, client)


@router.get("", response_model=CheckPage, summary="Recent checks, newest first")
def list_checks(
    request: Request,
    service: ServiceDep,
    limit: int | None = Query(None, ge=1, le=200, description="page size (default 20)"),
    cursor: str | None = Query(None, description="next_cursor of the previous page"),
    status: StatusName | None = Query(None, description=f"only checks with this status: {', '.join(STATUSES)}"),
    client: Client = Depends(require_token),
) -> JSONResponse:
    """The client's own checks (every client's for an admin token)."""
    page = limit or service.settings.page_size
    records, next_cursor = service.store.recent(page, cursor, status, client.scope)
    return JSONResponse({"items": [check_out(request, r, client) for r in records], "next_cursor": next_cursor})


@router.get("/{check_id}", response_model=CheckOut, summary="A check: status and report", responses=NOT_FOUND)
def read_check(
    request: Request, check_id: str, service: ServiceDep, client: Client = Depends(require_token)
) -> JSONResponse:
    record = record_or_404(service, check_id, client)
    text = service.store.report(check_id) if record.status == "succeeded" else None
    return JSONResponse(check_out(request, record, client, json.loads(text) if text else None))


@router.delete(
    "/{check_id}",
    response_model=CheckOut,
    summary="Cancel a queued or running check",
    responses={
        **NOT_FOUND,
        409: {"model": ErrorOut, "description": "the check has already finished (succeeded, failed or cancelled)"},
    },
)
def cancel_check(
    request: Request, check_id: str, service: ServiceDep, client: Client = Depends(require_token)
) -> JSONResponse:
    """Cancel the check: it will not run, or its process is killed; answers the check, now ``cancelled``."""
    record_or_404(service, check_id, client)
    if not service.cancel(check_id):
        record = record_or_404(service, check_id, client)
        raise HTTPException(409, f"check {check_id} has already finished (status {record.status})")
    return JSONResponse(check_out(request, record_or_404(service, check_id, client), client))


@router.get(
    "/{check_id}/report.json",
    summary="The JSON report (the bytes `geomcheck check --format json` writes)",
    response_model=ReportOut,
    responses={200: {"content": {"application/json": {}}}, **NOT_FOUND, **NOT_READY},
)
def read_report_json(
    request: Request, check_id: str, service: ServiceDep, client: Client = Depends(require_token)
) -> Response:
    record, text = report_or_409(service, check_id, client)
    disposition = f'inline; filename="{download_name(record.robot, "-geomcheck.json")}"'
    return Response(text, media_type="application/json", headers={"Content-Disposition": disposition})


@router.get(
    "/{check_id}/report.html",
    summary="The report as a downloadable HTML page",
    response_class=Response,
    responses={
        200: {"content": {"text/html": {}}, "description": "an HTML page (attachment)"},
        **NOT_FOUND,
        **NOT_READY,
    },
)
def read_report_html(
    request: Request, check_id: str, service: ServiceDep, client: Client = Depends(require_token)
) -> Response:
    record, text = report_or_409(service, check_id, client)
    page = report_html(json.loads(text))
    disposition = f'attachment; filename="{download_name(record.robot, "-geomcheck.html")}"'
    return Response(page, media_type="text/html; charset=utf-8", headers={"Content-Disposition": disposition})


# report formats served besides JSON and HTML: format -> (URL suffix, media type, file suffix, title)
DOWNLOADS = {
    "sarif": ("/report.sarif", "application/sarif+json", "-geomcheck.sarif", "SARIF"),
    "junit": ("/report.junit.xml", "application/xml", "-geomcheck.junit.xml", "JUnit XML"),
}


def _download(fmt: str) -> Any:
    suffix, media, file_suffix, title = DOWNLOADS[fmt]

    def read_report(check_id: str, service: ServiceDep, client: Client = Depends(require_token)) -> Response:
        record, text = report_or_409(service, check_id, client)
        body = render(Report.from_dict(json.loads(text)), fmt)
        disposition = f'attachment; filename="{download_name(record.robot, file_suffix)}"'
        return Response(body, media_type=media, headers={"Content-Disposition": disposition})

    router.add_api_route(
        "/{check_id}" + suffix,
        read_report,
        methods=["GET"],
        name=f"read_report_{fmt}",
        summary=f"The report as {title} (what `geomcheck check --format {fmt}` writes)",
        response_class=Response,
        responses={200: {"content": {media: {}}}, **NOT_FOUND, **NOT_READY},
    )


for _fmt in DOWNLOADS:
    _download(_fmt)


@router.get(
    "/{check_id}/collision-matrix.srdf",
    summary="The computed collision matrix as a MoveIt SRDF",
    response_class=Response,
    responses={
        200: {"content": {"application/xml": {}}, "description": "SRDF with disable_collisions entries"},
        404: {"model": ErrorOut, "description": "no such check, or no matrix was computed (ask with matrix=true)"},
        **NOT_READY,
    },
)
def read_matrix_srdf(
    request: Request, check_id: str, service: ServiceDep, client: Client = Depends(require_token)
) -> Response:
    record, text = report_or_409(service, check_id, client)
    if not record.has_matrix:
        raise HTTPException(404, f"check {check_id} computed no collision matrix; submit it with matrix=true")
    srdf = matrix_srdf(json.loads(text))
    disposition = f'attachment; filename="{download_name(record.robot, ".srdf")}"'
    return Response(srdf, media_type="application/xml", headers={"Content-Disposition": disposition})


@router.get(
    "/{check_id}/fixes.patch",
    summary="The fixes of the check's findings as a unified diff against the uploaded files",
    response_class=Response,
    responses={
        200: {
            "content": {"text/x-diff": {}},
            "description": "a unified diff (`git apply`, `patch -p1`); empty when nothing is fixable",
            "headers": {
                "Geomcheck-Fixes": {
                    "description": "verified, or unverified / failed: the planned patch",
                    "schema": {"type": "string"},
                }
            },
        },
        **NOT_FOUND,
        409: {
            "model": ErrorOut,
            "description": "the check has no report (queued, running or failed), or its fixes are still being "
            "verified after waiting GEOMCHECK_WAIT_S",
        },
    },
)
async def read_fixes_patch(
    check_id: str,
    service: ServiceDep,
    drained: DrainedDep,
    unsafe: bool = Query(False, description="include unsafe fixes: fitted collision primitives, inertias"),
    client: Client = Depends(require_token),
) -> Response:
    """The safe fixes (all of them with ``unsafe=true``) of the check's findings, from the
    report's ``fixes`` section, verified as ``geomcheck fix`` verifies them: each applied to a
    copy of the upload and checked again. The report is answered before that verification
    ends; a patch asked for meanwhile waits for it (up to ``GEOMCHECK_WAIT_S``, then a 409 to
    retry). The ``Geomcheck-Fixes`` header says what the patch is: ``verified``, or the planned
    patch when verification was turned off (``unverified``) or did not finish (``failed``)."""
    deadline = time.monotonic() + service.settings.wait_s
    while True:
        record, text = await run_in_threadpool(report_or_409, service, check_id, client)
        if record.fixes != FIXES_VERIFYING:
            break
        if time.monotonic() >= deadline or drained():
            raise HTTPException(409, f"the fixes of check {check_id} are still being verified; retry shortly")
        await asyncio.sleep(PATCH_POLL_S)
    section = json.loads(text).get("sections", {}).get("fixes") or {}
    patch = section.get("unsafe_patch" if unsafe else "safe_patch", "")
    # the two patches under names of their own: downloading both keeps both (curl -O -J)
    suffix = "-unsafe-fixes.patch" if unsafe else "-fixes.patch"
    headers = {
        "Content-Disposition": f'attachment; filename="{download_name(record.robot, suffix)}"',
        "Geomcheck-Fixes": record.fixes or ("verified" if section.get("verified") else "unverified"),
    }
    return Response(patch, media_type="text/x-diff; charset=utf-8", headers=headers)
