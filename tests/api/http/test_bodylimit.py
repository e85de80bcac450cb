"""The body-limit middleware: size caps and the body timeout, on a bare ASGI app."""

from __future__ import annotations

import asyncio
import time

import pytest
from starlette.types import Message, Receive, Scope, Send

from api.errors import UploadTimeout, UploadTooLarge
from api.http.bodylimit import BodyLimitMiddleware

SCOPE: Scope = {"type": "http", "method": "POST", "path": "/", "headers": []}


async def read_all(scope: Scope, receive: Receive, send: Send) -> None:
    """An app that reads the whole body, then answers 200 with its length."""
    size, more = 0, True
    while more:
        message = await receive()
        size += len(message.get("body", b""))
        more = message.get("more_body", False)
    await send({"type": "http.response.start", "status": 200, "headers": []})
    await send({"type": "http.response.body", "body": str(size).encode()})


def trickle(chunks: list[bytes], pause_s: float) -> Receive:
    """A client sending ``chunks`` with ``pause_s`` before each, then waiting for ever."""
    queue = list(chunks)

    async def receive() -> Message:
        if not queue:
            await asyncio.sleep(3600)
        await asyncio.sleep(pause_s)
        body = queue.pop(0)
        return {"type": "http.request", "body": body, "more_body": bool(queue)}

    return receive


def run(app: BodyLimitMiddleware, receive: Receive) -> list[Message]:
    sent: list[Message] = []

    async def send(message: Message) -> None:
        sent.append(message)

    asyncio.run(app(SCOPE, receive, send))
    return sent


def test_a_body_that_arrives_in_time_passes() -> None:
    app = BodyLimitMiddleware(read_all, max_bytes=100, timeout_s=5.0)
    sent = run(app, trickle([b"a" * 10, b"b" * 20], 0.01))
    assert sent[0]["status"] == 200 and sent[1]["body"] == b"30"


def test_a_trickled_body_fails_at_the_deadline() -> None:
    app = BodyLimitMiddleware(read_all, max_bytes=1000, timeout_s=0.3)
    started = time.monotonic()
    with pytest.raises(UploadTimeout, match=r"did not arrive within 0.3 s \(2 bytes received\)") as caught:
        run(app, trickle([b"a", b"b", b"c", b"d", b"e", b"f", b"g", b"h"], 0.1))
    assert 0.25 < time.monotonic() - started < 2.0
    assert caught.value.http_status == 408


def test_a_stalled_body_fails_at_the_deadline() -> None:
    app = BodyLimitMiddleware(read_all, max_bytes=1000, timeout_s=0.2)
    with pytest.raises(UploadTimeout, match=r"\(5 bytes received\)"):
        run(app, stalled_after(b"12345"))


def stalled_after(first: bytes) -> Receive:
    sent = False

    async def receive() -> Message:
        nonlocal sent
        if sent:
            await asyncio.sleep(3600)
        sent = True
        return {"type": "http.request", "body": first, "more_body": True}

    return receive


def test_a_streamed_body_over_the_cap_fails_as_it_crosses() -> None:
    app = BodyLimitMiddleware(read_all, max_bytes=15, timeout_s=5.0)
    with pytest.raises(UploadTooLarge, match="exceeds the limit of 15 bytes"):
        run(app, trickle([b"a" * 10, b"b" * 10], 0.0))
