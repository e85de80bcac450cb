"""An API replica of the distributed mode (in-process) with a real `geomcheck worker` on Redis and PostgreSQL:
waiting POSTs, 202 when the wait runs out, DELETE of a queued check that a worker then leaves alone."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from apitools import (
    EXAMPLE,
    EXAMPLE_ROOT,
    TWO_LINKS,
    assert_progress_of_a_run,
    drop_store,
    long_chain,
    post_xml,
    post_zip,
    sleep_long,
    unique_prefix,
    verified_check,
    watch_progress,
    zip_folder,
)
from clustertools import cluster, database_url, redis_url
from fastapi.testclient import TestClient

from api.http.app import create_app
from api.settings import Settings
from api.store import Store

pytestmark = pytest.mark.long


@pytest.fixture
def replica(tmp_path: Path) -> Iterator[tuple[TestClient, Settings]]:
    database, broker, prefix = database_url(), redis_url(), unique_prefix()
    settings = Settings(
        data_dir=tmp_path / "api",
        database_url=database,
        broker_url=broker,
        table_prefix=prefix,
        queue=f"gc-test-{prefix.strip('_')}",
        wait_s=1.0,
        lease_s=2.0,
    )
    try:
        with TestClient(create_app(settings)) as client:
            yield client, settings
    finally:
        drop_store(database, prefix)


def test_queued_checks_wait_cancel_and_run_on_a_worker(replica: tuple[TestClient, Settings], tmp_path: Path) -> None:
    client, settings = replica
    assert client.get("/readyz").json() == {"ready": True, "database": "ok", "broker": "ok"}
    timed_out = post_xml(client, TWO_LINKS, root="two_links.urdf")  # no worker yet: the 1 s wait runs out
    assert timed_out.status_code == 202
    assert timed_out.headers["location"] == f"/v1/checks/{timed_out.json()['id']}"
    queued = post_xml(client, TWO_LINKS, wait="false").json()["id"]
    cancelled = client.delete(f"/v1/checks/{queued}")
    assert cancelled.status_code == 200
    assert (cancelled.json()["status"], cancelled.json()["reason"]) == ("cancelled", "cancelled by a DELETE request")
    again = client.delete(f"/v1/checks/{queued}")
    assert again.status_code == 409 and again.json()["detail"].endswith("has already finished (status cancelled)")
    assert client.delete("/v1/checks/nope").status_code == 404

    database, prefix = settings.database_url or "", settings.table_prefix
    with cluster(tmp_path, settings.broker_url or "", database, prefix, queue=settings.queue) as nodes:
        nodes.start_worker("w")
        service = client.app.state.service  # type: ignore[attr-defined]
        service.settings = settings.model_copy(update={"wait_s": 120.0})  # now a worker runs: wait for it
        done = post_xml(client, TWO_LINKS, root="two_links.urdf")
        assert done.status_code == 201, done.text
        assert done.json()["report"]["robot"]["name"] == "two_links"
        deadline = time.monotonic() + 60
        while client.get(f"/v1/checks/{timed_out.json()['id']}").json()["status"] != "succeeded":
            assert time.monotonic() < deadline, nodes.log("w")[-2000:]
            time.sleep(0.2)
        while "not claimed" not in nodes.log("w"):  # the cancelled check's message, consumed and dropped
            assert time.monotonic() < deadline, nodes.log("w")[-2000:]
            time.sleep(0.2)
        # the identical submission shared the first one's run; the result cache lives in the database,
        # so another replica answers a re-post from it at once
        assert done.json()["cached_from"] == timed_out.json()["id"]
        with TestClient(create_app(settings.model_copy(update={"data_dir": tmp_path / "api2"}))) as other:
            again = post_xml(other, TWO_LINKS, root="two_links.urdf")
            assert again.status_code == 201, again.text
            assert (again.json()["cached"], again.json()["cached_from"]) == (True, timed_out.json()["id"])
            assert again.json()["report"] == done.json()["report"]

        # a running check cancelled: its worker kills it at the next lease renewal, and never stores its result
        slow = post_zip(client, zip_folder(EXAMPLE), root=EXAMPLE_ROOT, matrix="true", samples="200000", wait="false")
        slow_id = slow.json()["id"]
        while client.get(f"/v1/checks/{slow_id}").json()["status"] != "running":
            assert time.monotonic() < deadline, nodes.log("w")[-2000:]
            time.sleep(0.05)
        assert client.delete(f"/v1/checks/{slow_id}").json()["status"] == "cancelled"
        while f"check {slow_id}: finished, but the check was cancelled" not in nodes.log("w"):
            assert time.monotonic() < deadline, nodes.log("w")[-2000:]
            time.sleep(0.1)
        # killed at its next lease renewal ("stopping it" in the log), or finished just before it: dropped either way
    assert client.get(f"/v1/checks/{queued}").json()["status"] == "cancelled"
    statuses = sorted(c["status"] for c in client.get("/v1/checks").json()["items"])
    assert statuses == ["cancelled", "cancelled", "succeeded", "succeeded", "succeeded"]


def test_a_check_on_a_worker_shows_its_progress_through_the_database(
    replica: tuple[TestClient, Settings], tmp_path: Path
) -> None:
    """The worker (another process, as it would be another machine) writes the progress of its
    check to PostgreSQL, where the API replica reads it."""
    client, settings = replica
    database, prefix = settings.database_url or "", settings.table_prefix
    with cluster(tmp_path, settings.broker_url or "", database, prefix, queue=settings.queue) as nodes:
        nodes.start_worker("w")
        # seven joints: the sweeps of a pair known to collide stop halving within its contact ranges,
        # and a shorter chain can finish between two polls of the progress
        created = post_xml(client, long_chain(7), wait="false", cache="false")
        assert created.status_code == 202
        seen, done = watch_progress(client.get, created.json()["id"])
        done = verified_check(client, done["id"])  # and the verification of its fixes, when it offers some
    assert_progress_of_a_run(seen)
    assert done["status"] == "succeeded" and done["progress"] is None


def test_the_distributed_mode_needs_a_shared_database(tmp_path: Path) -> None:
    from geomcheck.errors import UsageError

    with pytest.raises(UsageError, match="needs a database every node reaches"):
        create_app(Settings(data_dir=tmp_path, broker_url="redis://127.0.0.1:6379/0"))
    with pytest.raises(UsageError, match="invalid GEOMCHECK_BROKER_URL scheme"):
        create_app(Settings(data_dir=tmp_path, broker_url="kafka://x", database_url="postgresql://u@h/d"))


def test_a_worker_kills_a_running_check_cancelled_under_it(tmp_path: Path) -> None:
    from api.checks.blobs import JobSpec, pack
    from api.distributed.worker import CheckWorker

    database, prefix = database_url(), unique_prefix()
    settings = Settings(data_dir=tmp_path / "w", database_url=database, table_prefix=prefix, lease_s=1.5)
    store = Store(database, prefix)
    store.create_schema()
    upload = tmp_path / "upload"
    (upload / "tree").mkdir(parents=True)
    (upload / "tree" / "r.urdf").write_bytes(TWO_LINKS)
    spec = JobSpec("tree/r.urdf", "tree", "tree", None, {})
    store.create("slow", "r.urdf", {}, upload=store.put_blob(pack(upload)), spec=spec.as_json())
    worker = CheckWorker(settings, store, name="test-host:1")
    worker.target = sleep_long
    outcome: list[str] = []
    try:
        runner = threading.Thread(target=lambda: outcome.append(worker.run("slow")))
        runner.start()
        deadline = time.monotonic() + 60
        while store.get("slow").status != "running" or worker.runner.running != 1:  # type: ignore[union-attr]
            assert time.monotonic() < deadline
            time.sleep(0.05)
        cancelled_at = time.monotonic()
        assert store.cancel("slow")
        runner.join(timeout=30)
        assert time.monotonic() - cancelled_at < 5  # killed at the next renewal (every 0.5 s), not after an hour
        assert outcome == ["finished, but the check was cancelled or taken over meanwhile: result dropped"]
        assert worker.runner.running == 0
        record = store.get("slow")
        assert record is not None and (record.status, record.reason) == ("cancelled", "cancelled by a DELETE request")
        assert list(settings.work_dir.iterdir()) == []  # its work folder removed
    finally:
        worker.runner.stop()
        store.drop_schema()
        store.dispose()


def test_a_worker_killed_with_sigkill_leaves_no_beat_behind(tmp_path: Path) -> None:
    """``geomcheck worker --beat``: Celery runs beat in a process of its own, which outlived a
    worker killed with SIGKILL as an orphan; it now goes with it."""
    with cluster(tmp_path, redis_url(), database_url(), unique_prefix()) as nodes:
        env = {**nodes.env, "GEOMCHECK_DATA_DIR": str(tmp_path / "beat")}
        command = [sys.executable, "-m", "geomcheck", "worker", "--concurrency", "1", "--beat"]
        worker = subprocess.Popen(command, env=env, stdout=nodes._log("beat"), stderr=subprocess.STDOUT)
        nodes.workers["beat"] = worker
        nodes.wait_worker_ready("beat")
        deadline = time.monotonic() + 60
        while not (beats := children_running(worker.pid, "geomcheck worker")):
            assert time.monotonic() < deadline, "no beat process started"
            time.sleep(0.2)
        worker.kill()
        worker.wait(timeout=10)
        deadline = time.monotonic() + 10
        try:
            while alive := [pid for pid in beats if Path(f"/proc/{pid}").exists() and not zombie(pid)]:
                assert time.monotonic() < deadline, f"the beat process {alive} outlived its worker"
                time.sleep(0.1)
        finally:  # never leave one behind, whatever the outcome
            for pid in beats:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)


def children_running(parent: int, command: str) -> list[int]:
    """Pids of ``parent``'s children whose command line holds ``command``."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            cmdline = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if int(stat[1]) == parent and command in cmdline:
            found.append(int(entry.name))
    return found


def zombie(pid: int) -> bool:
    try:
        return (Path(f"/proc/{pid}") / "stat").read_text().rsplit(")", 1)[1].split()[0] == "Z"
    except OSError:
        return True
