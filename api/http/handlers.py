"""Error handlers: every failure becomes ``{"detail": one line}`` with its status.

Library failures (:class:`geomcheck.errors.GeomcheckError`) and upload failures
(:mod:`api.errors`) keep their ``http_status``. Nothing reaches the client as a traceback;
unexpected exceptions are logged and answered with a 500 naming their type.
"""

from __future__ import annotations

import logging

import sqlalchemy as sa
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.requests import ClientDisconnect

from api.errors import Overloaded, one_line
from api.store import StorageError
from geomcheck.errors import GeomcheckError

log = logging.getLogger("geomcheck.api")


def error_response(status: int, detail: object, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse({"detail": one_line(detail)}, status_code=status, headers=headers)


def _validation_detail(exc: RequestValidationError) -> str:
    parts = []
    for err in exc.errors():
        where = ".".join(str(p) for p in err.get("loc", ()) if p not in ("query", "body", "path"))
        parts.append(f"{err.get('loc', ('?',))[0]} parameter '{where}': {err.get('msg', 'invalid')}")
    return "; ".join(parts) or "invalid request"


def install_handlers(app: FastAPI) -> None:
    """Register the one-line JSON error handlers on ``app``."""

    async def geomcheck_error(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, GeomcheckError)
        headers = {"Retry-After": "5"} if isinstance(exc, Overloaded) else None
        return error_response(exc.http_status, exc, headers)

    async def validation_error(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, RequestValidationError)
        return error_response(400, _validation_detail(exc))  # a bad parameter is a usage error, like a bad option

    async def http_error(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, StarletteHTTPException)
        return error_response(exc.status_code, exc.detail, dict(exc.headers or {}))

    async def disconnected(request: Request, exc: Exception) -> JSONResponse:
        log.info("client left during %s %s", request.method, request.url.path)
        return error_response(400, "the client disconnected before the request body was complete")

    async def database_error(request: Request, exc: Exception) -> JSONResponse:
        log.warning("database error on %s %s: %s", request.method, request.url.path, type(exc).__name__)
        return error_response(503, "the database does not answer; retry later", {"Retry-After": "5"})

    async def unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unhandled error on %s %s", request.method, request.url.path)
        return error_response(500, f"internal error ({type(exc).__name__})")

    app.add_exception_handler(GeomcheckError, geomcheck_error)
    app.add_exception_handler(RequestValidationError, validation_error)
    app.add_exception_handler(StarletteHTTPException, http_error)
    app.add_exception_handler(ClientDisconnect, disconnected)
    # an outage of the database (PostgreSQL restarting, the network away) is the service's
    # unavailability, not a bug: 503 with a retry hint, as /healthz says
    app.add_exception_handler(sa.exc.OperationalError, database_error)
    app.add_exception_handler(sa.exc.InterfaceError, database_error)
    app.add_exception_handler(StorageError, database_error)
    app.add_exception_handler(Exception, unexpected)
