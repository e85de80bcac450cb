"""The distributed mode on loopback: 2 `geomcheck serve` and 2 `geomcheck worker` on a real broker and PostgreSQL.

Checks are submitted alternately to both APIs (12 in the default run, 40 with
``pytest -m campaign``), the first two slow by construction (a chain of continuous joints whose
sweeps take seconds: a worker then holds a check long enough to be caught at it, where the
others each take a fraction of a second), every sixth a package with meshes (a small one in the
default run, the bundled example in the campaign), the rest small bare URDFs; one worker is
SIGKILLed while it runs a check and one API is restarted: every check ends `succeeded`, with the CLI's
report, read the same from either API. Once with Redis, once with RabbitMQ as broker.
"""

from __future__ import annotations

import json
import socket
import time
from pathlib import Path
from typing import Any

import httpx
import pytest
import sqlalchemy as sa
from apitools import (
    EXAMPLE,
    EXAMPLE_ROOT,
    TWO_LINKS,
    assert_same_report,
    drop_store,
    long_chain,
    post_xml,
    unique_prefix,
    verified_check,
    zip_bytes,
    zip_folder,
)
from clustertools import Cluster, cluster, database_url, rabbitmq_url, redis_url
from fastapi.testclient import TestClient

from api.http.app import create_app
from api.settings import Settings
from api.store import Store
from geomcheck.cli import main as cli_main
from tests.packagetools import MESH_PACKAGE_ROOT, mesh_package, write_package

pytestmark = pytest.mark.long

CHECKS = 12  # the default run; the campaign submits CAMPAIGN_CHECKS
CAMPAIGN_CHECKS = 40
PACKAGE_EVERY = 6  # every sixth check is a package with meshes; the rest small bare URDFs
SLOW_FIRST = 2  # the first checks are slow (seconds of sweeps), one for each worker to be caught holding
SLOW_JOINTS = 5  # continuous joints of the slow chain: about 3 s of checking on a quiet 2-core machine
# a killed worker's check is taken over within about this [s]; a live worker renews its lease
# every third of it, so a loaded machine must delay a renewal by two thirds of it to lose one
LEASE_S = "4"
FINISH_TIMEOUT_S = 150.0


