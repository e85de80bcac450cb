"""The FastAPI application: ``create_app(settings)`` wires storage, the check service,
routers, the body-size limit and the error handlers."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

from fastapi import FastAPI
from fastapi.middleware.gzip import GZipMiddleware
from starlette.concurrency import run_in_threadpool

from api.checks.service import CheckService, Service
from api.http.bodylimit import BodyLimitMiddleware
from api.http.handlers import install_handlers
from api.http.openapi import install_openapi
from api.http.security import SecurityHeaders, install_docs
from api.results.compressed import CompressedReports
from api.routers import checks, health, rules, web
from api.settings import Settings
from api.store import Store
from geomcheck import __version__

GZIP_LEVEL = 5  # of responses compressed as they are sent [zlib level]
DESCRIPTION = """Collision and geometry verification for robot descriptions (URDF and xacro, MJCF, SDFormat).

POST a description to `/v1/checks` (a URDF or xacro document, a multipart form of package
files, or an archive of the package tree) and get the `geomcheck.report/1` report back, as
JSON or as an HTML page to download. Uploads are untrusted: size, count and ratio limits,
no paths outside the upload, xacro confined to the upload, each check in its own process
with CPU, memory and time limits."""


def create_app(settings: Settings | None = None) -> FastAPI:
    """The service for ``settings`` (read from the environment when omitted).

    The database schema is created and interrupted checks are recorded on start-up; running
    checks are stopped and the database released on shutdown.
    """
    settings = settings or Settings()
    store = Store(settings.database, settings.table_prefix)
    service: Service
    if settings.distributed:  # an API replica: geomcheck worker processes run the checks
        from api.distributed.dispatch import QueuedCheckService

        service = QueuedCheckService(settings, store)
    else:
        service = CheckService(settings, store)

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        await run_in_threadpool(service.start)
        try:
            yield
        finally:
            await run_in_threadpool(service.stop)

    app = FastAPI(
        title="geomcheck",
        version=__version__,
        description=DESCRIPTION,
        lifespan=lifespan,
        license_info={"name": "BSD-3-Clause"},
        docs_url=None,  # served by api.http.security from this service, not a CDN
        redoc_url=None,
    )
    app.state.settings = settings
    app.state.service = service
    app.state.compressed_reports = CompressedReports()
    # reports are large and compress about tenfold; level 5 costs a sixth of level 9's time for 20% more bytes
    app.add_middleware(GZipMiddleware, minimum_size=4096, compresslevel=GZIP_LEVEL)
    app.add_middleware(BodyLimitMiddleware, max_bytes=settings.max_body_bytes, timeout_s=settings.body_timeout_s)
    app.add_middleware(SecurityHeaders)  # outermost: refuses cross-origin POSTs before the body is read
    install_handlers(app)
    install_openapi(app)
    install_docs(app)
    app.include_router(health.router)
    app.include_router(rules.router)
    app.include_router(checks.router)
    app.include_router(web.router)
    app.include_router(web.pages)  # the page at / and /checks/{id}
    return app
