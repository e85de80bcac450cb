"""The service's result cache: identical submissions answered from the stored report."""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from typing import Any

from apitools import TWO_LINKS, check_slowly, post_xml, post_zip, verified_check, zip_bytes
from fastapi.testclient import TestClient

from api.results.cache import rerender
from tests.packagetools import MESH_PACKAGE_ROOT, mesh_package

WARN_ONLY = TWO_LINKS.replace(b'<axis xyz="0 0 1"/>', b'<axis xyz="0 0 2"/>')  # GC120, a warning


def without_ids(body: dict[str, Any]) -> dict[str, Any]:
    """The report of a POST answer, without the time it was made."""
    report = dict(body["report"])
    report.pop("created")
    return report


def test_an_identical_post_is_answered_from_the_stored_report(client: TestClient) -> None:
    first = post_xml(client, TWO_LINKS)
    second = post_xml(client, TWO_LINKS)
    assert (first.status_code, second.status_code) == (201, 201)
    a, b = first.json(), second.json()
    assert (a["cached"], a["cached_from"]) == (False, None)
    assert (b["cached"], b["cached_from"], b["status"]) == (True, a["id"], "succeeded")
    assert b["id"] != a["id"] and b["report"] == a["report"]  # the same report, timestamp included
    assert (b["verdict"], b["summary"]) == (a["verdict"], a["summary"])
    assert second.headers["location"] == f"/v1/checks/{b['id']}"
    stored = client.get(f"/v1/checks/{b['id']}/report.json")
    assert stored.status_code == 200 and json.loads(stored.text) == a["report"]
    assert client.get(f"/v1/checks/{b['id']}").json()["cached_from"] == a["id"]


def test_cache_false_runs_again(client: TestClient) -> None:
    first = post_xml(client, TWO_LINKS).json()
    fresh = post_xml(client, TWO_LINKS, cache="false").json()
    assert (fresh["cached"], fresh["cached_from"]) == (False, None)
    assert without_ids(fresh) == without_ids(first)
    form = client.post("/v1/checks", files={"description": ("robot.urdf", TWO_LINKS)}, data={"cache": "false"}).json()
    assert form["cached"] is False
    again = client.post("/v1/checks", files={"description": ("robot.urdf", TWO_LINKS)}).json()
    assert again["cached"] is True and again["cached_from"] in (first["id"], fresh["id"], form["id"])


def test_fail_on_is_applied_after_the_lookup(client: TestClient) -> None:
    first = post_xml(client, WARN_ONLY).json()
    verified_check(client, first["id"])  # a report is re-rendered once its fixes are verified
    assert (first["report"]["fail_on"], first["verdict"]) == ("error", "pass")
    assert [(d["code"], d["severity"]) for d in first["report"]["diagnostics"]] == [("GC120", "warning")]
    strict = post_xml(client, WARN_ONLY, fail_on="warning").json()
    assert (strict["cached"], strict["cached_from"]) == (True, first["id"])
    assert (strict["report"]["fail_on"], strict["report"]["verdict"], strict["verdict"]) == ("warning", "fail", "fail")
    uncached = verified_check(client, post_xml(client, WARN_ONLY, fail_on="warning", cache="false").json()["id"])
    assert without_ids(strict) == without_ids(uncached)
    # the stored report of the first check is untouched
    assert json.loads(client.get(f"/v1/checks/{first['id']}/report.json").text)["fail_on"] == "error"


def test_the_same_files_in_another_body_find_the_report(client: TestClient) -> None:
    package = mesh_package()
    archive = zip_bytes(package)
    first = post_zip(client, archive, root=MESH_PACKAGE_ROOT)
    assert first.status_code == 201, first.text
    files = [("files", (name, data)) for name, data in sorted(package.items())]
    form = client.post("/v1/checks", files=files, data={"root": MESH_PACKAGE_ROOT})
    assert form.status_code == 201, form.text
    assert (form.json()["cached"], form.json()["cached_from"]) == (True, first.json()["id"])
    # a changed option is another result
    other = post_zip(client, archive, root=MESH_PACKAGE_ROOT, samples="50", matrix="true")
    assert other.json()["cached"] is False


