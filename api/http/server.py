"""``geomcheck serve``: run the service under uvicorn (one process; checks run in their own processes,
or, with ``GEOMCHECK_BROKER_URL`` set, in ``geomcheck worker`` processes anywhere)."""

from __future__ import annotations

import asyncio
import logging
import time
from types import FrameType

import uvicorn
from fastapi import FastAPI
from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

from api.checks.service import lock_data_dir
from api.distributed.celery_app import check_distributed
from api.http.app import create_app
from api.settings import Settings
from api.store import Store

log = logging.getLogger("geomcheck.api")


def serve(host: str = "127.0.0.1", port: int = 8000, database: str | None = None) -> None:
    """Serve on ``host:port``; ``database`` overrides ``GEOMCHECK_DATABASE_URL``.

    The data folder lock (embedded mode only) and the database (schema created) are tried
    before the server starts, so a busy folder or a wrong URL is a one-line error, not a
    traceback. An API replica of the distributed mode holds no lock: any number share a database.
    """
    settings = Settings()
    if database:
        settings = settings.model_copy(update={"database_url": database})
    if settings.distributed:
        check_distributed(settings)
    else:
        lock_data_dir(settings.data_dir).close()
    probe = Store(settings.database, settings.table_prefix)
    try:
        probe.create_schema()
    finally:
        probe.dispose()
    logging.basicConfig(level=logging.INFO, format="%(levelname)s:     %(name)s: %(message)s")
    # a POST waiting for its check keeps its connection open: on SIGTERM it is answered 503 within
    # shutdown_timeout_s (api.routers.checks), then the lifespan ends the checks and records them failed
    app = create_app(settings)
    config = uvicorn.Config(
        app,
        host=host,
        port=port,
        log_level="info",
        proxy_headers=True,
        timeout_keep_alive=30,
        timeout_graceful_shutdown=max(1, round(settings.shutdown_timeout_s)),
        http=header_timeout_protocol(settings.header_timeout_s),
    )
    DrainingServer(config, app).run()


def header_timeout_protocol(timeout_s: float) -> type[HttpToolsProtocol]:
    """uvicorn's HTTP protocol closing a connection whose request headers have not all
    arrived ``timeout_s`` after it opened or after the request's first byte: uvicorn has no
    such limit, so a client sending a header byte now and then (slowloris) held a connection
    for ever. The body has its own limit (``body_timeout_s``, :mod:`api.http.bodylimit`)."""

    class HeaderTimeout(HttpToolsProtocol):
        header_timer: asyncio.TimerHandle | None = None

        def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
            super().connection_made(transport)
            self.arm_header_timer()

        def on_message_begin(self) -> None:
            super().on_message_begin()
            self.arm_header_timer()  # each request of a kept-alive connection

        def on_headers_complete(self) -> None:
            self.cancel_header_timer()
            super().on_headers_complete()

        def connection_lost(self, exc: Exception | None) -> None:
            self.cancel_header_timer()
            super().connection_lost(exc)

        def arm_header_timer(self) -> None:
            self.cancel_header_timer()
            self.header_timer = self.loop.call_later(timeout_s, self.headers_too_slow)

        def cancel_header_timer(self) -> None:
            if self.header_timer is not None:
                self.header_timer.cancel()
                self.header_timer = None

        def headers_too_slow(self) -> None:
            self.header_timer = None
            if not self.transport.is_closing():
                log.info("closed a connection whose request headers took more than %g s", timeout_s)
                self.transport.close()

    return HeaderTimeout


class DrainingServer(uvicorn.Server):
    """uvicorn's server telling the app when SIGTERM (or SIGINT) arrived, so requests still
    waiting can answer 503 themselves before uvicorn cancels them (it would answer a plain-text 500)."""

    def __init__(self, config: uvicorn.Config, app: FastAPI) -> None:
        super().__init__(config)
        self.app = app

    def handle_exit(self, sig: int, frame: FrameType | None) -> None:
        begin_draining(self.app)
        super().handle_exit(sig, frame)


def begin_draining(app: FastAPI) -> None:
    """Mark ``app`` as shutting down (the first call counts)."""
    if getattr(app.state, "draining_since", None) is None:
        app.state.draining_since = time.monotonic()
