"""Load test of the HTTP service: real servers on loopback, concurrent clients POSTing a description.

    python benchmarks/load_api.py [--clients 50] [--requests 500] [--workers 2] [--input example|pr2]
    python benchmarks/load_api.py --distributed [--worker-concurrency 1] [--clients 50] [--requests 200]
    python benchmarks/load_api.py --kill-run [--input pr2] [--requests 20]
    python benchmarks/load_api.py --cached [--input pr2] [--clients 50] [--requests 500]

Embedded (default): starts ``geomcheck serve`` on 127.0.0.1 (a free port) over a temporary
SQLite data folder, sends ``--requests`` POSTs from ``--clients`` concurrent clients, prints
the latency percentiles, the throughput and the error count, and stops the server.

``--distributed``: the Celery mode on the local Redis (``--broker``) and PostgreSQL
(``--database``), with its own table prefix and queue: two ``geomcheck serve`` replicas (the
clients alternate between them) and one ``geomcheck worker``, then a second one; the load
runs once with 1 and once with 2 worker processes and prints the same figures for each.

``--kill-run``: the deployment check of docs/deploy.md: 2 replicas, 2 workers, ``--requests``
POSTs (``wait=false``) spread over both replicas, one worker SIGKILLed once half of them
finished; prints how many succeeded and whether every report reads the same from both replicas.

``--cached``: the result cache. One POST checks the input; then ``--clients`` concurrent
clients re-post the same zip ``--requests`` times (answered from the stored report), and
then each client posts it once more with ``cache=false`` (checked again): both sets of
figures are printed side by side. Target: cached p50 under 50 ms, p95 under 200 ms, 0 errors.
The re-posts go through a bare asyncio HTTP/1.1 client (keep-alive, gzip'd answers checked
in their first 4 KiB), so the clients' CPU takes little from the server on a shared machine.

The throughput loads (embedded, ``--distributed``, ``--kill-run``) post with ``cache=false``,
so every check runs.

``--input pr2`` posts the 2009 PR2 package from ``$GEOMCHECK_CORPUS`` instead of
examples/pr2_base. Exit status 1 when any request failed. Only loopback traffic; every
wait is bounded.
"""

from __future__ import annotations

import argparse
import asyncio
import io
import json
import os
import secrets
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import zipfile
import zlib
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx
import numpy
import sqlalchemy as sa

from api.store import Store

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "examples" / "pr2_base"
EXAMPLE_ROOT = "robots/pr2_base.urdf.xacro"
PR2 = Path("pr2_2009") / "pr2_description"
PR2_ROOT = "robots/pr2.urdf.xacro"
START_TIMEOUT_S = 120.0
REQUEST_TIMEOUT_S = 900.0
KILL_RUN_TIMEOUT_S = 1800.0
FRESH = {"cache": "false"}  # the throughput loads run every check (identical POSTs would share one run)


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


