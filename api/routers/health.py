"""``GET /healthz``: liveness and readiness, open without a token."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse
from starlette.concurrency import run_in_threadpool

from api.schemas import HealthOut
from geomcheck import __version__

router = APIRouter(tags=["health"])


@router.get(
    "/healthz",
    response_model=HealthOut,
    summary="Service health",
    responses={503: {"model": HealthOut, "description": "the database does not answer"}},
)
async def healthz(request: Request) -> JSONResponse:
    """Answers while checks run (they run in other processes); 503 when the database does not answer."""
    service = request.app.state.service
    database_ok = await run_in_threadpool(service.store.ping)
    body = HealthOut(
        status="ok" if database_ok else "degraded",
        version=__version__,
        database="ok" if database_ok else "unavailable",
        workers=service.settings.workers,
        running=service.runner.running,
        pending=service.pending,
    )
    return JSONResponse(body.model_dump(), status_code=200 if database_ok else 503)
