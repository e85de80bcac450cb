"""Long schemathesis campaign against a real ``geomcheck serve`` on loopback.

    python benchmarks/fuzz_api.py --examples 200 --seed 1          # without tokens
    python benchmarks/fuzz_api.py --examples 200 --tokens          # with a bearer token

Runs every phase (examples, coverage, fuzzing, stateful) over every operation with every
check but the two the test suite also leaves out (see tests/api/http/test_schemathesis.py), and
prints the figures: scenarios, test cases, failures by check, 5xx answers, seconds.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

EXCLUDED_CHECKS = "positive_data_acceptance,allow_header_conformance"
TOKEN = "fuzz-token"


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=100, help="examples per operation and phase")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--tokens", action="store_true", help="start the service with a bearer token")
    ns = parser.parse_args()
    executable = shutil.which("schemathesis")
    if executable is None:
        sys.exit("schemathesis is in the test extra: pip install -e '.[test]'")
    folder = Path(tempfile.mkdtemp(prefix="geomcheck-fuzz-api-"))
    port = free_port()
    env = {**os.environ, "GEOMCHECK_DATA_DIR": str(folder / "data"), "GEOMCHECK_API_TOKENS": TOKEN if ns.tokens else ""}
    server = subprocess.Popen(
        [sys.executable, "-m", "geomcheck", "serve", "--host", "127.0.0.1", "--port", str(port)],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    base = f"http://127.0.0.1:{port}"
    events = folder / "events.ndjson"
    started = time.monotonic()
    try:
        deadline = time.monotonic() + 120
        while True:
            try:
                if httpx.get(f"{base}/healthz", timeout=2).status_code == 200:
                    break
            except httpx.HTTPError:
                pass
            if time.monotonic() > deadline or server.poll() is not None:
                sys.exit("geomcheck serve did not answer /healthz")
            time.sleep(0.2)
        command = [
            executable,
            "run",
            f"{base}/openapi.json",
            "--max-examples",
            str(ns.examples),
            "--seed",
            str(ns.seed),
            "--request-timeout",
            "300",
            "--exclude-checks",
            EXCLUDED_CHECKS,
            "--report",
            "ndjson",
            "--report-ndjson-path",
            str(events),
            "--no-color",
        ]
        if ns.tokens:
            command += ["--header", f"Authorization: Bearer {TOKEN}"]
        run = subprocess.run(command, capture_output=True, text=True, check=False)
    finally:
        server.send_signal(signal.SIGTERM)
        try:
            server.wait(timeout=60)
        except subprocess.TimeoutExpired:
            server.kill()
    seconds = time.monotonic() - started
    scenarios = cases = server_errors = 0
    failures: collections.Counter[str] = collections.Counter()
    for line in events.read_text(encoding="utf-8").splitlines():
        finished = json.loads(line).get("ScenarioFinished")
        if finished is None:
            continue
        scenarios += 1
        recorder = finished.get("recorder", {})
        cases += len(recorder.get("cases", {}))
        for interaction in recorder.get("interactions", {}).values():
            status = (interaction.get("response") or {}).get("status_code", 0)
            server_errors += status >= 500
        for checks in recorder.get("checks", {}).values():
            failures.update(c.get("name", "?") for c in checks if c.get("status") == "FAILURE")
    mode = "with tokens" if ns.tokens else "without tokens"
    print(f"schemathesis {mode}: {scenarios} scenarios, {cases} test cases, {server_errors} 5xx, {seconds:.0f} s")
    print(f"failures: {dict(failures) or 'none'}; schemathesis exit status {run.returncode}")
    if run.returncode != 0:
        print(run.stdout[-6000:])
    return run.returncode


if __name__ == "__main__":
    sys.exit(main())