def cli_report(cwd: Path, root: str, monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> dict[str, Any]:
    output = tmp_path / f"cli-{Path(root).name}.json"
    with monkeypatch.context() as patch:
        patch.chdir(cwd)
        assert cli_main(["check", root, "--format", "json", "--no-config", "-o", str(output)]) in (0, 1)
    return dict(json.loads(output.read_text()))


@pytest.fixture(scope="module")
def database() -> str:
    return database_url()


def running_on(store: Store, pid: int) -> list[str]:
    """Ids of the checks a worker process with ``pid`` holds now."""
    c = store.checks.c
    with store.engine.connect() as conn:
        rows = conn.execute(sa.select(c.id, c.owner).where(c.status == "running")).all()
    return [row.id for row in rows if row.owner and row.owner.split(":")[1] == str(pid)]


def attempts_of(store: Store, check_id: str) -> int:
    with store.engine.connect() as conn:
        return int(conn.execute(sa.select(store.checks.c.attempts).where(store.checks.c.id == check_id)).scalar_one())


def lost_leases(nodes: Cluster, check_id: str) -> int:
    """Runs of ``check_id`` that a live worker lost because its lease had lapsed (a renewal
    later than the lease, on a loaded machine): each one is an attempt more. The worker logs
    the heartbeat's notice when a renewal finds the check taken, and the dropped result when
    the run ends; a run whose check was taken between two renewals ends with the second alone.
    Per worker, the larger count is its number of lost runs."""
    noticed = f"check {check_id} was cancelled or taken over"
    dropped = f"check {check_id}: finished, but the check was cancelled or taken over meanwhile"
    return sum(max(nodes.log(name).count(noticed), nodes.log(name).count(dropped)) for name in nodes.workers)


def run_cluster(broker: str, database: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, checks: int) -> None:
    if checks > CHECKS:  # the campaign posts the bundled example
        if not (EXAMPLE / EXAMPLE_ROOT).is_file():
            pytest.skip("examples/pr2_base is not in this tree")
        package, package_root, archive = EXAMPLE, EXAMPLE_ROOT, zip_folder(EXAMPLE)
    else:
        files = mesh_package()
        package, package_root, archive = write_package(tmp_path / "package", files), MESH_PACKAGE_ROOT, zip_bytes(files)
    (tmp_path / "bare").mkdir()
    (tmp_path / "bare" / "two_links.urdf").write_bytes(TWO_LINKS)
    (tmp_path / "slow").mkdir()
    (tmp_path / "slow" / "long_chain.urdf").write_bytes(long_chain(SLOW_JOINTS))
    expected = {
        "package": cli_report(package, package_root, monkeypatch, tmp_path),
        "bare": cli_report(tmp_path / "bare", "two_links.urdf", monkeypatch, tmp_path),
        "slow": cli_report(tmp_path / "slow", "long_chain.urdf", monkeypatch, tmp_path),
    }
    assert expected["package"]["robot"]["meshes_loaded"] == expected["package"]["robot"]["meshes_total"] > 0
    prefix = unique_prefix()
    store = Store(database, prefix)
    try:
        with cluster(tmp_path, broker, database, prefix, lease_s=LEASE_S, requeue_after_s="30") as nodes:
            first = nodes.start_worker("w1")
            nodes.start_worker("w2")
            bases = [nodes.spawn_api("api1"), nodes.spawn_api("api2")]
            for name in ("api1", "api2"):
                nodes.wait_api_ready(name)
            for name in ("w1", "w2"):  # both take checks from the start
                nodes.wait_worker_ready(name)
            submitted: list[tuple[str, str]] = []
            fresh = {"wait": "false", "cache": "false"}  # every submission runs: identical ones would share one
            for i in range(checks):
                base = bases[i % 2]
                if i < SLOW_FIRST:
                    kind, body, params = "slow", long_chain(SLOW_JOINTS), {"root": "long_chain.urdf", **fresh}
                    headers = {"content-type": "application/xml"}
                elif i % PACKAGE_EVERY == 0:  # a package with meshes; the rest small bare URDFs (the test stays short)
                    kind, body, params = "package", archive, {"root": package_root, **fresh}
                    headers = {"content-type": "application/zip"}
                else:
                    kind, body, params = "bare", TWO_LINKS, {"root": "two_links.urdf", **fresh}
                    headers = {"content-type": "application/xml"}
                answer = httpx.post(f"{base}/v1/checks", content=body, params=params, headers=headers, timeout=60)
                assert answer.status_code == 202, answer.text
                assert answer.json()["status"] in ("queued", "running", "succeeded")  # a free worker may be quick
                submitted.append((answer.json()["id"], kind))

            # SIGKILL the first worker in the middle of a check it holds
            deadline = time.monotonic() + 90
            while not (held := running_on(store, first.pid)):
                assert time.monotonic() < deadline, f"worker w1 ran no check within 90 s: {nodes.log('w1')[-2000:]}"
                time.sleep(0.05)
            first.kill()
            first.wait(timeout=10)

            # restart the second API on the same port while the checks run
            port = nodes.stop_api("api2")
            assert nodes.start_api("api2", port) == bases[1]

            deadline = time.monotonic() + FINISH_TIMEOUT_S
            pending = {check_id for check_id, _ in submitted}
            while pending:
                assert time.monotonic() < deadline, f"{len(pending)} checks unfinished: {nodes.log('w2')[-3000:]}"
                page = httpx.get(f"{bases[0]}/v1/checks", params={"limit": 200}, timeout=30).json()["items"]
                pending -= {c["id"] for c in page if c["status"] not in ("queued", "running")}
                time.sleep(0.5)

            for check_id, kind in submitted:
                # the report is final once the verification of its fixes ended: compared before, the two
                # replicas can each serve it at another moment of that verification
                with httpx.Client(base_url=bases[0], timeout=30) as api:
                    one = verified_check(api, check_id)
                assert (one["status"], one["reason"]) == ("succeeded", None), one
                report_1 = httpx.get(f"{bases[0]}/v1/checks/{check_id}/report.json", timeout=30).text
                report_2 = httpx.get(f"{bases[1]}/v1/checks/{check_id}/report.json", timeout=30).text
                assert report_1 == report_2
                assert_same_report(json.loads(report_1), expected[kind])
            # taken over once, not lost: every further attempt is a lease the surviving worker says it lost
            assert all(attempts_of(store, check_id) == 2 + lost_leases(nodes, check_id) for check_id in held)
            metrics = httpx.get(f"{bases[1]}/metrics", timeout=30).text
            assert f'geomcheck_checks{{status="succeeded"}} {checks}.0' in metrics
            assert f"geomcheck_check_duration_seconds_count {checks}.0" in metrics
            assert "geomcheck_queue_depth 0.0" in metrics
    finally:
        store.drop_schema()
        store.dispose()


SIZES = [pytest.param(CHECKS, id="default"), pytest.param(CAMPAIGN_CHECKS, id="campaign", marks=pytest.mark.campaign)]


@pytest.mark.parametrize("checks", SIZES)
def test_cluster_on_redis(database: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, checks: int) -> None:
    run_cluster(redis_url(), database, tmp_path, monkeypatch, checks)


@pytest.mark.parametrize("checks", SIZES)
def test_cluster_on_rabbitmq(database: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, checks: int) -> None:
    run_cluster(rabbitmq_url(), database, tmp_path, monkeypatch, checks)


def test_readyz_names_an_unreachable_broker(database: str, tmp_path: Path) -> None:
    with socket.socket() as sock:  # a port nothing listens on once closed
        sock.bind(("127.0.0.1", 0))
        dead = f"redis://127.0.0.1:{sock.getsockname()[1]}/0"
    prefix = unique_prefix()
    settings = Settings(data_dir=tmp_path / "data", broker_url=dead, database_url=database, table_prefix=prefix)
    try:
        with TestClient(create_app(settings)) as client:
            ready = client.get("/readyz")
            assert ready.status_code == 503
            assert ready.json() == {"ready": False, "database": "ok", "broker": "unavailable"}
            assert client.get("/healthz").status_code == 200  # liveness: the process answers
            refused = post_xml(client, TWO_LINKS, wait="false")
            assert refused.status_code == 503
            assert refused.json()["detail"].startswith("the broker did not accept the check: ")
            failed = client.get("/v1/checks").json()["items"]
            assert [(c["status"], c["http_status"]) for c in failed] == [("failed", 503)]
    finally:
        drop_store(database, prefix)
