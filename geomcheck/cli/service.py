"""``geomcheck serve`` and ``geomcheck worker``: the HTTP service (``api/``), embedded or distributed."""

from __future__ import annotations

import argparse
import os

from geomcheck.errors import UsageError


def add_service_parsers(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """``serve`` (the HTTP service) and ``worker`` (a worker of its distributed mode)."""
    serve = sub.add_parser("serve", help="run the HTTP service (settings: GEOMCHECK_* environment variables)")
    serve.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    serve.add_argument("--port", type=int, default=8000, help="port to listen on (default 8000)")
    serve.add_argument("--database", metavar="URL", help="database URL (default: SQLite in GEOMCHECK_DATA_DIR)")
    serve.set_defaults(func=cmd_serve)

    worker = sub.add_parser(
        "worker",
        help="run checks for the HTTP service's distributed mode (GEOMCHECK_BROKER_URL, GEOMCHECK_DATABASE_URL)",
    )
    worker.add_argument("--concurrency", type=int, default=os.cpu_count() or 1, help="checks at once (default: cores)")
    worker.add_argument("--beat", action="store_true", help="also schedule the periodic retention (one per deployment)")
    worker.add_argument(
        "--ping",
        action="store_true",
        help="exit 0 when a worker on this host answers through the broker, else 1 (a container health check)",
    )
    worker.set_defaults(func=cmd_worker)


def cmd_serve(ns: argparse.Namespace) -> int:
    from api.http.server import serve  # the one sanctioned import of the service: the library never needs it

    serve(ns.host, ns.port, ns.database)
    return 0


def cmd_worker(ns: argparse.Namespace) -> int:
    if ns.ping:
        from api.distributed.health import local_worker_answers
        from api.settings import Settings

        return 0 if local_worker_answers(Settings()) else 1
    from api.distributed.worker import run_worker  # the service's Celery worker (distributed mode)

    if ns.concurrency < 1:
        raise UsageError(f"--concurrency must be at least 1, got {ns.concurrency}")
    run_worker(ns.concurrency, beat=ns.beat)
    return 0
