"""The database under a store: its engine, tables, write transactions and schema.

A :class:`Database` opens SQLite or PostgreSQL (SQLAlchemy 2 Core; ``postgresql://`` URLs use
psycopg 3), creates or migrates its tables on :meth:`Database.create_schema`, and gives the
other parts of the store (:mod:`api.store.checks`, :mod:`api.store.leases`,
:mod:`api.store.sharing`, :mod:`api.store.metrics`, :mod:`api.store.blobs`) their write
transactions and the statements they share.
"""

from __future__ import annotations

import contextlib
import hashlib
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import sqlalchemy as sa
from sqlalchemy.engine import Connection, Engine

from api.store.migrate import found_version, upgrade
from api.store.schema import StorageError, describe, normalise_url, tables

SQLITE_POOL_SIZE = 40  # connections kept open to a SQLite database [count]


class Database:
    """Tables named ``<prefix>checks`` etc. in the database at ``url`` (SQLAlchemy URL)."""

    def __init__(self, url: str, prefix: str = "") -> None:
        self.url = normalise_url(url)
        self.prefix = prefix
        self.metadata, self.checks, self.version_table, self.blobs, self.reports = tables(prefix)
        self.origin = self.checks.alias("origin")  # the check a cached one shares its report with
        self._origin_queries: dict[tuple[str, bool], Any] = {}
        # statements of the hot paths (every POST answered from the cache), built once
        c = self.checks.c
        self._record_by_id = self._with_origin_client(sa.select(*self._columns())).where(
            c.id == sa.bindparam("check_id")
        )
        own = self.reports.c
        self._holder_by_id = (
            sa.select(sa.case((own.check_id.is_not(None), c.id), else_=c.cached_from))
            .select_from(self.checks.outerjoin(self.reports, own.check_id == c.id))
            .where(c.id == sa.bindparam("check_id"))
        )
        self.engine = self._make_engine(self.url)
        # SQLite lets one writer in at a time and makes the others sleep in growing steps (up to
        # 100 ms); the threads of this process queue on a lock instead. One process writes a
        # SQLite database (the service locks its data folder), so this is all the contention.
        self._write_lock = threading.Lock() if self.engine.dialect.name == "sqlite" else None

    @contextlib.contextmanager
    def _begin(self) -> Iterator[Connection]:
        """A write transaction (behind the process's write lock on SQLite)."""
        with self._write_lock or contextlib.nullcontext(), self.engine.begin() as conn:
            yield conn

    @staticmethod
    def _make_engine(url: str) -> Engine:
        parsed = sa.make_url(url)
        if parsed.get_backend_name() == "sqlite":
            if parsed.database and parsed.database != ":memory:":
                Path(parsed.database).parent.mkdir(parents=True, exist_ok=True)
            # a connection per request thread (anyio's pool has 40): opening one costs more than the query
            engine = sa.create_engine(
                url,
                connect_args={"check_same_thread": False, "timeout": 30},
                pool_size=SQLITE_POOL_SIZE,
                max_overflow=10,
            )

            @sa.event.listens_for(engine, "connect")
            def _pragmas(dbapi_connection: Any, _record: Any) -> None:
                cursor = dbapi_connection.cursor()
                cursor.execute("PRAGMA journal_mode=WAL")
                cursor.execute("PRAGMA synchronous=NORMAL")
                cursor.close()

            return engine
        return sa.create_engine(url, pool_pre_ping=True, pool_size=5, max_overflow=10)

    @property
    def display_url(self) -> str:
        """The URL with any password hidden."""
        return sa.make_url(self.url).render_as_string(hide_password=True)

    def create_schema(self) -> int:
        """Create or migrate the tables to :data:`SCHEMA_VERSION` (:mod:`api.store.migrate`);
        returns the version found before (0: an empty database).

        One transaction; on PostgreSQL under an advisory lock named after the table prefix,
        so replicas starting at once on an empty database create and migrate it once.
        """
        try:
            with self._begin() as conn:
                self._lock_name(conn, f"geomcheck:{self.prefix}")
                return upgrade(conn, self.prefix, self.display_url)
        except sa.exc.SQLAlchemyError as err:
            raise StorageError(f"cannot open database {self.display_url}: {describe(err)}") from None

    def schema_version(self) -> int:
        with self.engine.connect() as conn:
            return found_version(conn, self.prefix)

    def drop_schema(self) -> None:
        """Drop this store's tables, Alembic's version table with them (tests clean up with it)."""
        self.metadata.drop_all(self.engine)
        alembic_version = self.engine.dialect.identifier_preparer.quote(f"{self.prefix}alembic_version")
        with self.engine.begin() as conn:
            conn.execute(sa.text(f"DROP TABLE IF EXISTS {alembic_version}"))

    def ping(self) -> bool:
        try:
            with self.engine.connect() as conn:
                conn.execute(sa.text("SELECT 1"))
            return True
        except sa.exc.SQLAlchemyError:
            return False

    def dispose(self) -> None:
        self.engine.dispose()

    @staticmethod
    def _lock_name(conn: Connection, name: str) -> None:
        """On PostgreSQL, hold an advisory lock named ``name`` until the transaction ends, so
        replicas doing the same thing at once take turns (SQLite has one writing process)."""
        if conn.dialect.name == "postgresql":
            key = int.from_bytes(hashlib.sha256(name.encode()).digest()[:8], "big", signed=True)
            conn.execute(sa.text("SELECT pg_advisory_xact_lock(:key)"), {"key": key})

    def _columns(self) -> list[sa.Column[Any]]:
        return [c for c in self.checks.c if c.name != "spec"]

    def _with_origin_client(self, query: Any) -> Any:
        """``query`` over the checks with the client of each one's origin (``origin_client``)."""
        origin = self.checks.alias("record_origin")
        columns = (
            origin.c.client.label("origin_client"),
            origin.c.progress.label("origin_progress"),
            origin.c.fixes.label("origin_fixes"),
            origin.c.fixes_reason.label("origin_fixes_reason"),
        )
        return query.add_columns(*columns).select_from(
            self.checks.outerjoin(origin, origin.c.id == self.checks.c.cached_from)
        )
