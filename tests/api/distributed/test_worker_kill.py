"""A `geomcheck worker` killed with SIGKILL in the middle of a check leaves no process behind:
not the check's, not the forkserver's, not the embedded beat's (``--beat``)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import httpx
import sqlalchemy as sa
from apitools import long_chain, unique_prefix
from clustertools import cluster, database_url, redis_url

from api.store import Store


def descendants(pid: int) -> list[int]:
    """Every process under ``pid`` (Linux: /proc/PID/task/*/children)."""
    found: list[int] = []
    try:
        tasks = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return found
    for task in tasks:
        try:
            with open(f"/proc/{pid}/task/{task}/children") as handle:
                children = [int(c) for c in handle.read().split()]
        except OSError:
            continue
        for child in children:
            found += [child, *descendants(child)]
    return found


def alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie waiting for its parent's wait does not)."""
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_a_killed_worker_leaves_no_process_behind(tmp_path: Path) -> None:
    database, broker, prefix = database_url(), redis_url(), unique_prefix()
    store = Store(database, prefix)
    try:
        with cluster(tmp_path, broker, database, prefix) as nodes:
            worker = nodes.start_worker("w1", 1, "--beat")
            base = nodes.start_api("api1")
            nodes.wait_worker_ready("w1")
            params = {"wait": "false", "matrix": "true", "samples": "200000", "cache": "false"}
            answer = httpx.post(
                f"{base}/v1/checks",
                content=long_chain(60),
                params=params,
                headers={"content-type": "application/xml"},
                timeout=30,
            )
            assert answer.status_code == 202, answer.text
            deadline = time.monotonic() + 60
            while True:
                with store.engine.connect() as conn:
                    status = conn.execute(
                        sa.select(store.checks.c.status).where(store.checks.c.id == answer.json()["id"])
                    ).scalar_one()
                if status == "running":
                    break
                assert status == "queued" and time.monotonic() < deadline, nodes.log("w1")[-2000:]
                time.sleep(0.05)
            # the forkserver, the check process it forks, the resource tracker and the beat
            while len(processes := descendants(worker.pid)) < 4 and time.monotonic() < deadline:
                time.sleep(0.05)
            assert len(processes) >= 4, processes
            worker.kill()
            worker.wait(timeout=10)
            deadline = time.monotonic() + 10
            while (left := [p for p in processes if alive(p)]) and time.monotonic() < deadline:
                time.sleep(0.1)
            assert left == []  # was: the embedded beat ran on, an orphan
    finally:
        store.drop_schema()
        store.dispose()
