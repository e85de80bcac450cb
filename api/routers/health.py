"""``/healthz`` (liveness), ``/readyz`` (database and broker reachable) and ``/metrics``, open without a token."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import JSONResponse, Response
from starlette.concurrency import run_in_threadpool

from api.http.deps import ServiceDep
from api.http.metrics import CONTENT_TYPE, render_metrics
from api.http.schemas import HealthOut
from geomcheck import __version__

router = APIRouter(tags=["health"])


@router.get(
    "/healthz",
    response_model=HealthOut,
    summary="Service health",
    responses={503: {"model": HealthOut, "description": "the database does not answer"}},
)
async def healthz(service: ServiceDep) -> JSONResponse:
    """Answers while checks run (they run in other processes); 503 when the database does not answer."""
    database_ok = await run_in_threadpool(service.store.ping)
    try:  # the distributed service counts in the database
        running, pending = await run_in_threadpool(lambda: (service.running, service.pending))
    except Exception:
        running = pending = 0
    body = HealthOut(
        status="ok" if database_ok else "degraded",
        version=__version__,
        database="ok" if database_ok else "unavailable",
        workers=service.settings.workers,
        running=running,
        pending=pending,
    )
    return JSONResponse(body.model_dump(), status_code=200 if database_ok else 503)


@router.get(
    "/readyz",
    summary="Readiness: the database and (distributed mode) the broker answer",
    responses={503: {"description": "the database or the broker does not answer"}},
)
async def readyz(service: ServiceDep) -> JSONResponse:
    """``{"ready": bool, "database": "ok"|"unavailable", "broker": "ok"|"unavailable"|"not used"}``."""
    checks: dict[str, bool] = await run_in_threadpool(service.readiness)
    body: dict[str, object] = {name: "ok" if ok else "unavailable" for name, ok in checks.items()}
    body.setdefault("broker", "not used")
    ready = all(checks.values())
    body = {"ready": ready, **body}
    return JSONResponse(body, status_code=200 if ready else 503)


@router.get(
    "/metrics",
    summary="Prometheus metrics: checks by status, queue depth, check-duration histogram",
    response_class=Response,
    responses={200: {"content": {"text/plain": {}}}},
)
async def metrics(service: ServiceDep) -> Response:
    settings = service.settings
    dead_letters = None
    if settings.distributed:  # Celery is imported by the distributed mode only
        from api.distributed.deadletters import dead_letter_count

        def dead_letters() -> int | None:
            return dead_letter_count(settings)

    text = await run_in_threadpool(render_metrics, service.store, settings.distributed, dead_letters)
    return Response(text, media_type=CONTENT_TYPE)
