"""What the route handlers are given by FastAPI's dependencies instead of reading the
application's state themselves: the check service, the settings, the compressed reports and
whether the service is shutting down."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Annotated

from fastapi import Depends, FastAPI, Request

from api.checks.service import Service
from api.results.compressed import CompressedReports
from api.settings import Settings

DRAIN_MARGIN_S = 1.0  # a waiting POST answers this long before uvicorn closes its connection [s]


def get_service(request: Request) -> Service:
    service: Service = request.app.state.service
    return service


def get_settings(request: Request) -> Settings:
    settings: Settings = request.app.state.settings
    return settings


def get_compressed_reports(request: Request) -> CompressedReports:
    reports: CompressedReports = request.app.state.compressed_reports
    return reports


def drained(app: FastAPI) -> bool:
    """Whether the service is shutting down (SIGTERM) and a waiting request must answer now:
    ``shutdown_timeout_s`` after the signal, less a margin, before uvicorn cancels it."""
    since = getattr(app.state, "draining_since", None)
    if since is None:
        return False
    grace = max(1, round(app.state.settings.shutdown_timeout_s)) - DRAIN_MARGIN_S
    return time.monotonic() - since >= grace


def get_drained(request: Request) -> Callable[[], bool]:
    app = request.app
    return lambda: drained(app)


ServiceDep = Annotated[Service, Depends(get_service)]
SettingsDep = Annotated[Settings, Depends(get_settings)]
CompressedReportsDep = Annotated[CompressedReports, Depends(get_compressed_reports)]
DrainedDep = Annotated[Callable[[], bool], Depends(get_drained)]

__all__ = [
    "CompressedReportsDep",
    "DrainedDep",
    "ServiceDep",
    "SettingsDep",
    "drained",
    "get_compressed_reports",
    "get_drained",
    "get_service",
    "get_settings",
]
