"""The Redis transport of the worker, refusing malformed messages instead of dying on them.

kombu's Redis channel parses each message it pops as a JSON envelope inside the worker's
event loop: a message that is not JSON, or JSON that is not an envelope (no ``properties``,
no ``delivery_tag``, a body that is not base64), raises out of the loop and Celery stops
the worker ("Unrecoverable error: JSONDecodeError"). Anyone who can write to the queue (a
misconfigured client, another application sharing the Redis database) could stop every
worker with one ``LPUSH``. Here a popped message is checked before it is delivered; a bad
one is logged and dropped (it was already removed from the list by ``BRPOP``/``RPOP``), and
the worker goes on. Messages whose envelope is sound but whose body Celery cannot decode
are Celery's to reject (it logs and acknowledges them).
"""

from __future__ import annotations

import logging
from typing import Any

from kombu.exceptions import ContentDisallowed, DecodeError
from kombu.transport import redis
from kombu.utils.encoding import bytes_to_str
from kombu.utils.json import loads

log = logging.getLogger("geomcheck.worker")

MALFORMED = (ValueError, TypeError, KeyError, AttributeError, UnicodeError, DecodeError, ContentDisallowed)
SHOWN_BYTES = 80  # of a rejected message, in the log line [bytes]


def _shown(item: Any) -> str:
    text = item if isinstance(item, str) else bytes(item).decode("utf-8", "replace")
    return repr(text[:SHOWN_BYTES]) + ("..." if len(text) > SHOWN_BYTES else "")


class Channel(redis.Channel):
    """A Redis channel that checks every popped message's envelope before delivering it."""

    def _envelope(self, item: Any, queue: str) -> dict[str, Any] | None:
        """The parsed envelope of ``item``, or None (logged) when it is malformed."""
        try:
            payload = loads(bytes_to_str(item))
            if not isinstance(payload, dict) or not isinstance(payload.get("properties"), dict):
                raise ValueError("not a kombu message envelope")
            info = payload["properties"].get("delivery_info")
            if not isinstance(info, dict):
                raise ValueError("no delivery_info")
            self.Message(payload, channel=self)  # what delivering it builds: raises as it would
        except MALFORMED as err:
            log.error(
                "rejected a malformed message on queue %s (%s: %s): %s", queue, type(err).__name__, err, _shown(item)
            )
            return None
        return payload

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
