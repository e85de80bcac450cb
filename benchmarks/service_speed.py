"""How long the service takes to answer with a report, against ``geomcheck check --no-cache``.

    python benchmarks/service_speed.py [--repeat 3] [--robot pr2_2009]

The robot is a table of ``robots.toml`` (``$GEOMCHECK_CORPUS``; by default the 2009 PR2),
zipped as its package tree: the folder holding its root file and packages. Each repeat times

* ``geomcheck check ROOT --package ... --no-cache --format json`` in a fresh process, stage
  caches off (what a CI job pays), and
* a POST of the zip (``root`` as robots.toml names it, ``cache=false``) to a real
  ``geomcheck serve`` on loopback (embedded mode, SQLite, no stage cache), until it answers
  with the report; then how long the verification of the offered fixes goes on after it.

It prints each figure, the minimum and median of each, the ratio of the medians (target:
the service answers within 1.5 times the CLI's time) and the load average before and after
(the machine may be shared: figures taken under load are slower, and the ratio says more
than either). Exit status 1 when the ratio misses the target or a request failed.
"""

from __future__ import annotations

import argparse
import io
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import httpx

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
import corpus_robots  # noqa: E402  (the scripts folder is not a package)

TARGET_RATIO = 1.5  # the service's answer against the CLI's whole run [ratio]
START_TIMEOUT_S = 120.0
REQUEST_TIMEOUT_S = 900.0


def load_average() -> str:
    one, five, fifteen = os.getloadavg()
    return f"{one:.2f} {five:.2f} {fifteen:.2f}"


def tree_of(robot: corpus_robots.CorpusRobot) -> Path:
    return Path(os.path.commonpath([str(p) for p in robot.packages.values()] + [str(robot.root.parent)]))


def zipped(tree: Path) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED, compresslevel=1) as archive:
        for path in sorted(tree.rglob("*")):
            if path.is_file():
                archive.write(path, path.relative_to(tree).as_posix())
    return buffer.getvalue()


def time_cli(robot: corpus_robots.CorpusRobot, cache_dir: Path) -> float:
    flags = [f"--package={name}={folder}" for name, folder in robot.packages.items()]
    flags += [f"--arg={name}={value}" for name, value in robot.args.items()]
    command = [sys.executable, "-m", "geomcheck", "check", str(robot.root), *flags, "--no-cache", "--format", "json"]
    env = {**os.environ, "GEOMCHECK_CACHE_DIR": str(cache_dir), "GEOMCHECK_UNTRUSTED": "0"}
    started = time.perf_counter()
    done = subprocess.run(command, env=env, capture_output=True, timeout=REQUEST_TIMEOUT_S, cwd=tree_of(robot))
    seconds = time.perf_counter() - started
    if done.returncode not in (0, 1):
        raise SystemExit(f"geomcheck check failed ({done.returncode}): {done.stderr.decode()[-2000:]}")
    return seconds


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def start_server(data_dir: Path, port: int) -> subprocess.Popen[bytes]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("GEOMCHECK_")}
    env.update(GEOMCHECK_DATA_DIR=str(data_dir), GEOMCHECK_WORKERS="1", GEOMCHECK_WAIT_S=str(REQUEST_TIMEOUT_S))
    command = [sys.executable, "-m", "geomcheck", "serve", "--host", "127.0.0.1", "--port", str(port)]
    log = (data_dir / "server.log").open("wb")
    return subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT, cwd=REPO)


def wait_healthy(base: str, server: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    while time.monotonic() < deadline:
        if server.poll() is not None:
            raise SystemExit(f"the server exited with status {server.returncode} before answering")
        try:
            if httpx.get(f"{base}/healthz", timeout=2).status_code == 200:
                return
        except httpx.HTTPError:
            pass
        time.sleep(0.2)
    raise SystemExit(f"the server did not answer /healthz within {START_TIMEOUT_S:g} s")


def time_service(base: str, body: bytes, root: str, args: dict[str, str]) -> tuple[float, float, str]:
    """Seconds until the POST answers with the report, then until the fixes are verified, and their state."""
    params: list[tuple[str, str]] = [("root", root), ("cache", "false")]
    params += [("args", f"{name}={value}") for name, value in args.items()]
    started = time.perf_counter()
    response = httpx.post(
        f"{base}/v1/checks",
        params=params,
        content=body,
        headers={"content-type": "application/zip"},
        timeout=REQUEST_TIMEOUT_S,
    )
    answered = time.perf_counter() - started
    if response.status_code != 201:
        raise SystemExit(f"POST answered {response.status_code}: {response.text[:2000]}")
    check = response.json()
    while (check.get("fixes") or {}).get("status") == "verifying":
        time.sleep(0.25)
        check = httpx.get(f"{base}/v1/checks/{check['id']}", timeout=30).json()
    state = (check.get("fixes") or {}).get("status") or "none offered"
    return answered, time.perf_counter() - started - answered, state


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--robot", default="pr2_2009", help="a table of robots.toml")
    options = parser.parse_args()
    corpus = corpus_robots.corpus_dir()
    if corpus is None:
        raise SystemExit("the robot corpus was not found: set GEOMCHECK_CORPUS")
    [robot] = [r for r in corpus_robots.robots(corpus) if r.name == options.robot]
    tree = tree_of(robot)
    root = robot.root.relative_to(tree).as_posix()
    body = zipped(tree)
    print(f"robot {robot.name}: {root} in {tree.name}/ ({len(body) / 1e6:.1f} MB zipped); cores {os.cpu_count()}")
    print(f"load average before: {load_average()}")
    cli: list[float] = []
    service: list[float] = []
    after: list[float] = []
    with tempfile.TemporaryDirectory(prefix="geomcheck-service-speed-") as scratch:
        data = Path(scratch) / "data"
        data.mkdir()
        port = free_port()
        server = start_server(data, port)
        base = f"http://127.0.0.1:{port}"
        try:
            wait_healthy(base, server)
            for index in range(options.repeat):
                cli.append(time_cli(robot, Path(scratch) / f"cache-{index}"))
                answered, verifying, state = time_service(base, body, root, dict(robot.args))
                service.append(answered)
                after.append(verifying)
                print(
                    f"  run {index + 1}: geomcheck check --no-cache {cli[-1]:.2f} s; service report {answered:.2f} s "
                    f"(ratio {answered / cli[-1]:.2f}), fixes {state} {verifying:.2f} s after it; "
                    f"load {load_average()}"
                )
        finally:
            server.send_signal(signal.SIGINT)
            try:
                server.wait(timeout=60)
            except subprocess.TimeoutExpired:
                server.kill()
                server.wait(timeout=10)
    ratio = statistics.median(service) / statistics.median(cli)
    print(f"geomcheck check --no-cache: min {min(cli):.2f} s, median {statistics.median(cli):.2f} s")
    print(f"service, POST to report:    min {min(service):.2f} s, median {statistics.median(service):.2f} s")
    print(f"fixes verified after it:    min {min(after):.2f} s, median {statistics.median(after):.2f} s")
    print(f"ratio service / CLI (medians): {ratio:.2f} (target at most {TARGET_RATIO:g})")
    print(f"load average after: {load_average()}")
    return 0 if ratio <= TARGET_RATIO else 1


if __name__ == "__main__":
    sys.exit(main())
