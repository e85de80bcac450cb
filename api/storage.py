"""Persistence of checks and their reports: SQLAlchemy 2 Core over SQLite or PostgreSQL.

One table of checks (status, figures), one of their JSON reports as the CLI writes them
(``reports``, kept apart so the checks' rows stay small), a table of uploads stored by
content (``blobs``, read by the workers of the distributed mode) and a ``schema_version``
table: the schema is created on start, and a database written by an older service is
brought up to date by the functions in ``MIGRATIONS`` (version n-1 -> n). On PostgreSQL
both happen under an advisory lock, so replicas starting at once on an empty database do
not race. Table names carry an optional prefix so several services (or test runs) can
share a database.

Every result write is guarded by the check's current status (and, in the distributed mode,
by the lease owner), so a late finisher never overwrites a cancelled or re-run check. The
report is read only through :meth:`Store.report`: a check answered from the result cache
(``cached_from``) has no report of its own, or one that differs from its origin's only in
``fail_on``, and reads its origin's through one join. Checks that share an identical check
still in flight (followers) are settled with their origin in the transaction that finishes it.
"""

from __future__ import annotations

import base64
import contextlib
import datetime as dt
import hashlib
import json
import sqlite3
import threading
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import sqlalchemy as sa
from sqlalchemy.engine import Connection, Engine

from geomcheck.errors import GeomcheckError, UsageError

SCHEMA_VERSION = 6

STATUSES = ("queued", "running", "succeeded", "failed", "cancelled")
FINISHED = ("succeeded", "failed", "cancelled")
UNFINISHED = ("queued", "running")
# what a check answered from the cache takes from the check whose report it shares
SHARED_FIGURES = ("robot", "verdict", "errors", "warnings", "infos", "has_matrix")
# check-duration histogram buckets of /metrics [s]
DURATION_BUCKETS = (0.5, 1.0, 2.0, 5.0, 10.0, 30.0, 60.0, 120.0, 300.0)


SQLITE_POOL_SIZE = 40  # connections kept open to a SQLite database [count]
KILLED_STATUS = 422  # as api.sandbox: the input cannot be processed within the limits


def exhausted_reason(max_attempts: int) -> str:
    return (
        f"the check was started {max_attempts} times and its worker was lost each time "
        "(killed, or out of memory); it is not tried again"
    )


def _progress(row: Any) -> dict[str, Any] | None:
    """The stored progress of an unfinished check: its own, or while it follows an identical
    check in flight, that check's."""
    if row.status not in UNFINISHED:
        return None
    text = row.progress or getattr(row, "origin_progress", None)
    return json.loads(text) if text else None


class StorageError(GeomcheckError):
    """The database cannot be opened or has a schema this service cannot use."""

    http_status = 503


def utcnow() -> dt.datetime:
    return dt.datetime.now(tz=dt.UTC)


def _utc(value: dt.datetime | None) -> dt.datetime | None:
    if value is None:
        return None
    return value if value.tzinfo is not None else value.replace(tzinfo=dt.UTC)


def normalise_url(url: str) -> str:
    """``postgresql://`` and ``postgres://`` use psycopg 3, the driver installed with geomcheck."""
    for scheme in ("postgresql://", "postgres://"):
        if url.startswith(scheme):
            return "postgresql+psycopg://" + url[len(scheme) :]
    return url


@dataclass(frozen=True)
class CheckRecord:
    """One stored check, without its report text."""

    id: str
    status: str
    created: dt.datetime
    started: dt.datetime | None
    finished: dt.datetime | None
    source: str
    robot: str | None
    verdict: str | None
    summary: dict[str, int] | None
    has_matrix: bool
    http_status: int | None
    reason: str | None
    options: dict[str, Any]
    seconds: float | None
    cached_from: str | None = None
    client: str | None = None  # the client (token name) that submitted the check
    origin_client: str | None = None  # the client of the check whose report this one shares
    progress: dict[str, Any] | None = None  # a running check's stage and fraction (geomcheck.progress)


@dataclass(frozen=True)
class CacheKeys:
    """What a check is looked up by in the result cache (see :mod:`api.resultcache`).

    ``request_key`` (the request's bytes and options) and ``result_key`` (the canonical
    upload and effective options): either may be unknown. ``fail_on`` is the report's
    lowest failing severity, ``default_fail_on`` the one a request naming none gets.
    """

    request_key: str | None = None
    result_key: str | None = None
    fail_on: str | None = None
    default_fail_on: str | None = None


@dataclass(frozen=True)
class Shared:
    """A new check answered from the cache: ``record``, whether it follows a check in flight,
    and the check whose row holds its report text (``holder``; None while following)."""

    record: CheckRecord
    following: bool
    holder: str | None = None


