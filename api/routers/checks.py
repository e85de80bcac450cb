"""``/v1/checks``: submit a description, follow the check, download its report."""

from __future__ import annotations

import asyncio
import json
import secrets
import time
from typing import Any, Literal, get_args

from fastapi import APIRouter, Depends, HTTPException, Query, Request
from fastapi.responses import JSONResponse, Response
from starlette.concurrency import run_in_threadpool

from api.checks.job import FIXES_VERIFYING, CheckJob
from api.checks.options import REQUEST_ONLY, RawOptions, request_config
from api.checks.service import Service, asked_options
from api.http.auth import Client, require_token
from api.http.handlers import error_response
from api.http.openapi import CHECK_REQUEST_BODY, OPTION_PARAMETERS
from api.http.schemas import CheckOut, CheckPage, ErrorOut, ReportOut
from api.results.cache import fail_on_value, request_key, rerender, restamp, upload_keys
from api.results.compressed import CompressedReports, gzip_around
from api.results.html import download_name, report_html
from api.results.srdf import matrix_srdf
from api.store import STATUSES, CacheKeys, CheckRecord, Shared
from api.uploads.body import SUPPORTED_TYPES, discard, media_type, receive, unpack_received
from api.uploads.layout import arrange
from api.uploads.tree import UploadLimits, UploadTree
from geomcheck.option_spec import parse_bool
from geomcheck.report import Report, render

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


DRAIN_POLL_S = 0.25  # how often a waiting POST looks whether the service is shutting down [s]
PATCH_POLL_S = 0.25  # how often a patch asked for while the fixes are verified looks whether they are [s]
DRAIN_MARGIN_S = 1.0  # a waiting POST answers this long before uvicorn closes its connection [s]


def drained(request: Request) -> bool:
    """Whether the service is shutting down (SIGTERM) and a waiting POST must answer now:
    ``shutdown_timeout_s`` after the signal, less a margin, before uvicorn cancels it."""
    since = getattr(request.app.state, "draining_since", None)
    if since is None:
        return False
    grace = max(1, round(request.app.state.settings.shutdown_timeout_s)) - DRAIN_MARGIN_S
    return time.monotonic() - since >= grace


def _service(request: Request) -> Service:
    service: Service = request.app.state.service
    return service


def check_path(request: Request, check_id: str, suffix: str = "") -> str:
    return f"{request.scope.get('root_path', '')}/v1/checks/{check_id}{suffix}"


def check_out(
    request: Request, record: CheckRecord, client: Client, report: dict[str, Any] | None = None
) -> dict[str, Any]:
    """The JSON of :class:`CheckOut` for ``record`` as ``client`` may see it (the report is
    passed through unchanged): a check answered from another client's result does not name it."""
    cached_from = record.cached_from if client.sees(record.origin_client) else None
    links: dict[str, str | None] = {
        "self": check_path(request, record.id),
        "report_json": check_path(request, record.id, "/report.json"),
        "report_html": check_path(request, record.id, "/report.html"),
        "report_sarif": check_path(request, record.id, "/report.sarif"),
        "report_junit": check_path(request, record.id, "/report.junit.xml"),
        "fixes_patch": check_path(request, record.id, "/fixes.patch"),
        "collision_matrix_srdf": None,
    }
    if record.has_matrix:
        links["collision_matrix_srdf"] = check_path(request, record.id, "/collision-matrix.srdf")
    body = CheckOut.model_validate(
        {
            "id": record.id,
            "status": record.status,
            "created": record.created,
            "started": record.started,
            "finished": record.finished,
            "source": record.source,
            "robot": record.robot,
            "verdict": record.verdict,
            "summary": record.summary,
            "http_status": record.http_status,
            "reason": record.reason,
            "seconds": record.seconds,
            "progress": record.progress,
            "options": record.options,
            "cached": record.cached_from is not None,
            "cached_from": cached_from,
            "fixes": {"status": record.fixes, "reason": record.fixes_reason} if record.fixes else None,
            "root": record.root,
            "links": links,
        }
    ).model_dump(mode="json", by_alias=True)
    body["report"] = report
    return body


def _record_or_404(service: Service, check_id: str, client: Client) -> CheckRecord:
    """The check, when ``client`` owns it (or is an admin); 404 otherwise, as for an unknown id,
    so another client's ids cannot even be confirmed."""
    record = service.store.get(check_id)
    if record is None or not client.sees(record.client):
        raise HTTPException(404, f"no check with id {check_id!r}")
    return record


