"""Storage of checks in SQLite and PostgreSQL, schema versions, and reports surviving a restart."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
import sqlalchemy as sa
from apitools import TWO_LINKS, drop_store, post_xml, unique_prefix
from fastapi.testclient import TestClient

from api.http.app import create_app
from api.settings import Settings
from api.store import SCHEMA_VERSION, StorageError, Store, normalise_url
from geomcheck.errors import UsageError


@pytest.fixture(params=["sqlite", pytest.param("postgresql", marks=pytest.mark.postgres)])
def database(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[tuple[str, str]]:
    """(URL, table prefix) of an empty database; PostgreSQL tables are dropped afterwards."""
    if request.param == "sqlite":
        yield f"sqlite:///{tmp_path / 'checks.db'}", ""
        return
    url = request.getfixturevalue("pg_url")
    prefix = unique_prefix()
    yield url, prefix
    drop_store(url, prefix)


@pytest.fixture
def store(database: tuple[str, str]) -> Iterator[Store]:
    s = Store(*database)
    s.create_schema()
    yield s
    s.dispose()


def test_a_check_goes_from_queued_to_succeeded(store: Store) -> None:
    store.create("abc", "robots/r.urdf", {"samples": 10})
    record = store.get("abc")
    assert record is not None
    assert (record.status, record.source, record.options, record.summary) == (
        "queued",
        "robots/r.urdf",
        {"samples": 10},
        None,
    )
    assert record.created.tzinfo is not None
    store.mark_running("abc")
    assert store.get("abc").status == "running"  # type: ignore[union-attr]
    store.finish_ok("abc", '{"schema": "x"}', "r", "fail", {"error": 2, "warning": 1, "info": 0}, False, 1.5)
    done = store.get("abc")
    assert done is not None
    assert (done.status, done.robot, done.verdict, done.summary, done.seconds) == (
        "succeeded",
        "r",
        "fail",
        {"error": 2, "warning": 1, "info": 0},
        1.5,
    )
    assert done.finished is not None and done.started is not None and done.finished >= done.started
    assert store.report("abc") == '{"schema": "x"}'
    assert store.get("nope") is None and store.report("nope") is None


def test_failures_and_interrupted_checks(store: Store) -> None:
    store.create("a", "r.urdf", {})
    store.create("b", "r.urdf", {})
    store.mark_running("b")
    store.create("c", "r.urdf", {})
    store.finish_failed("c", 422, "bad.urdf:1:2: GC101 malformed-xml: oops", 0.2)
    assert store.interrupt_unfinished("restarted") == 2
    records = {r.id: r for r in store.recent(10)[0]}
    assert {k: (r.status, r.http_status, r.reason) for k, r in records.items()} == {
        "a": ("failed", 503, "restarted"),
        "b": ("failed", 503, "restarted"),
        "c": ("failed", 422, "bad.urdf:1:2: GC101 malformed-xml: oops"),
    }


def test_recent_pages_with_a_cursor(store: Store) -> None:
    for i in range(5):
        store.create(f"id{i}", "r.urdf", {})
    store.finish_failed("id3", 422, "x")
    seen, cursor = [], None
    while True:
        page, cursor = store.recent(2, cursor)
        seen.append([r.id for r in page])
        if cursor is None:
            break
    assert seen == [["id4", "id3"], ["id2", "id1"], ["id0"]]
    assert [r.id for r in store.recent(10, status="failed")[0]] == ["id3"]


def test_schema_version_is_recorded_and_a_newer_database_refused(store: Store) -> None:
    assert store.schema_version() == SCHEMA_VERSION
    assert store.create_schema() == SCHEMA_VERSION  # idempotent: found the current version
    with store.engine.begin() as conn:
        conn.execute(store.version_table.insert().values(version=SCHEMA_VERSION + 1, applied_at=sa.func.now()))
    with pytest.raises(StorageError, match=f"schema version {SCHEMA_VERSION + 1}, newer than this service"):
        store.create_schema()


def test_the_cache_lookup_walks_an_index_newest_first(tmp_path: Path) -> None:
    """Every cache hit adds a row with its key: the lookup must not read them all (SQLite's plan)."""
    store = Store(f"sqlite:///{tmp_path / 'checks.db'}", "")
    store.create_schema()
    for key in ("request_key", "result_key"):
        for finished in (True, False):
            query = store._origin_query(key, finished).params(key="k", client="alice")
            sql = query.compile(store.engine, compile_kwargs={"literal_binds": True})
            with store.engine.connect() as conn:
                plan = " | ".join(row[-1] for row in conn.exec_driver_sql(f"EXPLAIN QUERY PLAN {sql}").all())
            assert f"USING INDEX ix_checks_{key}_seq ({key}=?)" in plan, plan
            assert "TEMP B-TREE" not in plan, plan  # no sort of the key's rows
    store.dispose()


def test_unreachable_database_is_a_one_line_error(tmp_path: Path) -> None:
    store = Store("postgresql://nobody:secret@127.0.0.1:1/none?connect_timeout=1")
    with pytest.raises(StorageError) as err:
        store.create_schema()
    message = str(err.value)
    assert message.startswith("cannot open database postgresql+psycopg://nobody:***@127.0.0.1:1/none")
    assert "secret" not in message and "\n" not in message


def test_urls_use_psycopg_3() -> None:
    assert normalise_url("postgresql://u@h/db") == "postgresql+psycopg://u@h/db"
    assert normalise_url("postgres://u@h/db") == "postgresql+psycopg://u@h/db"
    assert normalise_url("sqlite:///x.db") == "sqlite:///x.db"


def test_reports_survive_a_restart(database: tuple[str, str], tmp_path: Path) -> None:
    url, prefix = database
    settings = Settings(data_dir=tmp_path / "data", database_url=url, table_prefix=prefix)
    with TestClient(create_app(settings)) as first:
        created = post_xml(first, TWO_LINKS, root="two_links.urdf").json()
        report_json = first.get(f"/v1/checks/{created['id']}/report.json").text
        queued = post_xml(first, TWO_LINKS, wait="false").json()["id"]
    with TestClient(create_app(settings)) as second:
        again = second.get(f"/v1/checks/{created['id']}")
        assert again.status_code == 200 and again.json() == created
        assert second.get(f"/v1/checks/{created['id']}/report.json").text == report_json
        assert second.get(f"/v1/checks/{created['id']}/report.html").status_code == 200
        left = second.get(f"/v1/checks/{queued}").json()
        assert left["status"] in ("succeeded", "failed")  # finished, or recorded as interrupted by the restart
        if left["status"] == "failed":
            assert left["http_status"] == 503
            assert left["reason"] in (  # depending on how far it got when the service stopped
                "the service is stopping",
                "the service stopped while the check ran",
                "the service restarted before this check finished; submit it again",
            )


def test_the_default_database_is_a_sqlite_file_in_the_data_folder(make_client: Callable[..., TestClient]) -> None:
    client = make_client()
    settings = client.app.state.settings  # type: ignore[attr-defined]
    assert settings.database == f"sqlite:///{(settings.data_dir / 'geomcheck.db').resolve()}"
    post_xml(client, TWO_LINKS)
    assert (settings.data_dir / "geomcheck.db").is_file()


def test_one_service_per_data_folder(make_settings: Callable[..., Settings]) -> None:
    settings = make_settings()
    busy = pytest.raises(UsageError, match="another geomcheck service is using the data folder")
    with TestClient(create_app(settings)), busy:
        TestClient(create_app(settings)).__enter__()
    with TestClient(create_app(settings)) as again:  # released on shutdown
        assert again.get("/healthz").status_code == 200