def folder_zip(folder: Path) -> bytes:
    """``folder``'s files zipped, named relative to it."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(p for p in folder.rglob("*") if p.is_file()):
            archive.write(path, path.relative_to(folder).as_posix())
    return buf.getvalue()


def input_body(name: str) -> tuple[bytes, str, str]:
    """(zip, root file, label) of ``--input``."""
    if name == "pr2":
        corpus = os.environ.get("GEOMCHECK_CORPUS")
        if not corpus or not (Path(corpus) / PR2 / PR2_ROOT).is_file():
            raise SystemExit("--input pr2 needs GEOMCHECK_CORPUS naming the shared corpus (with pr2_2009)")
        return folder_zip(Path(corpus) / PR2), PR2_ROOT, "the 2009 PR2 (pr2_description)"
    return example_zip(), EXAMPLE_ROOT, "examples/pr2_base"


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def start_process(command: list[str], env: dict[str, str], log: Path) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [sys.executable, "-m", "geomcheck", *command], env=env, stdout=log.open("ab"), stderr=subprocess.STDOUT
    )


def wait_worker_ready(log: Path, worker: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    while " ready." not in log.read_text(errors="replace"):
        if worker.poll() is not None:
            raise SystemExit(f"the worker exited with status {worker.returncode}; see {log}")
        if time.monotonic() > deadline:
            raise SystemExit(f"the worker was not ready within {START_TIMEOUT_S:g} s")
        time.sleep(0.2)


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


def run_load(
    bases: list[str],
    body: bytes,
    clients: int,
    requests: int,
    root: str = EXAMPLE_ROOT,
    params: dict[str, str] | None = None,
    cached: bool | None = None,
) -> tuple[list[float], list[str], float]:
    """(latencies [s] of the successful requests, error descriptions, wall time [s]); client i uses bases[i % n].

    ``cached`` True or False: a success must also have been answered (or not) from the cache."""
    latencies: list[float] = []
    errors: list[str] = []
    lock = threading.Lock()
    per_client = [requests // clients + (1 if i < requests % clients else 0) for i in range(clients)]

    def client(index: int) -> None:
        count = per_client[index]
        with httpx.Client(base_url=bases[index % len(bases)], timeout=REQUEST_TIMEOUT_S) as http:
            for _ in range(count):
                started = time.perf_counter()
                try:
                    response = http.post(
                        "/v1/checks",
                        content=body,
                        params={"root": root, **(params or {})},
                        headers={"content-type": "application/zip"},
                    )
                    elapsed = time.perf_counter() - started
                    # the check's fields come first: read them without parsing the report
                    head = response.content[:4096]
                    ok = response.status_code == 201 and b'"status":"succeeded"' in head
                    if cached is not None:
                        ok = ok and (b'"cached":true' in head) == cached
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
        list(pool.map(client, range(clients)))
    return latencies, errors, time.perf_counter() - started


async def _raw_clients(
    host: str, port: int, request: bytes, clients: int, requests: int, cached: bool
) -> tuple[list[float], list[str], float]:
    """``requests`` identical HTTP/1.1 requests over ``clients`` keep-alive connections, each
    sending its next request when the answer to the last has arrived (closed loop).

    A bare asyncio client: httpx's per-request work (and gunzipping a large report) costs
    more CPU than the server's cached answer, and the clients share the server's cores. Each
    answer must be 201, gzip'd, and say ``"cached":true`` (or not) in its first 4 KiB."""
    latencies: list[float] = []
    errors: list[str] = []
    per_client = [requests // clients + (1 if i < requests % clients else 0) for i in range(clients)]
    wanted = b'"cached":true' if cached else b'"cached":false'

    async def client(count: int) -> None:
        reader, writer = await asyncio.open_connection(host, port)
        try:
            for _ in range(count):
                started = time.perf_counter()
                writer.write(request)
                await writer.drain()
                head = await reader.readuntil(b"\r\n\r\n")
                lines = head.decode("latin-1").split("\r\n")
                pairs = (line.partition(":") for line in lines[1:] if line)
                fields = {k.strip().lower(): v.strip() for k, _, v in pairs}
                body = await reader.readexactly(int(fields.get("content-length", "0")))
                elapsed = time.perf_counter() - started
                status = lines[0].split(" ", 2)[1]
                start = body
                if fields.get("content-encoding") == "gzip":
                    start = zlib.decompressobj(16 + zlib.MAX_WBITS).decompress(body, 4096)
                if status == "201" and b'"status":"succeeded"' in start and wanted in start:
                    latencies.append(elapsed)
                else:
                    errors.append(f"{status}: {start[:200]!r}")
        finally:
            writer.close()

    started = time.perf_counter()
    await asyncio.gather(*(client(n) for n in per_client if n))
    return latencies, errors, time.perf_counter() - started


def run_raw_load(
    base: str, body: bytes, clients: int, requests: int, root: str, cached: bool = True
) -> tuple[list[float], list[str], float]:
    """:func:`run_load` of ``body`` (a zip) with the bare asyncio client of :func:`_raw_clients`."""
    host, port = base.removeprefix("http://").rsplit(":", 1)
    head = (
        f"POST /v1/checks?root={root} HTTP/1.1\r\nHost: {host}:{port}\r\nContent-Type: application/zip\r\n"
        f"Accept-Encoding: gzip\r\nContent-Length: {len(body)}\r\n\r\n"
    )
    return asyncio.run(_raw_clients(host, int(port), head.encode("latin-1") + body, clients, requests, cached))


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


def report(label: str, latencies: list[float], errors: list[str], wall: float, run_times: list[float]) -> None:
    done = len(latencies)
    print(f"[{label}] requests: {done + len(errors)}  succeeded: {done}  errors: {len(errors)}")
    print(
        f"[{label}] latency p50: {percentile(latencies, 50):.3f} s  p95: {percentile(latencies, 95):.3f} s  "
        f"max: {max(latencies, default=float('nan')):.3f} s"
    )
    print(f"[{label}] wall time: {wall:.1f} s  throughput: {done / wall:.2f} checks/s")
    print(
        f"[{label}] check process time (stored per check): p50 {percentile(run_times, 50):.3f} s  "
        f"p95 {percentile(run_times, 95):.3f} s over {len(run_times)} checks; the rest of a latency is queueing"
    )
    for error in errors[:5]:
        print(f"[{label}] error: {error}")


def embedded(ns: argparse.Namespace, body: bytes, root: str, label: str) -> int:
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory(prefix="geomcheck-load-") as tmp:
        data_dir = Path(tmp)
        server = start_server(data_dir, port, ns.workers)
        try:
            wait_healthy(base, server)
            print(
                f"embedded server {base}: {ns.workers} check workers; {ns.clients} clients, {ns.requests} POSTs of "
                f"{label} as a zip ({len(body)} bytes)"
            )
            latencies, errors, wall = run_load([base], body, ns.clients, ns.requests, root, FRESH)
            run_times = check_run_times(base, ns.requests)
        finally:
            stop_server(server)
    report(f"embedded, {ns.workers} workers", latencies, errors, wall, run_times)
    return 1 if errors else 0


def process_cpu_s(pid: int) -> float:
    """User + system CPU time [s] of process ``pid`` so far (Linux /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def cached_load(ns: argparse.Namespace, body: bytes, root: str, label: str) -> int:
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory(prefix="geomcheck-load-") as tmp:
        server = start_server(Path(tmp), port, ns.workers)
        try:
            wait_healthy(base, server)
            print(
                f"embedded server {base}: {ns.workers} check workers; {label} as a zip ({len(body)} bytes); "
                f"{ns.clients} clients re-posting it {ns.requests} times, then {ns.clients} POSTs with cache=false"
            )
            first, first_errors, _ = run_load([base], body, 1, 1, root, cached=False)  # computes and stores
            if first_errors:
                print(f"the first check failed: {first_errors[0]}")
                return 1
            print(f"first check (computed): {first[0]:.3f} s")
            cpu_before = process_cpu_s(server.pid)
            hits, hit_errors, hit_wall = run_raw_load(base, body, ns.clients, ns.requests, root)
            server_cpu_ms = (process_cpu_s(server.pid) - cpu_before) / max(1, len(hits)) * 1000
            fresh, fresh_errors, fresh_wall = run_load(
                [base], body, ns.clients, ns.clients, root, {"cache": "false"}, cached=False
            )
            run_times = check_run_times(base, ns.requests + ns.clients + 1)
        finally:
            stop_server(server)
    report("cached", hits, hit_errors, hit_wall, [])
    print(f"[cached] server CPU per answer: {server_cpu_ms:.1f} ms (the clients run on the same machine)")
    report("uncached (cache=false)", fresh, fresh_errors, fresh_wall, run_times)
    ratio = percentile(fresh, 50) / percentile(hits, 50) if hits else float("nan")
    print(
        f"cached p50 {percentile(hits, 50) * 1000:.1f} ms (target < 50 ms), p95 {percentile(hits, 95) * 1000:.1f} ms "
        f"(target < 200 ms), errors {len(hit_errors)}; uncached p50 {percentile(fresh, 50):.2f} s ({ratio:.0f}x)"
    )
    return 1 if hit_errors or fresh_errors else 0


class Deployment:
    """Replicas and workers of the distributed mode with their own table prefix and queue."""

    def __init__(self, ns: argparse.Namespace, tmp: Path) -> None:
        self.tmp = tmp
        self.prefix = f"bench{secrets.token_hex(3)}_"
        self.env = {
            **os.environ,
            "GEOMCHECK_BROKER_URL": ns.broker,
            "GEOMCHECK_DATABASE_URL": ns.database,
            "GEOMCHECK_TABLE_PREFIX": self.prefix,
            "GEOMCHECK_QUEUE": f"bench-{self.prefix.rstrip('_')}",
            "GEOMCHECK_MAX_QUEUED": "100000",
        }
        self.env.pop("GEOMCHECK_API_TOKENS", None)
        self.concurrency = ns.worker_concurrency
        self.apis: list[tuple[str, subprocess.Popen[bytes]]] = []
        self.workers: list[subprocess.Popen[bytes]] = []

    def start_api(self) -> str:
        port = free_port()
        name = f"api{len(self.apis) + 1}"
        env = {**self.env, "GEOMCHECK_DATA_DIR": str(self.tmp / name)}
        server = start_process(["serve", "--host", "127.0.0.1", "--port", str(port)], env, self.tmp / f"{name}.log")
        base = f"http://127.0.0.1:{port}"
        wait_healthy(base, server)
        self.apis.append((base, server))
        return base

    def start_worker(self) -> subprocess.Popen[bytes]:
        name = f"worker{len(self.workers) + 1}"
        env = {**self.env, "GEOMCHECK_DATA_DIR": str(self.tmp / name)}
        log = self.tmp / f"{name}.log"
        worker = start_process(["worker", "--concurrency", str(self.concurrency)], env, log)
        wait_worker_ready(log, worker)
        self.workers.append(worker)
        return worker

    def stop(self) -> None:
        for _, server in self.apis:
            stop_server(server)
        for worker in self.workers:
            stop_server(worker)
        store = Store(self.env["GEOMCHECK_DATABASE_URL"], self.prefix)
        store.drop_schema()
        store.dispose()


def distributed(ns: argparse.Namespace, body: bytes, root: str, label: str) -> int:
    failed = False
    with tempfile.TemporaryDirectory(prefix="geomcheck-load-") as tmp:
        deployment = Deployment(ns, Path(tmp))
        try:
            bases = [deployment.start_api(), deployment.start_api()]
            for count in (1, 2):
                deployment.start_worker()
                print(
                    f"distributed: 2 API replicas, {count} worker process(es) x {ns.worker_concurrency} "
                    f"(threads pool); {ns.clients} clients, {ns.requests} POSTs of {label} ({len(body)} bytes)"
                )
                latencies, errors, wall = run_load(bases, body, ns.clients, ns.requests, root, FRESH)
                run_times = check_run_times(bases[0], ns.requests * count)[: ns.requests]
                report(f"distributed, {count} worker(s)", latencies, errors, wall, run_times)
                failed = failed or bool(errors)
        finally:
            deployment.stop()
    return 1 if failed else 0


def kill_run(ns: argparse.Namespace, body: bytes, root: str, label: str) -> int:
    """POST ``--requests`` checks over 2 replicas, SIGKILL a worker halfway, verify every one succeeds."""
    with tempfile.TemporaryDirectory(prefix="geomcheck-kill-") as tmp:
        deployment = Deployment(ns, Path(tmp))
        try:
            bases = [deployment.start_api(), deployment.start_api()]
            victim = deployment.start_worker()
            deployment.start_worker()
            print(f"kill run: 2 replicas, 2 workers x {ns.worker_concurrency}; {ns.requests} POSTs of {label}")
            started = time.perf_counter()
            ids = []
            for i in range(ns.requests):
                answer = httpx.post(
                    f"{bases[i % 2]}/v1/checks",
                    content=body,
                    params={"root": root, "wait": "false", **FRESH},
                    headers={"content-type": "application/zip"},
                    timeout=REQUEST_TIMEOUT_S,
                )
                if answer.status_code != 202:
                    raise SystemExit(f"POST answered {answer.status_code}: {answer.text[:200]}")
                ids.append(answer.json()["id"])
            statuses: dict[str, str] = {}
            killed_at = None
            deadline = time.monotonic() + KILL_RUN_TIMEOUT_S
            while True:
                statuses = {i: httpx.get(f"{bases[0]}/v1/checks/{i}", timeout=30).json()["status"] for i in ids}
                finished = [i for i, s in statuses.items() if s not in ("queued", "running")]
                if killed_at is None and len(finished) >= len(ids) // 2:
                    running = sum(s == "running" for s in statuses.values())
                    victim.kill()
                    killed_at = time.perf_counter() - started
                    print(f"SIGKILL worker 1 at {killed_at:.1f} s: {len(finished)} finished, {running} running")
                if len(finished) == len(ids):
                    break
                if time.monotonic() > deadline:
                    raise SystemExit(f"{len(ids) - len(finished)} checks unfinished after {KILL_RUN_TIMEOUT_S:g} s")
                time.sleep(1.0)
            wall = time.perf_counter() - started
            same = 0
            reports = set()
            for check_id in ids:
                one = httpx.get(f"{bases[0]}/v1/checks/{check_id}/report.json", timeout=60)
                two = httpx.get(f"{bases[1]}/v1/checks/{check_id}/report.json", timeout=60)
                same += one.status_code == 200 and one.text == two.text
                if one.status_code == 200:  # the same input gives the same report, but for its creation time
                    reports.add(json.dumps({**one.json(), "created": None}, sort_keys=True))
            store = Store(ns.database, deployment.prefix)
            with store.engine.connect() as conn:
                retried = conn.execute(
                    sa.select(sa.func.count()).select_from(store.checks).where(store.checks.c.attempts > 1)
                ).scalar()
            store.dispose()
            succeeded = sum(s == "succeeded" for s in statuses.values())
            print(
                f"kill run: {succeeded}/{len(ids)} succeeded in {wall:.1f} s; {retried} taken over after the kill; "
                f"same report from both replicas: {same}/{len(ids)}; distinct reports (sans 'created'): {len(reports)}"
            )
            return 0 if succeeded == same == len(ids) else 1
        finally:
            deployment.stop()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=50, help="concurrent clients (default 50)")
    parser.add_argument("--requests", type=int, default=None, help="POSTs in all (default 500; 20 with --kill-run)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 2, help="check processes of the server")
    parser.add_argument("--input", choices=("example", "pr2"), default="example", help="what to POST")
    parser.add_argument("--distributed", action="store_true", help="the Celery mode with 1, then 2 workers")
    parser.add_argument("--kill-run", action="store_true", help="SIGKILL a worker halfway; verify nothing is lost")
    parser.add_argument("--cached", action="store_true", help="re-posts answered from the cache against cache=false")
    parser.add_argument("--worker-concurrency", type=int, default=1, help="checks at once per worker process")
    parser.add_argument("--broker", default="redis://127.0.0.1:6379/0", help="broker URL (distributed)")
    parser.add_argument(
        "--database", default="postgresql+psycopg://postgres@127.0.0.1:5432/test", help="PostgreSQL URL (distributed)"
    )
    ns = parser.parse_args()
    if ns.requests is None:
        ns.requests = 20 if ns.kill_run else 500
    body, root, label = input_body(ns.input)
    print(f"load average before: {', '.join(f'{x:.2f}' for x in os.getloadavg())}; {os.cpu_count()} cores")
    if ns.kill_run:
        return kill_run(ns, body, root, label)
    if ns.cached:
        return cached_load(ns, body, root, label)
    if ns.distributed:
        return distributed(ns, body, root, label)
    return embedded(ns, body, root, label)


if __name__ == "__main__":
    sys.exit(main())
