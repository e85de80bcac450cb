"""The embedded service's check lifecycle: DELETE cancels, /readyz, /metrics, retention."""

from __future__ import annotations

import datetime as dt
import threading
import time
from collections.abc import Callable

from apitools import TWO_LINKS, drop_store, post_xml, sleep_long
from fastapi.testclient import TestClient

from api.checks.service import delete_old_checks
from api.store import utcnow


def test_delete_kills_a_running_check(make_client: Callable[..., TestClient]) -> None:
    client = make_client(workers=1)
    service = client.app.state.service  # type: ignore[attr-defined]
    service.target = sleep_long
    check_id = post_xml(client, TWO_LINKS, wait="false").json()["id"]
    # queued behind it (one worker); cache=false: an identical submission would share its run
    waiting = post_xml(client, TWO_LINKS, wait="false", cache="false").json()["id"]
    deadline = time.monotonic() + 30
    while client.get(f"/v1/checks/{check_id}").json()["status"] != "running" or service.running != 1:
        assert time.monotonic() < deadline
        time.sleep(0.05)
    started = time.monotonic()
    answer = client.delete(f"/v1/checks/{check_id}")
    assert answer.status_code == 200
    assert (answer.json()["status"], answer.json()["http_status"]) == ("cancelled", 409)
    assert client.delete(f"/v1/checks/{waiting}").json()["status"] == "cancelled"
    while service.pending:  # the sleeping process is killed, the queued one never starts
        assert time.monotonic() - started < 10
        time.sleep(0.05)
    assert service.running == 0
    for cancelled in (check_id, waiting):
        record = client.get(f"/v1/checks/{cancelled}").json()
        assert (record["status"], record["reason"]) == ("cancelled", "cancelled by a DELETE request")
    assert client.delete(f"/v1/checks/{check_id}").status_code == 409


def test_a_waiting_post_whose_check_is_cancelled_answers_409(make_client: Callable[..., TestClient]) -> None:
    client = make_client(workers=1)
    client.app.state.service.target = sleep_long  # type: ignore[attr-defined]
    answers: list[object] = []
    poster = threading.Thread(target=lambda: answers.append(post_xml(client, TWO_LINKS)))
    poster.start()
    deadline = time.monotonic() + 30
    while not (running := client.get("/v1/checks", params={"status": "running"}).json()["items"]):
        assert time.monotonic() < deadline
        time.sleep(0.05)
    client.delete(f"/v1/checks/{running[0]['id']}")
    poster.join(timeout=30)
    response = answers[0]
    assert response.status_code == 409  # type: ignore[attr-defined]
    assert response.json() == {"detail": "cancelled by a DELETE request"}  # type: ignore[attr-defined]


def test_readyz_and_metrics(client: TestClient) -> None:
    assert client.get("/readyz").json() == {"ready": True, "database": "ok", "broker": "not used"}
    assert post_xml(client, TWO_LINKS).status_code == 201
    metrics = client.get("/metrics")
    assert metrics.status_code == 200 and metrics.headers["content-type"].startswith("text/plain")
    lines = metrics.text.splitlines()
    assert 'geomcheck_checks{status="succeeded"} 1.0' in lines
    assert 'geomcheck_checks{status="queued"} 0.0' in lines
    assert "geomcheck_queue_depth 0.0" in lines
    assert "geomcheck_distributed 0.0" in lines
    assert "geomcheck_check_duration_seconds_count 1.0" in lines
    assert 'geomcheck_check_duration_seconds_bucket{le="+Inf"} 1.0' in lines


def test_retention_deletes_old_finished_checks(make_client: Callable[..., TestClient]) -> None:
    client = make_client(retention_days=7)
    service = client.app.state.service  # type: ignore[attr-defined]
    old = post_xml(client, TWO_LINKS).json()["id"]
    new = post_xml(client, TWO_LINKS, cache="false").json()["id"]
    with service.store.engine.begin() as conn:
        checks = service.store.checks
        conn.execute(checks.update().where(checks.c.id == old).values(created_at=utcnow() - dt.timedelta(days=8)))
    assert delete_old_checks(service.settings, service.store) == (1, 0)
    assert client.get(f"/v1/checks/{old}").status_code == 404
    assert client.get(f"/v1/checks/{new}").json()["status"] == "succeeded"


def test_a_database_outage_is_503_not_500(make_client: Callable[..., TestClient], pg_url: str) -> None:
    import sqlalchemy as sa
    from apitools import unique_prefix

    prefix = unique_prefix()
    client = make_client(database_url=pg_url, table_prefix=prefix)
    check_id = post_xml(client, TWO_LINKS).json()["id"]
    store = client.app.state.service.store  # type: ignore[attr-defined]
    working = store.engine
    # PostgreSQL goes away: nothing listens where the service's connections go
    store.engine = sa.create_engine("postgresql+psycopg://nobody@127.0.0.1:1/gone?connect_timeout=1")
    try:
        for path in ("/v1/checks", f"/v1/checks/{check_id}", f"/v1/checks/{check_id}/report.json"):
            answer = client.get(path)
            assert answer.status_code == 503, path
            assert answer.json() == {"detail": "the database does not answer; retry later"}
            assert answer.headers["retry-after"] == "5"
        assert post_xml(client, TWO_LINKS, cache="false").status_code == 503
    finally:
        store.engine.dispose()
        store.engine = working
    assert client.get(f"/v1/checks/{check_id}").status_code == 200  # back once it answers again
    drop_store(pg_url, prefix)
