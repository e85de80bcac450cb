"""The worker's health check: does a geomcheck worker on this host answer the broker?

A container orchestrator (Docker's HEALTHCHECK, compose's ``healthcheck``) runs
``geomcheck worker --ping``: it asks every worker through the broker (Celery's
``active_queues`` broadcast) and succeeds when one whose name ends in ``@<this host>`` answers
consuming this deployment's queue, which proves the worker process runs and still consumes
from the broker.
"""

from __future__ import annotations

import socket

from api.distributed.celery_app import make_celery
from api.settings import Settings

PING_TIMEOUT_S = 3.0  # how long replies are awaited [s]


def local_worker_answers(settings: Settings, host: str | None = None, timeout_s: float = PING_TIMEOUT_S) -> bool:
    """Whether a worker named ``...@host`` (default: this machine's name) answers through the
    broker and consumes ``settings.queue``: a worker of another deployment on the same host and
    broker (another queue) proves nothing of this one."""
    host = host or socket.gethostname()
    app = make_celery(settings)
    try:
        replies = app.control.inspect(timeout=timeout_s).active_queues() or {}
    finally:
        app.close()
    return any(
        name.endswith(f"@{host}") and any(queue.get("name") == settings.queue for queue in queues or ())
        for name, queues in replies.items()
    )