def test_an_identical_post_in_flight_shares_the_run(make_client: Callable[..., TestClient]) -> None:
    client = make_client(workers=1)
    client.app.state.service.target = check_slowly  # type: ignore[attr-defined]
    origin = post_xml(client, TWO_LINKS, wait="false").json()
    follower = post_xml(client, TWO_LINKS, wait="false")
    assert follower.status_code == 202
    body = follower.json()
    assert (body["status"], body["cached"], body["cached_from"]) == ("queued", True, origin["id"])
    waiting = post_xml(client, TWO_LINKS)  # waits for the shared run
    assert waiting.status_code == 201 and waiting.json()["cached_from"] == origin["id"]
    assert client.app.state.service.pending == 0  # type: ignore[attr-defined]
    done = client.get(f"/v1/checks/{body['id']}").json()
    assert (done["status"], done["verdict"]) == ("succeeded", "pass")
    assert done["report"] == client.get(f"/v1/checks/{origin['id']}").json()["report"] == waiting.json()["report"]


def test_a_follower_of_a_cancelled_check_fails_and_asks_to_submit_again(
    make_client: Callable[..., TestClient],
) -> None:
    client = make_client(workers=1)
    client.app.state.service.target = check_slowly  # type: ignore[attr-defined]
    origin = post_xml(client, TWO_LINKS, wait="false").json()
    follower = post_xml(client, TWO_LINKS, wait="false").json()
    assert client.delete(f"/v1/checks/{origin['id']}").json()["status"] == "cancelled"
    record = client.get(f"/v1/checks/{follower['id']}").json()
    assert (record["status"], record["http_status"]) == ("failed", 503)
    assert record["reason"] == (f"the identical check {origin['id']} this one shared was cancelled; submit it again")
    deadline = time.monotonic() + 30
    while client.app.state.service.pending:  # type: ignore[attr-defined]
        assert time.monotonic() < deadline
        time.sleep(0.05)
    again = post_xml(client, TWO_LINKS)  # nothing to share: it runs
    assert again.status_code == 201 and again.json()["cached"] is False


def test_failed_checks_are_not_shared(client: TestClient) -> None:
    broken = b"<robot name='x'><link name='a'></robot>"
    first = post_xml(client, broken)
    second = post_xml(client, broken)
    assert (first.status_code, second.status_code) == (422, 422)
    items = client.get("/v1/checks").json()["items"]
    assert [i["cached"] for i in items] == [False, False]


def test_rerender_changes_only_fail_on_and_verdict(client: TestClient) -> None:
    text = client.get(f"/v1/checks/{post_xml(client, WARN_ONLY).json()['id']}/report.json").text
    again, verdict = rerender(text, "error")
    assert again == text and verdict == "pass"
    strict, verdict = rerender(text, "warning")
    assert verdict == "fail"
    a, b = json.loads(text), json.loads(strict)
    assert {k for k in a if a[k] != b[k]} == {"fail_on", "verdict"}


def test_check_processes_share_stage_caches_when_configured(
    make_client: Callable[..., TestClient], tmp_path: Any
) -> None:
    stages = tmp_path / "stages"
    client = make_client(stage_cache_dir=stages)
    archive = zip_bytes(mesh_package())
    first = post_zip(client, archive, root=MESH_PACKAGE_ROOT)
    assert first.status_code == 201, first.text
    assert first.json()["report"]["robot"]["meshes_loaded"] == 2
    stored = {p.parent.parent.name for p in stages.rglob("*") if p.is_file() and p.parent.parent != stages}
    assert {"mesh-load", "mesh-solid", "sweep-pair"} <= stored

    def analyses() -> list[Any]:
        # xacro expansions are keyed by the files' absolute paths: each check's folder is new
        return sorted(p for p in stages.rglob("*") if p.is_file() and not p.parent.parent.name.startswith("xacro"))

    verified_check(client, first.json()["id"])  # its fixes' verification reads and fills the caches too
    entries = analyses()
    again = post_zip(client, archive, root=MESH_PACKAGE_ROOT, cache="false")  # run again, from the stage caches
    verified_check(client, again.json()["id"])
    assert again.json()["cached"] is False
    assert without_ids(again.json()) == without_ids(first.json())
    assert analyses() == entries  # every mesh analysis and pair sweep read, none computed again
