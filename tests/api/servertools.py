"""A real ``geomcheck serve`` for the tests that need one: uvicorn on a loopback port, in its own process."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

import httpx


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


@contextmanager
def serving(data_dir: Path, port: int | None = None, start_timeout_s: float = 90, **settings: str) -> Iterator[str]:
    """``geomcheck serve`` on ``port`` (a free one by default) until the block ends, stopped by
    its pid (SIGTERM, then SIGKILL after a bounded wait); yields its base URL once it answers
    ``/healthz``. ``settings`` are ``GEOMCHECK_<NAME>`` variables (``api_tokens="t"``)."""
    port = port or free_port()
    env = {
        **os.environ,
        "GEOMCHECK_DATA_DIR": str(data_dir),
        **{f"GEOMCHECK_{k.upper()}": v for k, v in settings.items()},
    }
    command = [sys.executable, "-m", "geomcheck", "serve", "--host", "127.0.0.1", "--port", str(port)]
    with tempfile.TemporaryFile() as log:  # a file, not a pipe: a server writing much never blocks on it
        server = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=log)
        base = f"http://127.0.0.1:{port}"
        try:
            _wait_healthy(server, base, start_timeout_s, log)
            yield base
        finally:
            server.send_signal(signal.SIGTERM)
            try:
                server.wait(timeout=30)
            except subprocess.TimeoutExpired:
                server.kill()
                server.wait(timeout=10)


def _wait_healthy(server: subprocess.Popen[bytes], base: str, timeout_s: float, log: IO[bytes]) -> None:
    deadline = time.monotonic() + timeout_s
    while True:
        if server.poll() is not None:
            log.seek(0)
            raise AssertionError(f"geomcheck serve exited: {log.read().decode(errors='replace')[-2000:]}")
        try:
            if httpx.get(f"{base}/healthz", timeout=2).status_code == 200:
                return
        except httpx.HTTPError:
            pass
        assert time.monotonic() < deadline, f"the server did not answer /healthz within {timeout_s:g} s"
        time.sleep(0.1)
