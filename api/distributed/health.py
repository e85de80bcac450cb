"""The worker's health check: does a geomcheck worker on this host answer the broker?

A container orchestrator (Docker's HEALTHCHECK, compose's ``healthcheck``) runs
``geomcheck worker --ping``: it asks this deployment's workers on this host through the broker
(Celery's ``active_queues`` broadcast on the deployment's own control exchange, to the names
ending in ``@<this host>``) and succeeds when one answers consuming this deployment's queue,
which proves the worker process runs and still consumes from the broker. It returns at the
first answer; only an unhealthy host waits the whole timeout.
"""

from __future__ import annotations

import re
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
    # the first answer of a worker on this host settles it (limit=1): no wait for the others
    pattern = f".*@{re.escape(host)}$"
    try:
        inspect = app.control.inspect(timeout=timeout_s, limit=1, pattern=pattern, matcher="pcre")
        replies = inspect.active_queues() or {}
    finally:
        app.close()
    return any(
        name.endswith(f"@{host}") and any(queue.get("name") == settings.queue for queue in queues or ())
        for name, queues in replies.items()
    )
