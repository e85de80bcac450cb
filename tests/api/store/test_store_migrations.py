"""Alembic migrations of the store: a database of every earlier schema version, as the service
of that version left it (before Alembic: the store's revisions up to that version, without
Alembic's record), is brought to the current schema with its data, on SQLite and PostgreSQL;
so is one that Alembic left at an earlier revision."""

from __future__ import annotations

import datetime as dt
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import sqlalchemy as sa
from alembic import command
from apitools import database_at_version, drop_store, unique_prefix

from api.store import SCHEMA_VERSION, CacheKeys, StorageError, Store
from api.store.migrate import alembic_config, revision_of

NOW = dt.datetime(2026, 1, 2, 3, 4, 5, tzinfo=dt.UTC)


def write_legacy_database(url: str, prefix: str, version: int) -> None:
    """A database of schema ``version`` holding one succeeded check (with its report, an upload
    and cache keys where that version had them), as its service wrote it."""
    tables = database_at_version(url, prefix, version)
    engine = sa.create_engine(url)
    row: dict[str, Any] = {
        "id": "old",
        "status": "succeeded",
        "created_at": NOW,
        "finished_at": NOW,
        "source": "r.urdf",
        "robot": "r",
        "verdict": "pass",
        "errors": 0,
        "warnings": 1,
        "infos": 2,
        "has_matrix": False,
        "options": "{}",
        "seconds": 1.5,
    }
    report = json.dumps({"fail_on": "error", "version": version})
    with engine.begin() as conn:
        if version < 4:
            row["report"] = report
        if version >= 2:
            conn.execute(tables["blobs"].insert().values(digest="d" * 64, size=3, created_at=NOW, data=b"abc"))
            row["upload"] = "d" * 64
        if version >= 3:
            row.update(request_key="req", result_key="res", fail_on="error", default_fail_on="error")
        if version >= 5:
            row["client"] = "alice"
        conn.execute(tables["checks"].insert().values(**row))
        if version >= 4:
            conn.execute(tables["reports"].insert().values(check_id="old", report=report))
    engine.dispose()


def shape(store: Store) -> dict[str, Any]:
    """Tables, columns and indexes (name -> columns) of the store's tables."""
    inspector = sa.inspect(store.engine)
    names = sorted(n for n in inspector.get_table_names() if n.startswith(store.prefix))
    return {
        name.removeprefix(store.prefix): (
            sorted(c["name"] for c in inspector.get_columns(name)),
            sorted(
                (i["name"].replace(store.prefix, "", 1), tuple(i["column_names"])) for i in inspector.get_indexes(name)
            ),
        )
        for name in names
    }


@pytest.fixture(params=["sqlite", pytest.param("postgresql", marks=pytest.mark.postgres)])
def database(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[tuple[str, str]]:
    """(URL, table prefix) of an empty database; a unique prefix on PostgreSQL, dropped afterwards."""
    if request.param == "sqlite":
        yield f"sqlite:///{tmp_path / 'checks.db'}", "gc_"
        return
    url, prefix = request.getfixturevalue("pg_url"), unique_prefix()
    yield url, prefix
    drop_store(url, prefix)


@pytest.fixture
def fresh_shape(database: tuple[str, str]) -> Iterator[dict[str, Any]]:
    """The schema an empty database of the same kind gets (every revision run), to compare
    migrated ones with; its tables are dropped afterwards."""
    url, prefix = database
    store = Store(url, f"fresh{prefix}")
    try:
        assert store.create_schema() == 0
        yield shape(store)
    finally:
        store.drop_schema()
        store.dispose()


@pytest.mark.parametrize("version", range(1, SCHEMA_VERSION))
def test_a_database_of_every_earlier_version_is_migrated_with_its_data(
    database: tuple[str, str], version: int, fresh_shape: dict[str, Any]
) -> None:
    url, prefix = database
    write_legacy_database(url, prefix, version)
    store = Store(url, prefix)
    try:
        assert store.create_schema() == version
        assert store.schema_version() == SCHEMA_VERSION
        with store.engine.connect() as conn:
            revision = conn.execute(sa.text(f"SELECT version_num FROM {prefix}alembic_version")).scalar_one()
        assert revision == revision_of(SCHEMA_VERSION)
        assert shape(store) == fresh_shape  # the same tables, columns and indexes as a database made today
        old = store.get("old")
        assert old is not None
        assert (old.status, old.robot, old.summary, old.seconds) == (
            "succeeded",
            "r",
            {"error": 0, "warning": 1, "info": 2},
            1.5,
        )
        assert old.client == ("alice" if version >= 5 else None) and old.progress is None
        assert json.loads(store.report("old") or "{}") == {"fail_on": "error", "version": version}
        if version >= 2:
            assert store.get_blob("d" * 64) == b"abc"
        if version >= 3:  # its keys answer an identical request from the cache
            shared = store.share("again", "r.urdf", {}, CacheKeys(request_key="req"), None, lambda t, f: (t, "pass"))
            assert shared is not None and shared.holder == "old"
        # and the migrated database works as a new one: a check run under a lease, with progress
        store.create("new", "r.urdf", {}, upload="e" * 64, spec={})
        claim = store.claim("new", "w", lease_s=60, max_attempts=3)
        assert claim is not None and claim.attempt == 1
        assert store.set_progress("new", {"stage": "fit", "fraction": 0.5}, owner="w")
        assert store.get("new").progress == {"stage": "fit", "fraction": 0.5}  # type: ignore[union-attr]
        assert store.finish_ok("new", '{"fail_on": "error"}', "r", "pass", {}, False, 1.0, owner="w", fixes="verifying")
        assert store.renew("new", "w", lease_s=60)  # the lease is kept while the fixes are verified
        assert store.finish_fixes("new", "verified", '{"fail_on": "error", "fixes": 1}', owner="w")
        assert (store.get("new").fixes, json.loads(store.report("new") or "{}")) == (  # type: ignore[union-attr]
            "verified",
            {"fail_on": "error", "fixes": 1},
        )
        assert old.fixes is None and old.root is None
        assert store.create_schema() == SCHEMA_VERSION  # again: nothing to do
    finally:
        store.dispose()


@pytest.mark.parametrize("revision", [revision_of(v) for v in range(1, SCHEMA_VERSION)])
def test_a_database_alembic_left_at_an_earlier_revision_is_upgraded(database: tuple[str, str], revision: str) -> None:
    url, prefix = database
    store = Store(url, prefix)
    try:
        with store.engine.begin() as conn:
            command.upgrade(alembic_config(conn, prefix), revision)
        assert store.schema_version() == int(revision)
        assert store.create_schema() == int(revision)
        assert store.schema_version() == SCHEMA_VERSION
        store.create("c", "r.urdf", {}, client="bob")
        assert store.recent(5, client="bob")[0][0].id == "c"
    finally:
        store.dispose()


def test_a_database_newer_than_the_service_is_refused(database: tuple[str, str]) -> None:
    url, prefix = database
    store = Store(url, prefix)
    try:
        store.create_schema()
        with store.engine.begin() as conn:
            conn.execute(store.version_table.insert().values(version=SCHEMA_VERSION + 1, applied_at=NOW))
        with pytest.raises(StorageError, match=f"schema version {SCHEMA_VERSION + 1}, newer than this service"):
            store.create_schema()
    finally:
        store.dispose()
