"""What the ``/v1/checks`` handlers answer: a check as a client may see it, and a finished
check's report spliced into the answer as stored."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from fastapi import HTTPException, Request
from fastapi.responses import JSONResponse, Response
from starlette.concurrency import run_in_threadpool

from api.checks.service import Service
from api.http.auth import Client
from api.http.deps import CompressedReportsDep, DrainedDep, ServiceDep
from api.http.handlers import error_response
from api.http.schemas import CheckOut
from api.results.compressed import CompressedReports, gzip_around
from api.store import CheckRecord, Shared

DRAIN_POLL_S = 0.25  # how often a waiting POST looks whether the service is shutting down [s]


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


def record_or_404(service: Service, check_id: str, client: Client) -> CheckRecord:
    """The check, when ``client`` owns it (or is an admin); 404 otherwise, as for an unknown id,
    so another client's ids cannot even be confirmed."""
    record = service.store.get(check_id)
    if record is None or not client.sees(record.client):
        raise HTTPException(404, f"no check with id {check_id!r}")
    return record


def report_or_409(service: Service, check_id: str, client: Client) -> tuple[CheckRecord, str]:
    record = record_or_404(service, check_id, client)
    text = service.store.report(check_id) if record.status == "succeeded" else None
    if text is None:
        why = f": {record.reason}" if record.reason else ""
        raise HTTPException(409, f"check {check_id} has no report (status {record.status}{why})")
    return record, text


@dataclass
class Answers:
    """The answers of a ``POST /v1/checks`` to ``client``: a check shared from an identical one,
    or one queued, once it finished (or when waiting must end)."""

    request: Request
    service: Service
    drained: Callable[[], bool]
    reports: CompressedReports

    async def finished(self, check_id: str, future: Any, client: Client) -> Response:
        """201 with the report once the check finished, its error, or 202 when it has not in time."""
        location = {"Location": check_path(self.request, check_id)}
        waiting = asyncio.ensure_future(self.service.wait_finished(check_id, future))
        while True:
            done, _ = await asyncio.wait({waiting}, timeout=DRAIN_POLL_S)
            if done:
                break
            if self.drained():
                waiting.cancel()
                return error_response(
                    503, "the service is shutting down: the check was stopped; submit it again", {"Retry-After": "5"}
                )
        finished = waiting.result()
        if finished is None:  # not finished within GEOMCHECK_WAIT_S; poll the Location
            return await self.queued(check_id, client)
        if not finished.outcome.ok:
            return error_response(finished.outcome.status, finished.outcome.reason)
        report_json = finished.outcome.value.report_json
        return await self.report(finished.record, client, 201, location, report_json)

    async def queued(self, check_id: str, client: Client) -> Response:
        """202 with the check as it is now: poll its Location."""
        record = await run_in_threadpool(record_or_404, self.service, check_id, client)
        location = {"Location": check_path(self.request, check_id)}
        return JSONResponse(check_out(self.request, record, client), status_code=202, headers=location)

    async def shared(self, shared: Shared, wait: bool, client: Client) -> Response:
        """The answer to a check shared with an identical one: finished (its report at once) or in flight."""
        record = shared.record
        location = {"Location": check_path(self.request, record.id)}
        if not wait:
            return JSONResponse(check_out(self.request, record, client), status_code=202, headers=location)
        if shared.following:
            return await self.finished(record.id, None, client)
        return await self.report(record, client, 201, location, holder=shared.holder)

    async def report(
        self,
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
        head = json.dumps(check_out(self.request, record, client), ensure_ascii=False, separators=(",", ":"))
        assert head.endswith(',"report":null}')
        head = head[: -len("null}")]
        store = self.service.store
        if report_json is not None:
            holder = record.id
        elif holder is None:
            holder = await run_in_threadpool(store.report_holder, record.id)
        if holder is not None and "gzip" in self.request.headers.get("accept-encoding", "").lower():
            entry = self.reports.get(holder)
            if entry is None:
                text = report_json if report_json is not None else await run_in_threadpool(store.report, holder)
                entry = await run_in_threadpool(self.reports.put, holder, (text or "null").strip().encode("utf-8"))
            body = gzip_around(head.encode("utf-8"), entry, b"}")
            zipped = {**headers, "Content-Encoding": "gzip", "Vary": "Accept-Encoding"}
            return Response(body, status_code=status, media_type="application/json", headers=zipped)
        if report_json is None and holder is not None:
            report_json = await run_in_threadpool(store.report, holder)
        text = head + (report_json or "null").strip() + "}"
        return Response(text.encode("utf-8"), status_code=status, media_type="application/json", headers=headers)


def answers_for(request: Request, service: ServiceDep, drained: DrainedDep, reports: CompressedReportsDep) -> Answers:
    return Answers(request, service, drained, reports)


__all__ = ["Answers", "answers_for", "check_out", "check_path", "record_or_404", "report_or_409"]
