"""``geomcheck serve`` and ``geomcheck worker``: the HTTP service (``api/``), embedded or distributed."""

from __future__ import annotations

import argparse

from geomcheck.errors import UsageError


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