def _report_or_409(service: Service, check_id: str, client: Client) -> tuple[CheckRecord, str]:
    record = _record_or_404(service, check_id, client)
    text = service.store.report(check_id) if record.status == "succeeded" else None
    if text is None:
        why = f": {record.reason}" if record.reason else ""
        raise HTTPException(409, f"check {check_id} has no report (status {record.status}{why})")
    return record, text


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
    service = _service(request)
    settings = service.settings
    raw = RawOptions()
    raw.add_pairs(((k, v) for k, v in request.query_params.multi_items() if k not in REQUEST_ONLY), "query")
    asked = request_config(raw, settings.max_samples, settings.work_dir)  # bad options refused before the body
    if media_type(request) not in SUPPORTED_TYPES:
        shown = media_type(request) or "none"
        return error_response(415, f"unsupported Content-Type {shown!r}; use one of {', '.join(SUPPORTED_TYPES)}")
    check_id = secrets.token_urlsafe(16)
    workdir = settings.work_dir / check_id
    limits = UploadLimits(settings.max_files, settings.max_unpacked_bytes, settings.max_ratio, settings.max_path_length)
    trees: list[UploadTree] = []

    def make_tree() -> UploadTree:  # the work folder is made only for a body that must be unpacked
        if not trees:
            trees.append(UploadTree(workdir / "tree", limits))
        return trees[0]

    submitted = reserved = False
    future = None
    try:
        received = await receive(request, workdir, make_tree, raw, root)
        use_cache = cache and (received.cache is None or parse_bool(received.cache, "cache"))
        fast_key = None
        if received.sha256 is not None:  # a document or archive: the query holds every option
            fast_key = request_key(received.kind, received.sha256, root, raw, settings, verify_fixes)
        if use_cache and fast_key is not None:
            keys = CacheKeys(request_key=fast_key)
            shared = await run_in_threadpool(
                service.store.share,
                check_id,
                None,
                None,
                keys,
                fail_on_value(asked),
                rerender,
                client.name,
                None,
                restamp,
            )
            if shared is not None:
                return await _answer_shared(request, service, shared, wait, client)
        upload = await unpack_received(received, make_tree, raw, root)
        layout = await run_in_threadpool(arrange, upload.tree.root, upload.root, upload.srdf, settings.max_path_length)
        config = request_config(raw, settings.max_samples, layout.display_root, layout.srdf)
        job = CheckJob(
            check_id,
            layout.root_file,
            layout.display_root,
            layout.search_root,
            config,
            client.name,
            verify_fixes=verify_fixes,
        )
        keys = await run_in_threadpool(upload_keys, job, fast_key)
        chosen = layout.root_choice.to_dict() if layout.root_choice is not None else None
        if use_cache and keys.result_key is not None:
            source = layout.root_file.relative_to(layout.display_root).as_posix()
            shared = await run_in_threadpool(
                service.store.share,
                check_id,
                source,
                asked_options(job),
                keys,
                fail_on_value(config),
                rerender,
                client.name,
                chosen,
                restamp,
            )
            if shared is not None:
                return await _answer_shared(request, service, shared, wait, client)
        # a place in the queue is taken once the body has arrived, so slow uploads hold none
        service.reserve()
        reserved = True
        future = await run_in_threadpool(service.submit, job, workdir, raw, keys, chosen)
        submitted = True
    finally:
        if reserved and not submitted:
            service.release()
        if not submitted and workdir.exists():
            await run_in_threadpool(discard, workdir)
    location = {"Location": check_path(request, check_id)}
    if not wait:
        record = await run_in_threadpool(_record_or_404, service, check_id, client)
        return JSONResponse(check_out(request, record, client), status_code=202, headers=location)
    return await _answer_finished(request, service, check_id, future, client)


async def _answer_finished(request: Request, service: Service, check_id: str, future: Any, client: Client) -> Response:
    """201 with the report once the check finished, its error, or 202 when it has not in time."""
    location = {"Location": check_path(request, check_id)}
    waiting = asyncio.ensure_future(service.wait_finished(check_id, future))
    while True:
        done, _ = await asyncio.wait({waiting}, timeout=DRAIN_POLL_S)
        if done:
            break
        if drained(request):
            waiting.cancel()
            return error_response(
                503, "the service is shutting down: the check was stopped; submit it again", {"Retry-After": "5"}
            )
    finished = waiting.result()
    if finished is None:  # not finished within GEOMCHECK_WAIT_S; poll the Location
        record = await run_in_threadpool(_record_or_404, service, check_id, client)
        return JSONResponse(check_out(request, record, client), status_code=202, headers=location)
    if not finished.outcome.ok:
        return error_response(finished.outcome.status, finished.outcome.reason)
    report_json = finished.outcome.value.report_json
    return await report_answer(request, service, finished.record, client, 201, location, report_json)


async def _answer_shared(request: Request, service: Service, shared: Shared, wait: bool, client: Client) -> Response:
    """The answer to a check shared with an identical one: finished (its report at once) or in flight."""
    record = shared.record
    location = {"Location": check_path(request, record.id)}
    if not wait:
        return JSONResponse(check_out(request, record, client), status_code=202, headers=location)
    if shared.following:
        return await _answer_finished(request, service, record.id, None, client)
    return await report_answer(request, service, record, client, 201, location, holder=shared.holder)


