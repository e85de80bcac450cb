"""ASGI middleware capping request bodies, by ``Content-Length``, while streaming, and in time.

A declared length over the cap is refused before the body is read; a body that turns out
longer (chunked transfer, a lying header) fails the read with :class:`UploadTooLarge`
the moment the cap is crossed, so no more than ``max_bytes`` are ever buffered. A body
must arrive whole within ``timeout_s`` of the first read: a client that trickles it (a
slow-upload attack holding the server's connections) fails with :class:`UploadTimeout`
(408) instead of waiting for ever.
"""

from __future__ import annotations

import asyncio
import time

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from api.errors import UploadTimeout, UploadTooLarge
from api.http.handlers import error_response


class BodyLimitMiddleware:
    def __init__(self, app: ASGIApp, max_bytes: int, timeout_s: float = 120.0) -> None:
        self.app = app
        self.max_bytes = max_bytes
        self.timeout_s = timeout_s

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        declared = dict(scope.get("headers") or ()).get(b"content-length")
        if declared is not None:
            try:
                length = int(declared)
            except ValueError:
                await error_response(400, "invalid Content-Length header")(scope, receive, send)
                return
            if length > self.max_bytes:
                response = error_response(
                    413, f"request body of {length} bytes exceeds the limit of {self.max_bytes} bytes"
                )
                await response(scope, receive, send)
                return
        received = 0
        deadline: float | None = None
        complete = False

        async def limited_receive() -> Message:
            nonlocal received, deadline, complete
            if complete:  # later reads wait for the client to go away: no deadline on them
                return await receive()
            if deadline is None:
                deadline = time.monotonic() + self.timeout_s
            try:  # a timeout scope, not wait_for: no task is made for every chunk of the body
                async with asyncio.timeout(max(0.0, deadline - time.monotonic())):
                    message = await receive()
            except TimeoutError:
                raise UploadTimeout(
                    f"the request body did not arrive within {self.timeout_s:g} s ({received} bytes received)"
                ) from None
            complete = message["type"] != "http.request" or not message.get("more_body", False)
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > self.max_bytes:
                    raise UploadTooLarge(f"request body exceeds the limit of {self.max_bytes} bytes")
            return message

        await self.app(scope, limited_receive, send)
