"""The Redis transport of the worker, refusing malformed messages instead of dying on them.

kombu's Redis channel parses each message it pops as a JSON envelope inside the worker's
event loop: a message that is not JSON, or JSON that is not an envelope (no ``properties``,
no ``delivery_tag``, a body that is not base64, fields of the wrong types), raises out of the
loop and Celery stops the worker ("Unrecoverable error: JSONDecodeError"). Anyone who can write
to the queue (a misconfigured client, another application sharing the Redis database) could
stop every worker with one ``LPUSH``. Here a popped message is checked before it is delivered;
a bad one is logged and put on the dead-letter list (it was already removed from the queue by
``BRPOP``/``RPOP``), and the worker goes on. A sound envelope whose content Celery fails on is
dead-lettered by the consumer (:mod:`api.distributed.deadletters`).
"""

from __future__ import annotations

import logging
from typing import Any

from kombu.exceptions import ContentDisallowed, DecodeError
from kombu.transport import redis
from kombu.utils.encoding import bytes_to_str
from kombu.utils.json import loads

from api.distributed.deadletters import dead_letter_queue, shown, trim_redis_list

log = logging.getLogger("geomcheck.worker")

MALFORMED = (ValueError, TypeError, KeyError, AttributeError, UnicodeError, DecodeError, ContentDisallowed)
# the envelope's fields kombu and Celery read, with the type each must have when present
ENVELOPE_TYPES: dict[str, type | tuple[type, ...]] = {
    "body": str,
    "headers": dict,
    "content-type": str,
    "content-encoding": str,
}


class Channel(redis.Channel):
    """A Redis channel that checks every popped message's envelope before delivering it."""

    def _envelope(self, item: Any, queue: str) -> dict[str, Any] | None:
        """The parsed envelope of ``item``, or None (logged) when it is malformed."""
        try:
            payload = loads(bytes_to_str(item))
            if not isinstance(payload, dict) or not isinstance(payload.get("properties"), dict):
                raise ValueError("not a kombu message envelope")
            properties = payload["properties"]
            info = properties.get("delivery_info")
            if not isinstance(info, dict):
                raise ValueError("no delivery_info")
            if not all(isinstance(info.get(key), str) for key in ("exchange", "routing_key")):
                raise TypeError("the delivery_info's exchange or routing_key is not a string")
            if not isinstance(properties.get("delivery_tag"), str):
                raise TypeError("the delivery_tag is not a string")
            for key, kind in ENVELOPE_TYPES.items():
                if payload.get(key) is not None and not isinstance(payload[key], kind):
                    raise TypeError(f"{key} is a {type(payload[key]).__name__}")
            if properties.get("body_encoding") not in (None, "base64"):
                raise ValueError(f"unknown body_encoding {properties.get('body_encoding')!r}")
            self.Message(payload, channel=self)  # what delivering it builds: raises as it would
        except MALFORMED as err:
            log.error(
                "rejected a malformed message on queue %s (%s: %s): %s", queue, type(err).__name__, err, shown(item)
            )
            self._dead_letter(item, queue)
            return None
        return payload

    def _dead_letter(self, item: Any, queue: str) -> None:
        """Put the raw ``item`` on the dead-letter list of ``queue`` (the newest kept)."""
        name = dead_letter_queue(queue)
        try:
            with self.conn_or_acquire() as client:
                client.lpush(name, item)
                trim_redis_list(client, name)
        except Exception as err:  # the message is dropped all the same
            log.error("the malformed message could not be dead-lettered (%s): dropped", err)

    def _brpop_read(self, **options: Any) -> bool:
        try:
            try:
                dest__item = self.client.parse_response(self.client.connection, "BRPOP", **options)
            except self.connection_errors:
                # disconnect so the next iteration reconnects (as kombu does)
                self.client.connection.disconnect()
                raise
            if not dest__item:
                raise redis.Empty()
            dest, item = dest__item
            dest = bytes_to_str(dest).rsplit(self.sep, 1)[0]
            self._queue_cycle.rotate(dest)
            payload = self._envelope(item, dest)
            if payload is not None:
                self.connection._deliver(payload, dest)
            return True
        finally:
            self._in_poll = None  # type: ignore[assignment]
            flush = getattr(self, "_flush_brpop_reauth", None)  # kombu >= 5.7
            if flush is not None:
                flush()

    def _get(self, queue: Any, timeout: Any = None) -> Any:
        with self.conn_or_acquire() as client:
            for pri in self.priority_steps:
                item = client.rpop(self._q_for_pri(queue, pri))
                if item:
                    self._maybe_update_queues_expire(client, queue)
                    payload = self._envelope(item, queue)
                    if payload is not None:
                        return payload
            self._maybe_update_queues_expire(client, queue)
            raise redis.Empty()


class Transport(redis.Transport):
    Channel = Channel
