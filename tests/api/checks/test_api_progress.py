"""A running check's progress through ``GET /v1/checks/{id}`` (embedded mode), and the
throttled writer carrying it from the check process into the store."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import pytest
from apitools import (
    assert_progress_of_a_run,
    long_chain,
    post_xml,
    post_zip,
    report_then_hang,
    verified_check,
    watch_progress,
    zip_bytes,
)
from fastapi.testclient import TestClient

from api.checks.progress import ProgressWriter
from tests.packagetools import MESH_PACKAGE_ROOT, mesh_package

pytestmark = pytest.mark.long


def test_a_running_check_shows_its_stage_and_fraction(make_client: Callable[..., TestClient]) -> None:
    client = make_client(workers=1)
    # seven joints: a shorter chain's sweeps, pruned within their contact ranges, can pass between two polls
    created = post_xml(client, long_chain(7), wait="false", cache="false")
    assert created.status_code == 202
    seen, done = watch_progress(client.get, created.json()["id"])
    assert_progress_of_a_run(seen)
    done = verified_check(client, done["id"])  # and the verification of its fixes, when it offers some
    assert done["status"] == "succeeded" and done["progress"] is None
    # the stored row keeps no stale progress either
    record = client.app.state.service.store.get(done["id"])  # type: ignore[attr-defined]
    assert record is not None and record.progress is None


def test_a_queued_check_has_no_progress_yet(make_client: Callable[..., TestClient]) -> None:
    client = make_client(workers=1)
    first = post_xml(client, long_chain(5), wait="false", cache="false").json()
    second = post_xml(client, long_chain(4), wait="false", cache="false").json()
    waiting = client.get(f"/v1/checks/{second['id']}").json()
    assert waiting["status"] == "queued" and waiting["progress"] is None
    assert client.delete(f"/v1/checks/{first['id']}").status_code in (200, 202, 204)
    assert client.delete(f"/v1/checks/{second['id']}").status_code in (200, 202, 204)
    assert client.get(f"/v1/checks/{first['id']}").json()["progress"] is None


class Recording:
    def __init__(self) -> None:
        self.writes: list[tuple[str, dict[str, Any], str | None]] = []

    def set_progress(self, check_id: str, stage: dict[str, Any], owner: str | None = None) -> bool:
        self.writes.append((check_id, stage, owner))
        return True


def test_the_writer_writes_the_newest_progress_at_most_twice_a_second() -> None:
    store = Recording()
    writer = ProgressWriter(store, "abc", owner="w1", min_interval_s=0.5)
    started = time.monotonic()
    for i in range(1000):
        writer.report({"stage": "matrix", "fraction": i / 1000})
    assert store.writes == [("abc", {"stage": "matrix", "fraction": 0.0}, "w1")]  # the first at once
    writer.flush()
    assert len(store.writes) == 1  # too soon
    time.sleep(max(0.0, 0.5 - (time.monotonic() - started)) + 0.05)
    writer.flush()
    assert store.writes[-1] == ("abc", {"stage": "matrix", "fraction": 0.999}, "w1")  # the newest, not a stale one
    writer.flush()
    assert len(store.writes) == 2  # nothing new to write


def test_the_report_comes_first_and_the_fixes_verification_after_as_its_own_phase(
    make_client: Callable[..., TestClient],
) -> None:
    """The POST answers with the report as soon as the check has it, offering the planned
    patches; the verification of the fixes follows as a state of its own (``fixes``), with
    its own stage list whose fraction never goes backwards, and ends with the verified report."""
    client = make_client(workers=1)
    created = post_zip(client, zip_bytes(mesh_package()), root=MESH_PACKAGE_ROOT)
    assert created.status_code == 201, created.text
    answered = created.json()
    assert answered["status"] == "succeeded" and answered["report"]["sections"]["fixes"]["verified"] is False
    assert answered["fixes"]["status"] in ("verifying", "verified")
    seen: list[dict[str, Any]] = []
    deadline = time.monotonic() + 300
    while True:
        check = client.get(f"/v1/checks/{answered['id']}").json()
        if check["fixes"]["status"] != "verifying":
            break
        if check["progress"] is not None and (not seen or seen[-1] != check["progress"]):
            seen.append(check["progress"])
        assert time.monotonic() < deadline
        time.sleep(0.05)
    assert check["fixes"] == {"status": "verified", "reason": None} and check["progress"] is None
    assert check["report"]["sections"]["fixes"]["verified"] is True
    assert check["report"]["diagnostics"] == answered["report"]["diagnostics"]  # the same findings
    for p in seen:  # while verifying: the fixes' own stages, never the check's
        assert p["phase"] == "fixes" and p["stages"] == 2
        assert p["stage"] in ("verifying safe fixes", "verifying all fixes")
    fractions = [p["fraction"] for p in seen]
    assert fractions == sorted(fractions)
    assert client.get(f"/v1/checks/{answered['id']}/fixes.patch").headers["geomcheck-fixes"] == "verified"


def test_a_verification_that_does_not_finish_leaves_the_report_and_says_why(
    make_client: Callable[..., TestClient],
) -> None:
    client = make_client(workers=1, check_timeout_s=20)
    client.app.state.service.target = report_then_hang  # type: ignore[attr-defined]
    created = post_zip(client, zip_bytes(mesh_package()), root=MESH_PACKAGE_ROOT)
    assert created.status_code == 201, created.text  # the report, before the verification hangs
    answered = created.json()
    assert answered["fixes"]["status"] == "verifying"
    deadline = time.monotonic() + 120
    while (check := client.get(f"/v1/checks/{answered['id']}").json())["fixes"]["status"] == "verifying":
        assert time.monotonic() < deadline
        time.sleep(0.2)
    assert check["status"] == "succeeded" and check["report"] == answered["report"]
    assert check["fixes"] == {
        "status": "failed",
        "reason": "the check exceeded the wall-clock limit of 20 s",
    }
    patch = client.get(f"/v1/checks/{answered['id']}/fixes.patch")
    assert patch.status_code == 200 and patch.headers["geomcheck-fixes"] == "failed"
    assert patch.text == answered["report"]["sections"]["fixes"]["safe_patch"]
