"""`geomcheck serve` as the docs run it: a real uvicorn on loopback, restarted over the same data folder."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx
import pytest
from apitools import TWO_LINKS

from geomcheck.cli import build_parser, main


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


@contextmanager
def serving(data_dir: Path, port: int) -> Iterator[str]:
    """``geomcheck serve`` on ``port`` until the block ends (stopped by its pid, SIGTERM)."""
    env = {**os.environ, "GEOMCHECK_DATA_DIR": str(data_dir)}
    command = [sys.executable, "-m", "geomcheck", "serve", "--host", "127.0.0.1", "--port", str(port)]
    server = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 60
        while True:
            assert server.poll() is None, server.stderr.read().decode() if server.stderr else ""
            try:
                if httpx.get(f"{base}/healthz", timeout=1).status_code == 200:
                    break
            except httpx.HTTPError:
                pass
            assert time.monotonic() < deadline, "the server did not answer /healthz within 60 s"
            time.sleep(0.1)
        yield base
    finally:
        server.send_signal(signal.SIGTERM)
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait(timeout=10)


def test_serve_answers_and_ids_survive_a_restart(tmp_path: Path) -> None:
    port = free_port()
    with serving(tmp_path / "data", port) as base:
        created = httpx.post(
            f"{base}/v1/checks",
            params={"root": "two_links.urdf"},
            content=TWO_LINKS,
            headers={"content-type": "application/xml"},
            timeout=120,
        )
        assert created.status_code == 201, created.text
        check_id = created.json()["id"]
        report = httpx.get(f"{base}/v1/checks/{check_id}/report.json").text
    with serving(tmp_path / "data", port) as base:
        again = httpx.get(f"{base}/v1/checks/{check_id}")
        assert again.status_code == 200 and again.json()["report"]["robot"]["name"] == "two_links"
        assert httpx.get(f"{base}/v1/checks/{check_id}/report.json").text == report
        assert httpx.get(f"{base}/v1/checks/{check_id}/report.html").status_code == 200


def test_serve_options() -> None:
    ns = build_parser().parse_args(["serve", "--host", "0.0.0.0", "--port", "9000", "--database", "sqlite:///x.db"])
    assert (ns.host, ns.port, ns.database, ns.func.__name__) == ("0.0.0.0", 9000, "sqlite:///x.db", "cmd_serve")
    defaults = build_parser().parse_args(["serve"])
    assert (defaults.host, defaults.port, defaults.database) == ("127.0.0.1", 8000, None)


def test_serve_with_an_unreachable_database_is_a_one_line_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("GEOMCHECK_DATA_DIR", str(tmp_path))
    status = main(["serve", "--database", "postgresql://nobody:hunter2@127.0.0.1:1/x?connect_timeout=1"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.startswith("geomcheck: error: cannot open database postgresql+psycopg://nobody:***@127.0.0.1:1/x")
    assert err.count("\n") == 1 and "hunter2" not in err


def test_the_library_does_not_import_the_service() -> None:
    code = (
        "import sys, geomcheck.cli, geomcheck.pipeline, geomcheck.report; "
        "print(any(m == 'api' or m.startswith('api.') for m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