async def report_answer(
    request: Request,
    service: Service,
    record: CheckRecord,
    client: Client,
    status: int,
    headers: dict[str, str],
    report_json: str | None = None,
    holder: str | None = None,
) -> Response:
    """:func:`check_out` of ``record`` with its report spliced in as stored (never parsed and
    written again). Gzip'd when the client accepts it, from the report compressed once
    (:mod:`api.results.compressed`); ``report_json`` is the report when the caller has it at hand,
    ``holder`` the check whose row holds it when the caller knows it."""
    head = json.dumps(check_out(request, record, client), ensure_ascii=False, separators=(",", ":"))
    assert head.endswith(',"report":null}')
    head = head[: -len("null}")]
    if report_json is not None:
        holder = record.id
    elif holder is None:
        holder = await run_in_threadpool(service.store.report_holder, record.id)
    if holder is not None and "gzip" in request.headers.get("accept-encoding", "").lower():
        cache: CompressedReports = request.app.state.compressed_reports
        entry = cache.get(holder)
        if entry is None:
            text = report_json if report_json is not None else await run_in_threadpool(service.store.report, holder)
            entry = await run_in_threadpool(cache.put, holder, (text or "null").strip().encode("utf-8"))
        body = gzip_around(head.encode("utf-8"), entry, b"}")
        zipped = {**headers, "Content-Encoding": "gzip", "Vary": "Accept-Encoding"}
        return Response(body, status_code=status, media_type="application/json", headers=zipped)
    if report_json is None and holder is not None:
        report_json = await run_in_threadpool(service.store.report, holder)
    text = head + (report_json or "null").strip() + "}"
    return Response(text.encode("utf-8"), status_code=status, media_type="application/json", headers=headers)


@router.get("", response_model=CheckPage, summary="Recent checks, newest first")
def list_checks(
    request: Request,
    limit: int | None = Query(None, ge=1, le=200, description="page size (default 20)"),
    cursor: str | None = Query(None, description="next_cursor of the previous page"),
    status: StatusName | None = Query(None, description=f"only checks with this status: {', '.join(STATUSES)}"),
    client: Client = Depends(require_token),
) -> JSONResponse:
    """The client's own checks (every client's for an admin token)."""
    service = _service(request)
    page = limit or service.settings.page_size
    records, next_cursor = service.store.recent(page, cursor, status, client.scope)
    return JSONResponse({"items": [check_out(request, r, client) for r in records], "next_cursor": next_cursor})


@router.get("/{check_id}", response_model=CheckOut, summary="A check: status and report", responses=NOT_FOUND)
def read_check(request: Request, check_id: str, client: Client = Depends(require_token)) -> JSONResponse:
    service = _service(request)
    record = _record_or_404(service, check_id, client)
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
def cancel_check(request: Request, check_id: str, client: Client = Depends(require_token)) -> JSONResponse:
    """Cancel the check: it will not run, or its process is killed; answers the check, now ``cancelled``."""
    service = _service(request)
    _record_or_404(service, check_id, client)
    if not service.cancel(check_id):
        record = _record_or_404(service, check_id, client)
        raise HTTPException(409, f"check {check_id} has already finished (status {record.status})")
    return JSONResponse(check_out(request, _record_or_404(service, check_id, client), client))


@router.get(
    "/{check_id}/report.json",
    summary="The JSON report (the bytes `geomcheck check --format json` writes)",
    response_model=ReportOut,
    responses={200: {"content": {"application/json": {}}}, **NOT_FOUND, **NOT_READY},
)
def read_report_json(request: Request, check_id: str, client: Client = Depends(require_token)) -> Response:
    record, text = _report_or_409(_service(request), check_id, client)
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
def read_report_html(request: Request, check_id: str, client: Client = Depends(require_token)) -> Response:
    record, text = _report_or_409(_service(request), check_id, client)
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

    def read_report(request: Request, check_id: str, client: Client = Depends(require_token)) -> Response:
        record, text = _report_or_409(_service(request), check_id, client)
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
def read_matrix_srdf(request: Request, check_id: str, client: Client = Depends(require_token)) -> Response:
    record, text = _report_or_409(_service(request), check_id, client)
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
    request: Request,
    check_id: str,
    unsafe: bool = Query(False, description="include unsafe fixes: fitted collision primitives, inertias"),
    client: Client = Depends(require_token),
) -> Response:
    """The safe fixes (all of them with ``unsafe=true``) of the check's findings, from the
    report's ``fixes`` section, verified as ``geomcheck fix`` verifies them: each applied to a
    copy of the upload and checked again. The report is answered before that verification
    ends; a patch asked for meanwhile waits for it (up to ``GEOMCHECK_WAIT_S``, then a 409 to
    retry). The ``Geomcheck-Fixes`` header says what the patch is: ``verified``, or the planned
    patch when verification was turned off (``unverified``) or did not finish (``failed``)."""
    service = _service(request)
    deadline = time.monotonic() + service.settings.wait_s
    while True:
        record, text = await run_in_threadpool(_report_or_409, service, check_id, client)
        if record.fixes != FIXES_VERIFYING:
            break
        if time.monotonic() >= deadline or drained(request):
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
