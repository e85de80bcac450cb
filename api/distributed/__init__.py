"""The distributed mode on Celery: API replicas enqueue checks, ``geomcheck worker`` processes run them.

:mod:`api.distributed.celery_app` configures Celery (acks late, one message per free slot),
:mod:`api.distributed.dispatch` is the API replicas' side, :mod:`api.distributed.worker`
the workers' (tasks, leases, recovery of abandoned checks, retention under Celery beat).
PostgreSQL holds the checks, their reports and the uploads; the broker (Redis or RabbitMQ)
holds only check ids.
"""

__all__ = ["celery_app", "deadletters", "dispatch", "health", "transport", "worker"]
