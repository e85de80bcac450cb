"""`geomcheck serve` as the docs run it: a real uvicorn on loopback, restarted over the same data folder."""

from __future__ import annotations

import contextlib
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx
import pytest
from apitools import TWO_LINKS
from servertools import free_port, serving

from geomcheck.cli import build_parser, main

pytestmark = pytest.mark.long


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


@pytest.mark.corpus
def test_sigterm_ends_waiting_posts_and_their_checks(tmp_path: Path, corpus: Path) -> None:
    from apitools import zip_folder

    from api.checks.service import RESTART_REASON
    from api.store import Store

    port = free_port()
    answers: list[tuple[int, object] | str] = []
    # the 2009 PR2 with a 200,000-sample collision matrix: minutes of work for each check
    slow = zip_folder(corpus / "pr2_2009" / "pr2_description")
    params = {"root": "robots/pr2.urdf.xacro", "matrix": "true", "samples": "200000", "cache": "false"}

    def post() -> None:
        try:
            response = httpx.post(
                f"http://127.0.0.1:{port}/v1/checks",
                params=params,
                content=slow,
                headers={"content-type": "application/zip"},
                timeout=120,
            )
            answers.append((response.status_code, response.json()))  # JSON, not uvicorn's plain-text 500
        except (httpx.HTTPError, ValueError) as err:
            answers.append(type(err).__name__)

    server_env = {"workers": "1", "shutdown_timeout_s": "2", "check_timeout_s": "600", "check_cpu_s": "600"}
    with serving(tmp_path / "data", port, **server_env) as base:
        posters = [threading.Thread(target=post) for _ in range(2)]  # one running, one queued behind it
        for poster in posters:
            poster.start()
        deadline = time.monotonic() + 60
        while httpx.get(f"{base}/healthz").json()["pending"] < 2:
            assert time.monotonic() < deadline
            time.sleep(0.1)
        stopped = time.monotonic()
    assert time.monotonic() - stopped < 20  # not after the checks' 600 s
    for poster in posters:
        poster.join(timeout=30)
    # both answered as documented before uvicorn closed their connections
    shutting_down = {"detail": "the service is shutting down: the check was stopped; submit it again"}
    assert answers == [(503, shutting_down), (503, shutting_down)]
    store = Store(f"sqlite:///{tmp_path / 'data' / 'geomcheck.db'}")
    try:
        records, _ = store.recent(10)
        # newest first: the queued check never started, the running one was stopped
        assert [(r.status, r.http_status, r.reason) for r in records] == [
            ("failed", 503, RESTART_REASON),
            ("failed", 503, "the service stopped while the check ran"),
        ]
    finally:
        store.dispose()


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


def test_a_connection_sending_its_headers_slowly_is_closed(tmp_path: Path) -> None:
    """slowloris: a header byte now and then held a connection for ever (uvicorn has no header timeout)."""
    port = free_port()
    with serving(tmp_path / "data", port, header_timeout_s="2") as base:
        with socket.create_connection(("127.0.0.1", port), timeout=30) as sock:
            started = time.monotonic()
            closed = False
            for byte in b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: " + b"a" * 40:
                try:
                    sock.sendall(bytes([byte]))
                except OSError:  # reset: closed by the server
                    closed = True
                    break
                sock.settimeout(0.5)
                try:
                    if sock.recv(1) == b"":
                        closed = True
                        break
                except TimeoutError:  # still open: the next byte
                    pass
                except OSError:  # a reset (TimeoutError, caught above, is an OSError too): closed by the server
                    closed = True
                    break
            elapsed = time.monotonic() - started
        assert closed and 1.5 < elapsed < 6, elapsed
        with socket.create_connection(("127.0.0.1", port), timeout=30) as idle:  # connected, sending nothing
            idle.settimeout(10)
            started = time.monotonic()
            with contextlib.suppress(ConnectionResetError):  # closed by the server with a reset: closed as well
                assert idle.recv(1) == b""
            assert time.monotonic() - started < 6
        assert httpx.get(f"{base}/healthz").status_code == 200  # an ordinary request is not affected
