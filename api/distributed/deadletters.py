"""Messages no worker can run go to a dead-letter queue: logged, counted, never requeued.

Anyone who can write to the broker (a misconfigured client, another application sharing it)
can put anything on the checks' queue. A message Celery cannot take apart raised out of the
worker's event loop: ``{"body": "%%%", "headers": {"task": ...}}`` on Redis made Celery's task
strategy fail with a ``TypeError``, the worker stopped ("Unrecoverable error"), its unacknowledged
message was restored to the queue, and it stopped the next worker too, workers started later
included. Here every message the worker's consumer fails on, whatever the exception, is
logged on one line, put on the dead-letter queue ``<queue>.dead`` (the newest
:data:`MAX_DEAD_LETTERS` are kept there for whoever investigates) and taken off the checks'
queue for good; ``/metrics`` shows how many the dead-letter queue holds
(``geomcheck_dead_letters``). Messages Celery itself refuses (an unknown task, a content type
it does not accept) are rejected by Celery without requeueing, as before. Malformed envelopes
on Redis are caught before delivery (:mod:`api.distributed.transport`) and dead-lettered there.
"""

from __future__ import annotations

import json
import logging
from typing import Any

from celery.worker.consumer import Consumer
from kombu import Connection, Exchange, Queue

from api.settings import Settings

log = logging.getLogger("geomcheck.worker")

MAX_DEAD_LETTERS = 1000  # messages the dead-letter queue keeps, the oldest dropped first [count]
SHOWN_BYTES = 80  # of a dead message, in the log line [bytes]
DEAD_LETTER_TIMEOUT_S = 5.0  # connecting to the broker to count the dead letters [s]
CONTENT_ERRORS = (LookupError, TypeError, ValueError, UnicodeError)  # what a message's content raises


def dead_letter_queue(queue: str) -> str:
    """The name of the dead-letter queue of the checks' ``queue``."""
    return f"{queue}.dead"


def dead_letter_declaration(queue: str) -> Queue:
    """The dead-letter queue, durable and bounded (RabbitMQ drops its oldest beyond the bound)."""
    name = dead_letter_queue(queue)
    arguments = {"x-max-length": MAX_DEAD_LETTERS, "x-overflow": "drop-head"}
    return Queue(name, Exchange(""), routing_key=name, durable=True, queue_arguments=arguments)


def shown(data: Any) -> str:
    """The start of a message's bytes for a log line."""
    text = data if isinstance(data, str) else bytes(data or b"").decode("utf-8", "replace")
    return repr(text[:SHOWN_BYTES]) + ("..." if len(text) > SHOWN_BYTES else "")


def trim_redis_list(client: Any, name: str) -> None:
    """Keep the newest :data:`MAX_DEAD_LETTERS` of a Redis dead-letter list (pushed at the left)."""
    client.ltrim(name, 0, MAX_DEAD_LETTERS - 1)


def _text(value: Any) -> str:
    try:
        return json.dumps(value, default=repr)[:2000]
    except (TypeError, ValueError, RecursionError):
        return repr(value)[:2000]


