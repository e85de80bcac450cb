"""The Celery application of the distributed mode, built from :class:`api.settings.Settings`.

Delivery is at least once: a message is acknowledged after the check's result is stored
(``acks_late``), is given back when its worker process is lost (``reject_on_worker_lost``),
and each worker holds one message per free slot (``prefetch_multiplier=1``) so the queue,
not a worker's buffer, holds the waiting checks. The effect is exactly once: a task only
acts on a check it claims in the database (see :meth:`api.store.Store.claim`).
"""

from __future__ import annotations

from typing import Any

from celery import Celery
from kombu import Connection

from api.settings import Settings
from geomcheck.errors import UsageError

RUN_CHECK = "geomcheck.run_check"
RETENTION = "geomcheck.retention"
BROKER_SCHEMES = ("redis://", "rediss://", "amqp://", "amqps://", "pyamqp://")
BROKER_TIMEOUT_S = 5.0  # connecting to the broker, publishing a message [s]


def check_distributed(settings: Settings) -> None:
    """:class:`UsageError` unless the broker URL is supported and the database is shared (not SQLite)."""
    url = settings.broker_url or ""
    if not url.startswith(BROKER_SCHEMES):
        shown = url.split("@")[-1]
        raise UsageError.bad_choice("GEOMCHECK_BROKER_URL scheme in", shown, BROKER_SCHEMES)
    if not settings.database_url or settings.database.startswith("sqlite"):
        raise UsageError(
            "the distributed mode (GEOMCHECK_BROKER_URL set) needs a database every node reaches: "
            "set GEOMCHECK_DATABASE_URL=postgresql://..."
        )


def make_celery(settings: Settings) -> Celery:
    """A Celery app for ``settings.broker_url`` publishing to and consuming ``settings.queue``."""
    check_distributed(settings)
    app = Celery("geomcheck", broker=settings.broker_url, set_as_current=False)
    transport: dict[str, Any] = {}
    if settings.broker_url and settings.broker_url.startswith(("redis://", "rediss://")):
        # an unacknowledged message (its worker vanished) is delivered again after this;
        # the lease notices a vanished worker sooner (api.distributed.worker.Recovery)
        transport["visibility_timeout"] = settings.visibility_timeout_s
        # a malformed message is logged and dropped instead of stopping the worker
        app.conf.broker_transport = "api.distributed.transport:Transport"
    app.conf.update(
        task_acks_late=True,
        task_reject_on_worker_lost=True,
        task_acks_on_failure_or_timeout=True,
        worker_prefetch_multiplier=1,
        task_default_queue=settings.queue,
        # broadcasts (the health check's, remote control) reach this deployment's workers only:
        # another deployment on the same broker has its own control exchange
        control_exchange=f"{settings.queue}.control",
        task_create_missing_queues=True,
        task_ignore_result=True,
        result_backend=None,
        task_serializer="json",
        accept_content=["json"],
        broker_transport_options=transport,
        broker_connection_timeout=BROKER_TIMEOUT_S,
        broker_connection_retry_on_startup=True,
        broker_heartbeat=30,
        task_publish_retry=True,
        task_publish_retry_policy={"max_retries": 3, "interval_start": 0.2, "interval_step": 0.5, "interval_max": 2},
        # a message the consumer fails on is dead-lettered, never raised out of the event loop
        worker_consumer="api.distributed.deadletters:GuardedConsumer",
        worker_hijack_root_logger=False,
        worker_send_task_events=False,
        worker_cancel_long_running_tasks_on_connection_loss=False,
        beat_schedule={
            "delete-old-checks": {"task": RETENTION, "schedule": settings.retention_interval_s},
        },
        timezone="UTC",
    )
    return app


def publish(app: Celery, settings: Settings, check_id: str) -> None:
    """Put ``check_id`` on the queue (persistent message; raises when the broker does not take it)."""
    app.send_task(RUN_CHECK, args=[check_id], queue=settings.queue)


def broker_reachable(settings: Settings) -> bool:
    """True when the broker accepts a connection within :data:`BROKER_TIMEOUT_S`."""
    try:
        with Connection(settings.broker_url, connect_timeout=BROKER_TIMEOUT_S) as conn:
            conn.ensure_connection(max_retries=1, timeout=BROKER_TIMEOUT_S)
        return True
    except Exception:
        return False