# the stored report text and the fail_on asked for -> the report text with that fail_on, its verdict
Rerender = Callable[[str, str], tuple[str, str]]


def _tables(prefix: str) -> tuple[sa.MetaData, sa.Table, sa.Table, sa.Table, sa.Table]:
    metadata = sa.MetaData()
    big_id = sa.BigInteger().with_variant(sa.Integer(), "sqlite")
    checks = sa.Table(
        f"{prefix}checks",
        metadata,
        sa.Column("seq", big_id, primary_key=True, autoincrement=True),
        sa.Column("id", sa.String(32), nullable=False, unique=True),
        sa.Column("status", sa.String(16), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("started_at", sa.DateTime(timezone=True)),
        sa.Column("finished_at", sa.DateTime(timezone=True)),
        sa.Column("source", sa.String(1024), nullable=False),
        sa.Column("robot", sa.String(512)),
        sa.Column("verdict", sa.String(8)),
        sa.Column("errors", sa.Integer),
        sa.Column("warnings", sa.Integer),
        sa.Column("infos", sa.Integer),
        sa.Column("has_matrix", sa.Boolean, nullable=False, default=False),
        sa.Column("http_status", sa.Integer),
        sa.Column("reason", sa.Text),
        sa.Column("options", sa.Text, nullable=False),
        sa.Column("seconds", sa.Float),
        # version 4 moved the report text to the reports table
        # version 2: the distributed mode (queue, lease) and uploads stored by content
        *_v2_columns(),
        # version 3: the result cache
        *_v3_columns(),
        sa.Index(f"ix_{prefix}checks_status", "status"),
        sa.Index(f"ix_{prefix}checks_created", "created_at"),
        # version 4: a key's rows in submission order, so the newest origin is found without
        # reading every earlier answer that key had (each cache hit adds a row)
        sa.Index(f"ix_{prefix}checks_result_key_seq", "result_key", "seq"),
        sa.Index(f"ix_{prefix}checks_request_key_seq", "request_key", "seq"),
        sa.Index(f"ix_{prefix}checks_cached_from", "cached_from"),
        # version 5: the client owning each check, its checks listed newest first
        *_v5_columns(),
        sa.Index(f"ix_{prefix}checks_client_seq", "client", "seq"),
        # version 6: the stage a running check is in and the fraction done
        *_v6_columns(),
    )
    version = sa.Table(
        f"{prefix}schema_version",
        metadata,
        sa.Column("version", sa.Integer, primary_key=True, autoincrement=False),
        sa.Column("applied_at", sa.DateTime(timezone=True), nullable=False),
    )
    blobs = sa.Table(
        f"{prefix}blobs",
        metadata,
        sa.Column("digest", sa.String(64), primary_key=True),  # SHA-256 of data, hex
        sa.Column("size", sa.BigInteger, nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("data", sa.LargeBinary, nullable=False),
    )
    # version 4: report texts (a megabyte or more) apart from the checks' rows: SQLite stores a
    # long value inline with overflow pages, so reading any column after it walked the whole
    # text, and every cache lookup reads the origin's row
    reports = sa.Table(
        f"{prefix}reports",
        metadata,
        sa.Column("check_id", sa.String(32), primary_key=True),
        sa.Column("report", sa.Text, nullable=False),
    )
    return metadata, checks, version, blobs, reports


def _v2_columns() -> list[sa.Column[Any]]:
    return [
        sa.Column("attempts", sa.Integer, nullable=False, server_default="0"),
        sa.Column("owner", sa.String(160)),  # the worker run holding the lease
        sa.Column("lease_until", sa.DateTime(timezone=True)),
        sa.Column("enqueued_at", sa.DateTime(timezone=True)),
        sa.Column("upload", sa.String(64)),  # digest of the upload in blobs (distributed mode)
        sa.Column("spec", sa.Text),  # JSON: the upload's layout and the request's raw options
    ]


def _v3_columns() -> list[sa.Column[Any]]:
    return [
        sa.Column("request_key", sa.String(64)),  # the request's body and options (api.resultcache)
        sa.Column("result_key", sa.String(64)),  # the canonical upload, options and versions
        sa.Column("cached_from", sa.String(32)),  # the check whose report this one shares
        sa.Column("fail_on", sa.String(8)),  # the report's fail_on
        sa.Column("default_fail_on", sa.String(8)),  # fail_on of a request that names none
    ]


def _v5_columns() -> list[sa.Column[Any]]:
    # the token's client name; NULL for checks stored before version 5 (only an admin sees them)
    return [sa.Column("client", sa.String(64))]


def _v6_columns() -> list[sa.Column[Any]]:
    # JSON of geomcheck.progress.StageProgress.to_dict(), written while the check runs
    return [sa.Column("progress", sa.Text)]


def _add_columns(conn: Connection, checks: sa.Table, columns: list[sa.Column[Any]], indexes: tuple[str, ...]) -> None:
    preparer = conn.dialect.identifier_preparer
    table = preparer.format_table(checks)
    for column in columns:
        kind = column.type.compile(dialect=conn.dialect)
        default = f" DEFAULT {column.server_default.arg}" if column.server_default is not None else ""  # type: ignore[attr-defined]
        null = " NOT NULL" if not column.nullable else ""
        conn.execute(sa.text(f"ALTER TABLE {table} ADD COLUMN {preparer.quote(column.name)} {kind}{default}{null}"))
    for index in checks.indexes:
        if index.name and index.name.endswith(indexes):
            index.create(conn, checkfirst=True)


def _add_columns_v2(conn: Connection, checks: sa.Table) -> None:
    """Version 1 -> 2: lease, attempts, upload columns and the created_at index."""
    _add_columns(conn, checks, _v2_columns(), ("_created",))


def _add_columns_v3(conn: Connection, checks: sa.Table) -> None:
    """Version 2 -> 3: the result cache's keys, origin and fail_on columns and their indexes."""
    _add_columns(conn, checks, _v3_columns(), ("_result_key_seq", "_request_key_seq", "_cached_from"))


def _reports_apart_v4(conn: Connection, checks: sa.Table) -> None:
    """Version 3 -> 4: report texts moved to the reports table (created before the migrations
    run); the cache keys indexed with the submission order, replacing the key-only indexes."""
    preparer = conn.dialect.identifier_preparer
    table = preparer.format_table(checks)
    reports = preparer.quote(f"{checks.name.removesuffix('checks')}reports")
    conn.execute(
        sa.text(f"INSERT INTO {reports} (check_id, report) SELECT id, report FROM {table} WHERE report IS NOT NULL")
    )
    if conn.dialect.name != "sqlite" or sqlite3.sqlite_version_info >= (3, 35):
        conn.execute(sa.text(f"ALTER TABLE {table} DROP COLUMN report"))
    else:  # no DROP COLUMN before SQLite 3.35: the column stays, empty and unused
        conn.execute(sa.text(f"UPDATE {table} SET report = NULL"))
    for key in ("result_key", "request_key"):
        sa.Index(f"ix_{checks.name}_{key}", checks.c[key]).drop(conn, checkfirst=True)
    _add_columns(conn, checks, [], ("_result_key_seq", "_request_key_seq"))


def _add_columns_v5(conn: Connection, checks: sa.Table) -> None:
    """Version 4 -> 5: the owning client of each check, indexed with the submission order."""
    _add_columns(conn, checks, _v5_columns(), ("_client_seq",))


def _add_columns_v6(conn: Connection, checks: sa.Table) -> None:
    """Version 5 -> 6: the progress of a running check."""
    _add_columns(conn, checks, _v6_columns(), ())


# version -> function bringing a database at version - 1 to it
MIGRATIONS: Mapping[int, Callable[[Connection, sa.Table], None]] = {
    2: _add_columns_v2,
    3: _add_columns_v3,
    4: _reports_apart_v4,
    5: _add_columns_v5,
    6: _add_columns_v6,
}


def digest_of(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


@dataclass(frozen=True)
class Claim:
    """A check a worker run may execute: its attempt number, stored upload digest and spec."""

    check_id: str
    attempt: int
    upload: str | None
    spec: dict[str, Any]


def describe(err: sa.exc.SQLAlchemyError) -> str:
    """The first line of the driver's message (no SQL, no parameters)."""
    return str(err.orig if isinstance(err, sa.exc.DBAPIError) else err).splitlines()[0]


def encode_cursor(seq: int) -> str:
    return base64.urlsafe_b64encode(f"c1:{seq}".encode()).decode().rstrip("=")


def decode_cursor(cursor: str) -> int:
    try:
        text = base64.urlsafe_b64decode(cursor + "=" * (-len(cursor) % 4)).decode()
        tag, _, number = text.partition(":")
        if tag != "c1":
            raise ValueError(tag)
        return int(number)
    except ValueError:
        raise UsageError(f"invalid cursor {cursor[:64]!r}; use the next_cursor of a previous page") from None


class Store:
    """Checks in a database at ``url`` (SQLAlchemy URL), tables named ``<prefix>checks`` etc."""

    def __init__(self, url: str, prefix: str = "") -> None:
        self.url = normalise_url(url)
        self.prefix = prefix
        self.metadata, self.checks, self.version_table, self.blobs, self.reports = _tables(prefix)
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
        """Create missing tables and migrate to :data:`SCHEMA_VERSION`; returns the version found before.

        One transaction; on PostgreSQL under an advisory lock named after the table prefix,
        so replicas starting at once on an empty database create and migrate it once.
        """
        try:
            with self._begin() as conn:
                self._lock_name(conn, f"geomcheck:{self.prefix}")
                self.metadata.create_all(conn)
                found = conn.execute(sa.select(sa.func.max(self.version_table.c.version))).scalar()
                if found is None:
                    conn.execute(self.version_table.insert().values(version=SCHEMA_VERSION, applied_at=utcnow()))
                    return 0
                if found > SCHEMA_VERSION:
                    raise StorageError(
                        f"database {self.display_url} has schema version {found}, newer than this service's "
                        f"{SCHEMA_VERSION}; upgrade geomcheck"
                    )
                for version in range(found + 1, SCHEMA_VERSION + 1):
                    MIGRATIONS[version](conn, self.checks)
                    conn.execute(self.version_table.insert().values(version=version, applied_at=utcnow()))
                return int(found)
        except sa.exc.SQLAlchemyError as err:
            raise StorageError(f"cannot open database {self.display_url}: {describe(err)}") from None

    def schema_version(self) -> int:
        with self.engine.connect() as conn:
            return int(conn.execute(sa.select(sa.func.max(self.version_table.c.version))).scalar() or 0)

    def drop_schema(self) -> None:
        """Drop this store's tables (tests clean up with it)."""
        self.metadata.drop_all(self.engine)

    def ping(self) -> bool:
        try:
            with self.engine.connect() as conn:
                conn.execute(sa.text("SELECT 1"))
            return True
        except sa.exc.SQLAlchemyError:
            return False

    def dispose(self) -> None:
        self.engine.dispose()

    def create(
        self,
        check_id: str,
        source: str,
        options: Mapping[str, Any],
        upload: str | None = None,
        spec: Mapping[str, Any] | None = None,
        keys: CacheKeys | None = None,
        client: str = "",
    ) -> None:
        """Record a queued check owned by ``client``; ``upload`` (a blob digest) and ``spec`` are
        what a remote worker needs, ``keys`` what identical submissions will find it by."""
        now = utcnow()
        keys = keys or CacheKeys()
        with self._begin() as conn:
            conn.execute(
                self.checks.insert().values(
                    id=check_id,
                    status="queued",
                    created_at=now,
                    enqueued_at=now,
                    source=source,
                    options=json.dumps(options, sort_keys=True),
                    has_matrix=False,
                    upload=upload,
                    spec=json.dumps(spec, sort_keys=True) if spec is not None else None,
                    request_key=keys.request_key,
                    result_key=keys.result_key,
                    fail_on=keys.fail_on,
                    default_fail_on=keys.default_fail_on,
                    client=client,
                )
            )

    # the result cache

    @staticmethod
    def _lock_name(conn: Connection, name: str) -> None:
        """On PostgreSQL, hold an advisory lock named ``name`` until the transaction ends, so
        replicas doing the same thing at once take turns (SQLite has one writing process)."""
        if conn.dialect.name == "postgresql":
            key = int.from_bytes(hashlib.sha256(name.encode()).digest()[:8], "big", signed=True)
            conn.execute(sa.text("SELECT pg_advisory_xact_lock(:key)"), {"key": key})

    def _find_origin(self, conn: Connection, keys: CacheKeys, client: str) -> Any:
        """The newest check with ``keys`` whose report can be shared: finished successfully
        (preferred, by either key, any client's) or still in flight (``client``'s own only: a
        check in flight can still be cancelled, and one client's cancel must not fail another
        client's check); a cached check leads to the check it came from.

        One indexed lookup per key and status group: each walks the key's rows newest first
        and stops at the first that leads to a usable origin, so its cost does not grow with
        the number of answers the key already had."""
        for finished in (True, False):
            for name, value in (("request_key", keys.request_key), ("result_key", keys.result_key)):
                if value is None:
                    continue
                found = conn.execute(self._origin_query(name, finished), {"key": value, "client": client}).first()
                if found is not None:
                    return found
        return None

    def _origin_query(self, key: str, finished: bool) -> Any:
        """The lookup of :meth:`_find_origin` by column ``key``, of succeeded (``finished``) or
        unfinished origins; built once: building a statement costs more than running it."""
        query = self._origin_queries.get((key, finished))
        if query is None:
            c, origin = self.checks.c, self.origin
            statuses = ("succeeded",) if finished else UNFINISHED
            query = self._origin_queries[(key, finished)] = (
                sa.select(
                    origin.c.id,
                    origin.c.status,
                    origin.c.fail_on,
                    origin.c.source,
                    origin.c.options,
                    origin.c.client,
                    *(origin.c[name] for name in SHARED_FIGURES),
                    c.default_fail_on,
                )
                .join(origin, origin.c.id == sa.func.coalesce(c.cached_from, c.id))
                .where(c[key] == sa.bindparam("key"), origin.c.cached_from.is_(None), origin.c.status.in_(statuses))
                .order_by(c.seq.desc())
                .limit(1)
            )
            if not finished:
                query = self._origin_queries[(key, finished)] = query.where(origin.c.client == sa.bindparam("client"))
        return query

    def share(
        self,
        check_id: str,
        source: str | None,
        options: Mapping[str, Any] | None,
        keys: CacheKeys,
        fail_on: str | None,
        rerender: Rerender,
        client: str = "",
    ) -> Shared | None:
        """Answer a new check ``check_id`` from the check with the same ``keys``, or None.

        A finished origin: the new check is recorded succeeded at once, sharing the origin's
        report (re-rendered by ``rerender`` when the effective ``fail_on``, the request's or
        else the upload's default, differs from the origin's). An origin in flight with the
        same ``fail_on``: the new check is recorded queued and settles with it. On PostgreSQL
        the lookup and the insert hold an advisory lock on the key, so replicas agree. The new
        check belongs to ``client``; an origin in flight is shared only with its own client.
        ``source`` and ``options`` None (a request not unpacked yet): the origin's, with the
        asked ``fail_on``.
        """
        with self._begin() as conn:
            self._lock_name(conn, f"geomcheck:{self.prefix}:{keys.result_key or keys.request_key or check_id}")
            found = self._find_origin(conn, keys, client)
            if found is None:
                return None
            effective = fail_on or found.default_fail_on or found.fail_on
            if options is None:
                options = {**json.loads(found.options), "fail_on": fail_on or "error"}
            now = utcnow()
            values: dict[str, Any] = {
                "id": check_id,
                "created_at": now,
                "enqueued_at": now,
                "source": source if source is not None else found.source,
                "options": json.dumps(options, sort_keys=True),
                "cached_from": found.id,
                "request_key": keys.request_key,
                "result_key": keys.result_key,
                "fail_on": effective,
                "default_fail_on": keys.default_fail_on or found.default_fail_on,
                "client": client,
            }
            report: str | None = None
            if found.status != "succeeded":
                if effective != found.fail_on:
                    return None
                row = {"status": "queued", "has_matrix": False, **values}
                following, holder = True, None
            else:
                verdict, holder = found.verdict, found.id
                if effective != found.fail_on:  # the only case that reads the (large) report text
                    text = conn.execute(
                        sa.select(self.reports.c.report).where(self.reports.c.check_id == found.id)
                    ).scalar_one()
                    (report, verdict), holder = rerender(text, effective), check_id
                row = {
                    "status": "succeeded",
                    "started_at": now,
                    "finished_at": now,
                    **{name: getattr(found, name) for name in SHARED_FIGURES},
                    "verdict": verdict,
                    **values,
                }
                following = False
            # parameters, not .values(): the compiled insert is then reused from SQLAlchemy's cache
            conn.execute(self.checks.insert(), row)
            if holder == check_id:
                conn.execute(self.reports.insert(), {"check_id": check_id, "report": report})
        unset = dict.fromkeys(
            ("started_at", "finished_at", "robot", "verdict", "errors", "http_status", "reason", "progress")
        )
        record = self._record(SimpleNamespace(**{**unset, "seconds": None, "origin_client": found.client, **row}))
        return Shared(record, following, holder)

    def _settle_followers(self, conn: Connection) -> None:
        """Finish the checks that follow an origin which has finished, as it finished."""
        c = self.checks.c
        origin = self.origin
        rows = conn.execute(
            sa.select(
                c.id,
                origin.c.id.label("origin_id"),
                origin.c.status,
                *(origin.c[name] for name in SHARED_FIGURES),
                origin.c.http_status,
                origin.c.reason,
            )
            .join(origin, origin.c.id == c.cached_from)
            .where(c.status.in_(UNFINISHED), origin.c.status.in_(FINISHED))
        ).all()
        now = utcnow()
        for row in rows:
            values: dict[str, Any] = {
                "started_at": sa.func.coalesce(c.started_at, now),
                "finished_at": now,
                "lease_until": None,
            }
            if row.status == "succeeded":
                values.update(status="succeeded", **{name: getattr(row, name) for name in SHARED_FIGURES})
            elif row.status == "failed":
                values.update(status="failed", http_status=row.http_status, reason=row.reason)
            else:
                reason = f"the identical check {row.origin_id} this one shared was cancelled; submit it again"
                values.update(status="failed", http_status=503, reason=reason)
            conn.execute(self.checks.update().where(c.id == row.id, c.status.in_(UNFINISHED)).values(**values))

    def mark_running(self, check_id: str) -> bool:
        """queued -> running (the embedded service); False when the check is no longer queued."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id, self.checks.c.status == "queued")
                .values(status="running", started_at=utcnow(), attempts=self.checks.c.attempts + 1)
            )
            return bool(result.rowcount)

    def _writable(self, check_id: str, owner: str | None) -> Any:
        """Rows a result may be written to: the check while unfinished, and held by ``owner`` when given."""
        condition = sa.and_(self.checks.c.id == check_id, self.checks.c.status.in_(UNFINISHED))
        if owner is not None:
            condition = sa.and_(condition, self.checks.c.owner == owner, self.checks.c.status == "running")
        return condition

    def finish_ok(
        self,
        check_id: str,
        report_json: str,
        robot: str,
        verdict: str,
        summary: Mapping[str, int],
        has_matrix: bool,
        seconds: float,
        owner: str | None = None,
    ) -> bool:
        """Store the report; False (nothing written) when the check was finished, cancelled or taken over."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self._writable(check_id, owner))
                .values(
                    status="succeeded",
                    finished_at=utcnow(),
                    robot=robot,
                    verdict=verdict,
                    errors=summary.get("error", 0),
                    warnings=summary.get("warning", 0),
                    infos=summary.get("info", 0),
                    has_matrix=has_matrix,
                    seconds=seconds,
                    lease_until=None,
                    progress=None,
                )
            )
            if result.rowcount:
                conn.execute(self.reports.insert(), {"check_id": check_id, "report": report_json})
            self._settle_followers(conn)
            return bool(result.rowcount)

    def finish_failed(
        self, check_id: str, http_status: int, reason: str, seconds: float | None = None, owner: str | None = None
    ) -> bool:
        """Record the failure; False (nothing written) when the check was finished, cancelled or taken over."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self._writable(check_id, owner))
                .values(
                    status="failed",
                    finished_at=utcnow(),
                    http_status=http_status,
                    reason=reason,
                    seconds=seconds,
                    lease_until=None,
                    progress=None,
                )
            )
            self._settle_followers(conn)
            return bool(result.rowcount)

    def set_progress(self, check_id: str, stage: Mapping[str, Any], owner: str | None = None) -> bool:
        """Record how far a running check has come (held by ``owner`` when given); False when it
        is no longer running (finished, cancelled, or taken over)."""
        c = self.checks.c
        condition = sa.and_(c.id == check_id, c.status == "running")
        if owner is not None:
            condition = sa.and_(condition, c.owner == owner)
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update().where(condition).values(progress=json.dumps(dict(stage), sort_keys=True))
            )
            return bool(result.rowcount)

    def cancel(self, check_id: str) -> bool:
        """queued or running -> cancelled; False when the check had already finished."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id, self.checks.c.status.in_(UNFINISHED))
                .values(
                    status="cancelled",
                    finished_at=utcnow(),
                    http_status=409,
                    reason="cancelled by a DELETE request",
                    lease_until=None,
                )
            )
            self._settle_followers(conn)
            return bool(result.rowcount)

    def interrupt_unfinished(self, reason: str) -> int:
        """Mark every queued or running check failed with ``reason`` (after a restart); returns how many."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.status.in_(UNFINISHED))
                .values(status="failed", finished_at=utcnow(), http_status=503, reason=reason)
            )
            return int(result.rowcount or 0)

    def fail_unfinished(self, check_ids: list[str], http_status: int, reason: str) -> None:
        """Mark those of ``check_ids`` still queued or running failed with ``reason``."""
        if not check_ids:
            return
        with self._begin() as conn:
            conn.execute(
                self.checks.update()
                .where(self.checks.c.id.in_(check_ids), self.checks.c.status.in_(UNFINISHED))
                .values(status="failed", finished_at=utcnow(), http_status=http_status, reason=reason)
            )
            self._settle_followers(conn)

    # the distributed mode: leases held by worker runs

    def claim(self, check_id: str, owner: str, lease_s: float, max_attempts: int) -> Claim | None:
        """Take ``check_id`` for ``owner`` with a lease of ``lease_s`` [s].

        Possible when it is queued, or running under a lease that expired (its worker
        vanished). None when there is nothing to do: finished, cancelled, unknown, or held
        by a live lease. A check already started ``max_attempts`` times is failed instead.
        """
        now = utcnow()
        c = self.checks.c
        takeable = sa.and_(
            c.id == check_id,
            sa.or_(c.status == "queued", sa.and_(c.status == "running", c.lease_until < now)),
        )
        with self._begin() as conn:
            exhausted = conn.execute(
                self.checks.update()
                .where(takeable, c.attempts >= max_attempts)
                .values(
                    status="failed",
                    finished_at=now,
                    http_status=KILLED_STATUS,
                    reason=exhausted_reason(max_attempts),
                    lease_until=None,
                )
            ).rowcount
            if exhausted:
                self._settle_followers(conn)
                return None
            row = conn.execute(
                self.checks.update()
                .where(takeable)
                .values(
                    status="running",
                    started_at=now,
                    owner=owner,
                    lease_until=now + dt.timedelta(seconds=lease_s),
                    attempts=c.attempts + 1,
                )
                .returning(c.attempts, c.upload, c.spec)
            ).first()
        if row is None:
            return None
        return Claim(check_id, int(row.attempts), row.upload, json.loads(row.spec) if row.spec else {})

    def renew(self, check_id: str, owner: str, lease_s: float) -> bool:
        """Extend ``owner``'s lease; False when it lost the check (cancelled, or taken over after expiry)."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id, self.checks.c.owner == owner, self.checks.c.status == "running")
                .values(lease_until=utcnow() + dt.timedelta(seconds=lease_s))
            )
            return bool(result.rowcount)

    def recover_abandoned(self, max_attempts: int, requeue_after_s: float) -> tuple[list[str], int]:
        """Checks to publish again, and how many abandoned ones were failed.

        A running check whose lease expired lost its worker: back to ``queued`` (or
        ``failed`` once started ``max_attempts`` times). A check queued for longer than
        ``requeue_after_s`` [s] may have lost its message (a broker restarted without
        persistence): it is published again; a duplicate message finds it taken and does
        nothing. Each row changes in one statement, so of several recovering nodes only one
        acts on it.
        """
        now = utcnow()
        c = self.checks.c
        expired = sa.and_(c.status == "running", c.lease_until < now)
        with self._begin() as conn:
            failed = conn.execute(
                self.checks.update()
                .where(expired, c.attempts >= max_attempts)
                .values(
                    status="failed",
                    finished_at=now,
                    http_status=KILLED_STATUS,
                    reason=exhausted_reason(max_attempts),
                    lease_until=None,
                )
            ).rowcount
            requeued = conn.execute(
                self.checks.update()
                .where(expired)
                .values(status="queued", owner=None, lease_until=None, enqueued_at=now, progress=None)
                .returning(c.id)
            ).scalars()
            ids = list(requeued)
            stale = conn.execute(
                self.checks.update()
                .where(
                    c.status == "queued",
                    c.cached_from.is_(None),
                    c.enqueued_at < now - dt.timedelta(seconds=requeue_after_s),
                )
                .values(enqueued_at=now)
                .returning(c.id)
            ).scalars()
            ids.extend(stale)
            if failed:
                self._settle_followers(conn)
        return sorted(set(ids)), int(failed or 0)

    def count_unfinished(self) -> int:
        with self.engine.connect() as conn:
            return int(
                conn.execute(
                    sa.select(sa.func.count()).select_from(self.checks).where(self.checks.c.status.in_(UNFINISHED))
                ).scalar()
                or 0
            )

    def counts_by_status(self) -> dict[str, int]:
        """Number of stored checks per status (every status present, zeros included)."""
        with self.engine.connect() as conn:
            rows = conn.execute(sa.select(self.checks.c.status, sa.func.count()).group_by(self.checks.c.status)).all()
        counts = dict.fromkeys(STATUSES, 0)
        counts.update({str(status): int(n) for status, n in rows})
        return counts

    def duration_histogram(self, buckets: tuple[float, ...] = DURATION_BUCKETS) -> tuple[list[int], int, float]:
        """Finished checks' run times [s]: cumulative counts at ``buckets`` (then +Inf), the count and the sum."""
        seconds = self.checks.c.seconds
        columns = [sa.func.sum(sa.case((seconds <= b, 1), else_=0)) for b in buckets]
        with self.engine.connect() as conn:
            row = conn.execute(
                sa.select(*columns, sa.func.count(seconds), sa.func.coalesce(sa.func.sum(seconds), 0.0)).where(
                    seconds.is_not(None)
                )
            ).one()
        counts = [int(v or 0) for v in row[: len(buckets)]]
        return [*counts, int(row[-2])], int(row[-2]), float(row[-1])

    def delete_older_than(self, age_s: float) -> tuple[int, int]:
        """Delete checks created more than ``age_s`` [s] ago (reports with them) and uploads no check
        refers to any more; returns (checks, uploads) deleted. Unfinished checks are kept."""
        cutoff = utcnow() - dt.timedelta(seconds=age_s)
        c = self.checks.c
        with self._begin() as conn:
            shared = sa.select(c.cached_from).where(c.cached_from.is_not(None), c.created_at >= cutoff)
            old = sa.and_(c.created_at < cutoff, c.status.in_(FINISHED), c.id.not_in(shared))
            conn.execute(self.reports.delete().where(self.reports.c.check_id.in_(sa.select(c.id).where(old))))
            checks = conn.execute(self.checks.delete().where(old)).rowcount
            referenced = sa.select(c.upload).where(c.upload.is_not(None))
            uploads = conn.execute(
                self.blobs.delete().where(self.blobs.c.digest.not_in(referenced), self.blobs.c.created_at < cutoff)
            ).rowcount
        return int(checks or 0), int(uploads or 0)

    # uploads stored by content, readable by every worker

    def put_blob(self, data: bytes) -> str:
        """Store ``data`` once under its SHA-256 digest (hex), which is returned."""
        digest = digest_of(data)
        try:
            with self._begin() as conn:
                conn.execute(self.blobs.insert().values(digest=digest, size=len(data), created_at=utcnow(), data=data))
        except sa.exc.IntegrityError:  # stored before: refresh its age so retention keeps it
            with self._begin() as conn:
                conn.execute(self.blobs.update().where(self.blobs.c.digest == digest).values(created_at=utcnow()))
        return digest

    def get_blob(self, digest: str) -> bytes | None:
        with self.engine.connect() as conn:
            data = conn.execute(sa.select(self.blobs.c.data).where(self.blobs.c.digest == digest)).scalar()
        return bytes(data) if data is not None else None

    def _columns(self) -> list[sa.Column[Any]]:
        return [c for c in self.checks.c if c.name != "spec"]

    def _with_origin_client(self, query: Any) -> Any:
        """``query`` over the checks with the client of each one's origin (``origin_client``)."""
        origin = self.checks.alias("record_origin")
        columns = (origin.c.client.label("origin_client"), origin.c.progress.label("origin_progress"))
        return query.add_columns(*columns).select_from(
            self.checks.outerjoin(origin, origin.c.id == self.checks.c.cached_from)
        )

    @staticmethod
    def _record(row: Any) -> CheckRecord:
        summary = None
        if row.errors is not None:
            summary = {"error": row.errors, "warning": row.warnings, "info": row.infos}
        created = _utc(row.created_at)
        assert created is not None
        return CheckRecord(
            id=row.id,
            status=row.status,
            created=created,
            started=_utc(row.started_at),
            finished=_utc(row.finished_at),
            source=row.source,
            robot=row.robot,
            verdict=row.verdict,
            summary=summary,
            has_matrix=bool(row.has_matrix),
            http_status=row.http_status,
            reason=row.reason,
            options=json.loads(row.options),
            seconds=row.seconds,
            cached_from=row.cached_from,
            client=row.client,
            origin_client=row.origin_client,
            progress=_progress(row),
        )

    def get(self, check_id: str) -> CheckRecord | None:
        with self.engine.connect() as conn:
            row = conn.execute(self._record_by_id, {"check_id": check_id}).first()
        return self._record(row) if row is not None else None

    def report(self, check_id: str) -> str | None:
        """The stored JSON report text, exactly as written (None when there is none): the
        check's own, or for a check answered from the cache the report of its origin."""
        c = self.checks.c
        own, shared = self.reports.alias("own"), self.reports.alias("shared")
        query = (
            sa.select(sa.func.coalesce(own.c.report, shared.c.report))
            .select_from(
                self.checks.outerjoin(own, own.c.check_id == c.id).outerjoin(shared, shared.c.check_id == c.cached_from)
            )
            .where(c.id == check_id)
        )
        with self.engine.connect() as conn:
            return conn.execute(query).scalar()

    def report_holder(self, check_id: str) -> str | None:
        """The id of the check whose row holds ``check_id``'s report text (itself, or its origin)."""
        with self.engine.connect() as conn:
            return conn.execute(self._holder_by_id, {"check_id": check_id}).scalar()

    def recent(
        self, limit: int, cursor: str | None = None, status: str | None = None, client: str | None = None
    ) -> tuple[list[CheckRecord], str | None]:
        """Newest checks first, ``limit`` per page, only ``client``'s when given; returns the page
        and the cursor of the next one."""
        query = self._with_origin_client(sa.select(*self._columns())).order_by(self.checks.c.seq.desc())
        query = query.limit(limit + 1)
        if client is not None:
            query = query.where(self.checks.c.client == client)
        if cursor:
            query = query.where(self.checks.c.seq < decode_cursor(cursor))
        if status is not None:  # an empty status is no status: refused, not ignored
            if status not in STATUSES:
                raise UsageError.bad_choice("status", status, STATUSES)
            query = query.where(self.checks.c.status == status)
        with self.engine.connect() as conn:
            rows = conn.execute(query).all()
        page = rows[:limit]
        next_cursor = encode_cursor(page[-1].seq) if len(rows) > limit and page else None
        return [self._record(r) for r in page], next_cursor