class GuardedConsumer(Consumer):  # type: ignore[misc]
    """Celery's consumer, with every message its task handler fails on dead-lettered instead of
    raising out of the event loop (a lost connection still raises: Celery reconnects)."""

    def create_task_handler(self, *args: Any, **kwargs: Any) -> Any:
        handle = super().create_task_handler(*args, **kwargs)
        connection_errors = tuple(self.connection_errors or ())

        def guarded(message: Any) -> Any:
            try:
                return handle(message)
            except Exception as err:  # any message, any failure: never the worker's end
                # kombu counts KeyError among Redis's connection errors: raised while taking a
                # message apart, it is the message's, and re-raising it would restore the message
                if isinstance(err, connection_errors) and not isinstance(err, CONTENT_ERRORS):
                    raise
                self.dead_letter(message, err)
                return None

        return guarded

    def dead_letter(self, message: Any, err: Exception | None, settle: bool = True, reason: str = "") -> None:
        """Log ``message``, put a copy on the dead-letter queue and (``settle``) take it off the
        checks' queue for good (Celery's own refusals settle it themselves)."""
        queue = self.app.conf.task_default_queue
        body = getattr(message, "body", b"")
        why = reason or f"{type(err).__name__}: {err}"
        if err is not None:
            log.error("rejected a malformed message on queue %s (%s): %s", queue, why, shown(body))
        publish_dead_letter(
            self.app, queue, body, why, getattr(message, "headers", None), getattr(message, "properties", None)
        )
        if not settle:
            return
        try:
            if not message.acknowledged:
                message.reject(requeue=False)
        except Exception as failure:  # a tag the broker does not know: nothing to take back
            log.error("the malformed message could not be rejected (%s)", failure)

    # Celery's own refusals (logged, and rejected or acknowledged by Celery) are dead-lettered too

    def on_unknown_message(self, body: Any, message: Any) -> None:
        self.dead_letter(message, None, settle=False, reason="not a task message")
        super().on_unknown_message(body, message)

    def on_unknown_task(self, body: Any, message: Any, exc: Exception) -> None:
        self.dead_letter(message, None, settle=False, reason=f"unknown task: {exc}")
        super().on_unknown_task(body, message, exc)

    def on_invalid_task(self, body: Any, message: Any, exc: Exception) -> None:
        self.dead_letter(message, None, settle=False, reason=f"invalid task message: {exc}")
        super().on_invalid_task(body, message, exc)

    def on_decode_error(self, message: Any, exc: Exception) -> None:
        self.dead_letter(message, None, settle=False, reason=f"undecodable body: {exc}")
        super().on_decode_error(message, exc)


def publish_dead_letter(
    app: Any, queue: str, body: Any, reason: str, headers: Any = None, properties: Any = None
) -> None:
    """Put ``body`` (bytes as they came) on the dead-letter queue of ``queue`` with why it is
    there and the message's headers and properties; a failure is logged (the message is
    dropped all the same)."""
    data = (
        body if isinstance(body, bytes) else (body if isinstance(body, str) else _text(body)).encode("utf-8", "replace")
    )
    try:
        with app.producer_or_acquire() as producer:
            producer.publish(
                data,
                routing_key=dead_letter_queue(queue),
                exchange="",
                declare=[dead_letter_declaration(queue)],
                serializer=None,
                content_type="application/octet-stream",
                content_encoding="binary",
                headers={
                    "x-geomcheck-reason": reason[:500],
                    "x-original-headers": _text(headers),
                    "x-original-properties": _text(properties),
                },
                retry=False,
            )
            client = getattr(producer.channel, "client", None)
            if client is not None and hasattr(client, "ltrim"):  # Redis: the list is bounded here
                trim_redis_list(client, dead_letter_queue(queue))
    except Exception as failure:  # the message is dropped all the same
        log.error("the malformed message could not be dead-lettered (%s): dropped", failure)


def dead_letter_count(settings: Settings) -> int | None:
    """How many messages the dead-letter queue holds; ``None`` when the broker does not answer."""
    name = dead_letter_queue(settings.queue)
    try:
        with Connection(settings.broker_url, connect_timeout=DEAD_LETTER_TIMEOUT_S) as conn:
            conn.ensure_connection(max_retries=1, timeout=DEAD_LETTER_TIMEOUT_S)
            channel = conn.default_channel
            client = getattr(channel, "client", None)
            if client is not None and hasattr(client, "llen"):
                return int(client.llen(name))
            try:
                declared = dead_letter_declaration(settings.queue)(channel).queue_declare(passive=True)
            except conn.channel_errors:  # not declared yet: no message was ever dead-lettered
                return 0
            return int(declared.message_count)
    except Exception:  # the metric is left out, the scrape still answers
        return None
