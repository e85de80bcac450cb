"""Load test of the HTTP service: a real uvicorn on loopback, concurrent clients POSTing the bundled example.

    python benchmarks/load_api.py [--clients 50] [--requests 500] [--workers 2]

Starts ``geomcheck serve`` on 127.0.0.1 (a free port) over a temporary SQLite data folder,
sends ``--requests`` POSTs of examples/pr2_base as a zip from ``--clients`` concurrent
clients, prints the latency percentiles and the error count, and stops the server. Exit
status 1 when any request failed. Only loopback traffic; every wait is bounded.
"""

from __future__ import annotations

import argparse
import io
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import zipfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx
import numpy

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "examples" / "pr2_base"
EXAMPLE_ROOT = "robots/pr2_base.urdf.xacro"
START_TIMEOUT_S = 120.0
REQUEST_TIMEOUT_S = 600.0


def example_zip() -> bytes:
    """examples/pr2_base zipped as its package tree (waits a bounded time for it to exist)."""
    deadline = time.monotonic() + START_TIMEOUT_S
    while not (EXAMPLE / EXAMPLE_ROOT).is_file():
        if time.monotonic() > deadline:
            raise SystemExit(f"no {EXAMPLE / EXAMPLE_ROOT}: the bundled example is missing")
        time.sleep(1.0)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(p for p in EXAMPLE.rglob("*") if p.is_file()):
            archive.write(path, path.relative_to(EXAMPLE).as_posix())
    return buf.getvalue()


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def start_server(data_dir: Path, port: int, workers: int) -> subprocess.Popen[bytes]:
    env = {**os.environ, "GEOMCHECK_DATA_DIR": str(data_dir), "GEOMCHECK_WORKERS": str(workers)}
    env.pop("GEOMCHECK_DATABASE_URL", None)
    env.pop("GEOMCHECK_API_TOKENS", None)
    command = [sys.executable, "-m", "geomcheck", "serve", "--host", "127.0.0.1", "--port", str(port)]
    log = (data_dir / "server.log").open("wb")
    return subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT)


def wait_healthy(base: str, server: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    while time.monotonic() < deadline:
        if server.poll() is not None:
            raise SystemExit(f"the server exited with status {server.returncode} before answering")
        try:
            if httpx.get(f"{base}/healthz", timeout=2.0).status_code == 200:
                return
        except httpx.HTTPError:
            pass
        time.sleep(0.2)
    raise SystemExit(f"the server did not answer /healthz within {START_TIMEOUT_S:g} s")


def stop_server(server: subprocess.Popen[bytes]) -> None:
    if server.poll() is None:
        server.send_signal(signal.SIGINT)
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait(timeout=10)


def run_load(base: str, body: bytes, clients: int, requests: int) -> tuple[list[float], list[str], float]:
    """(latencies [s] of the successful requests, error descriptions, wall time [s])."""
    latencies: list[float] = []
    errors: list[str] = []
    lock = threading.Lock()
    per_client = [requests // clients + (1 if i < requests % clients else 0) for i in range(clients)]

    def client(count: int) -> None:
        with httpx.Client(base_url=base, timeout=REQUEST_TIMEOUT_S) as http:
            for _ in range(count):
                started = time.perf_counter()
                try:
                    response = http.post(
                        "/v1/checks",
                        content=body,
                        params={"root": EXAMPLE_ROOT},
                        headers={"content-type": "application/zip"},
                    )
                    elapsed = time.perf_counter() - started
                    ok = response.status_code == 201 and response.json()["status"] == "succeeded"
                    outcome = None if ok else f"{response.status_code}: {response.text[:200]}"
                except httpx.HTTPError as err:
                    elapsed, outcome = time.perf_counter() - started, f"{type(err).__name__}: {err}"
                with lock:
                    if outcome is None:
                        latencies.append(elapsed)
                    else:
                        errors.append(outcome)

    started = time.perf_counter()
    with ThreadPoolExecutor(max_workers=clients) as pool:
        list(pool.map(client, per_client))
    return latencies, errors, time.perf_counter() - started


def check_run_times(base: str, expected: int) -> list[float]:
    """Run time [s] of every stored succeeded check, paging through GET /v1/checks (bounded)."""
    times: list[float] = []
    cursor = None
    for _ in range(expected // 200 + 2):
        params: dict[str, str | int] = {"limit": 200, "status": "succeeded"}
        if cursor:
            params["cursor"] = cursor
        page = httpx.get(f"{base}/v1/checks", params=params, timeout=30).json()
        times.extend(item["seconds"] for item in page["items"] if item["seconds"] is not None)
        cursor = page["next_cursor"]
        if cursor is None:
            break
    return times


def percentile(values: list[float], q: float) -> float:
    """The ``q`` percentile (0..100) of ``values`` [s]; NaN when there are none."""
    return float(numpy.percentile(values, q)) if values else float("nan")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=50, help="concurrent clients (default 50)")
    parser.add_argument("--requests", type=int, default=500, help="POSTs in all (default 500)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 2, help="check processes of the server")
    ns = parser.parse_args()
    body = example_zip()
    load_before = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory(prefix="geomcheck-load-") as tmp:
        data_dir = Path(tmp)
        server = start_server(data_dir, port, ns.workers)
        try:
            wait_healthy(base, server)
            print(
                f"server {base}: {ns.workers} check workers; {ns.clients} clients, {ns.requests} POSTs of "
                f"examples/pr2_base as a zip ({len(body)} bytes)"
            )
            latencies, errors, wall = run_load(base, body, ns.clients, ns.requests)
            run_times = check_run_times(base, ns.requests)
        finally:
            stop_server(server)
    done = len(latencies)
    print(f"requests: {done + len(errors)}  succeeded: {done}  errors: {len(errors)}")
    print(
        f"latency p50: {percentile(latencies, 50):.3f} s  p95: {percentile(latencies, 95):.3f} s  "
        f"max: {max(latencies, default=float('nan')):.3f} s"
    )
    print(f"wall time: {wall:.1f} s  throughput: {done / wall:.2f} checks/s  (load average before: {load_before})")
    print(
        f"check process time (stored per check): p50 {percentile(run_times, 50):.3f} s  "
        f"p95 {percentile(run_times, 95):.3f} s over {len(run_times)} checks; the rest of a latency is queueing"
    )
    for error in errors[:5]:
        print(f"error: {error}")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
