"""Checks belong to the client whose token submitted them: another client gets 404 for every
read, download and cancel, lists only its own checks, and may reuse a result computed for
another client without learning that check's id; an admin token sees everything."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from apitools import TWO_LINKS, check_slowly, drop_store, unique_prefix
from fastapi.testclient import TestClient

from api.settings import Settings, parse_tokens

TOKENS = "alice=a-token,bob=b-token,ops=o-token:admin"
ALICE = {"Authorization": "Bearer a-token"}
BOB = {"Authorization": "Bearer b-token"}
ADMIN = {"Authorization": "Bearer o-token"}
READS = ("", "/report.json", "/report.html", "/report.sarif", "/report.junit.xml", "/collision-matrix.srdf")


@pytest.fixture(params=["sqlite", pytest.param("postgresql", marks=pytest.mark.postgres)])
def settings(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[Settings]:
    if request.param == "sqlite":
        yield Settings(data_dir=tmp_path / "data", api_tokens=TOKENS)
        return
    url, prefix = request.getfixturevalue("pg_url"), unique_prefix()
    yield Settings(data_dir=tmp_path / "data", api_tokens=TOKENS, database_url=url, table_prefix=prefix)
    drop_store(url, prefix)


def post(client: TestClient, headers: dict[str, str], **params: Any) -> Any:
    return client.post(
        "/v1/checks", content=TWO_LINKS, headers={"content-type": "application/xml", **headers}, params=params
    )


def ids(client: TestClient, headers: dict[str, str]) -> list[str]:
    return [item["id"] for item in client.get("/v1/checks", headers=headers).json()["items"]]


def test_another_clients_check_is_404_everywhere(settings: Settings, make_client: Callable[..., TestClient]) -> None:
    client = make_client(settings)
    mine = post(client, ALICE, matrix="true", samples=20)
    assert mine.status_code == 201
    check_id = mine.json()["id"]
    for suffix in (*READS, "/fixes.patch"):
        assert client.get(f"/v1/checks/{check_id}{suffix}", headers=ALICE).status_code == 200, suffix
        theirs = client.get(f"/v1/checks/{check_id}{suffix}", headers=BOB)
        assert (theirs.status_code, theirs.json()) == (404, {"detail": f"no check with id {check_id!r}"}), suffix
        assert client.get(f"/v1/checks/{check_id}{suffix}", headers=ADMIN).status_code == 200, suffix
    assert client.delete(f"/v1/checks/{check_id}", headers=BOB).status_code == 404
    assert client.get(f"/v1/checks/{check_id}", headers=ALICE).json()["status"] == "succeeded"
    assert ids(client, ALICE) == [check_id]
    assert ids(client, BOB) == []
    assert ids(client, ADMIN) == [check_id]
    assert client.get("/v1/checks", headers=BOB, params={"status": "succeeded"}).json()["items"] == []


def test_a_shared_result_does_not_name_the_other_clients_check(
    settings: Settings, make_client: Callable[..., TestClient], monkeypatch: pytest.MonkeyPatch
) -> None:
    client = make_client(settings)
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1000000000")  # the reports' times
    first = post(client, ALICE).json()
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    again = post(client, BOB)
    assert again.status_code == 201
    body = again.json()
    assert (body["cached"], body["cached_from"]) == (True, None)  # reused, but not named
    # nor timed: the report is the same but for the time, this check's (was: alice's check's)
    assert (first["report"]["created"], body["report"]["created"]) == ("2001-09-09T01:46:40Z", "2023-11-14T22:13:20Z")
    assert {**body["report"], "created": ""} == {**first["report"], "created": ""}
    download = client.get(f"/v1/checks/{body['id']}/report.json", headers=BOB).json()
    assert download["created"] == "2023-11-14T22:13:20Z"
    assert client.get(f"/v1/checks/{body['id']}", headers=BOB).json()["cached_from"] is None
    assert client.get(f"/v1/checks/{body['id']}", headers=ADMIN).json()["cached_from"] == first["id"]
    assert ids(client, BOB) == [body["id"]]
    assert client.get(f"/v1/checks/{first['id']}", headers=BOB).status_code == 404
    own = post(client, ALICE).json()  # the same client sees where its answer came from
    assert own["cached_from"] == first["id"]
    assert own["report"] == first["report"]  # and its own check's report as it is


def test_cancelling_a_check_never_fails_another_clients_identical_check(
    settings: Settings, make_client: Callable[..., TestClient]
) -> None:
    client = make_client(settings)
    client.app.state.service.target = check_slowly  # type: ignore[attr-defined]
    alices = post(client, ALICE, wait="false").json()
    bobs = post(client, BOB, wait="false").json()
    assert bobs["cached_from"] is None  # not following alice's run: it has a run of its own
    assert client.delete(f"/v1/checks/{alices['id']}", headers=ALICE).json()["status"] == "cancelled"
    deadline = time.monotonic() + 60
    status = ""
    while time.monotonic() < deadline:
        status = client.get(f"/v1/checks/{bobs['id']}", headers=BOB).json()["status"]
        if status not in ("queued", "running"):
            break
        time.sleep(0.2)
    assert status == "succeeded"


def test_token_list_names_clients_and_admins() -> None:
    alice, _bob, ops = parse_tokens(TOKENS)
    assert (alice.name, alice.token, alice.admin) == ("alice", "a-token", False)
    assert (ops.name, ops.admin) == ("ops", True)
    (bare,) = parse_tokens("s3cret")  # the format before names: a client of its own
    assert bare.name.startswith("token-") and bare.token == "s3cret"
    for bad in ("alice=x,alice=y", "a=x,b=x", "a b=x", "a="):
        with pytest.raises(ValueError, match="api_tokens"):
            parse_tokens(bad)
