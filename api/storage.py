"""Persistence of checks and their reports: SQLAlchemy 2 Core over SQLite or PostgreSQL.

One table of checks (status, figures, the JSON report as the CLI writes it) and a
``schema_version`` table: the schema is created on start, and a database written by an
older service is brought up to date by the functions in ``MIGRATIONS`` (version n-1 -> n).
Table names carry an optional prefix so several services (or test runs) can share a database.
"""

from __future__ import annotations

import base64
import datetime as dt
import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import sqlalchemy as sa
from sqlalchemy.engine import Connection, Engine

from geomcheck.errors import GeomcheckError, UsageError

SCHEMA_VERSION = 1
# version -> function bringing a database at version - 1 to it; none yet (version 1 is the first)
MIGRATIONS: Mapping[int, Callable[[Connection, sa.Table], None]] = {}

STATUSES = ("queued", "running", "succeeded", "failed")
FINISHED = ("succeeded", "failed")


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


def _tables(prefix: str) -> tuple[sa.MetaData, sa.Table, sa.Table]:
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
        sa.Column("report", sa.Text),
        sa.Index(f"ix_{prefix}checks_status", "status"),
    )
    version = sa.Table(
        f"{prefix}schema_version",
        metadata,
        sa.Column("version", sa.Integer, primary_key=True, autoincrement=False),
        sa.Column("applied_at", sa.DateTime(timezone=True), nullable=False),
    )
    return metadata, checks, version


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
        self.metadata, self.checks, self.version_table = _tables(prefix)
        self.engine = self._make_engine(self.url)

    @staticmethod
    def _make_engine(url: str) -> Engine:
        parsed = sa.make_url(url)
        if parsed.get_backend_name() == "sqlite":
            if parsed.database and parsed.database != ":memory:":
                Path(parsed.database).parent.mkdir(parents=True, exist_ok=True)
            engine = sa.create_engine(url, connect_args={"check_same_thread": False, "timeout": 30})

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
        """Create missing tables and migrate to :data:`SCHEMA_VERSION`; returns the version found before."""
        try:
            self.metadata.create_all(self.engine)
            with self.engine.begin() as conn:
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
            reason = str(err.orig if isinstance(err, sa.exc.DBAPIError) else err).splitlines()[0]
            raise StorageError(f"cannot open database {self.display_url}: {reason}") from None

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

    def create(self, check_id: str, source: str, options: Mapping[str, Any]) -> None:
        with self.engine.begin() as conn:
            conn.execute(
                self.checks.insert().values(
                    id=check_id,
                    status="queued",
                    created_at=utcnow(),
                    source=source,
                    options=json.dumps(options, sort_keys=True),
                    has_matrix=False,
                )
            )

    def mark_running(self, check_id: str) -> None:
        with self.engine.begin() as conn:
            conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id, self.checks.c.status == "queued")
                .values(status="running", started_at=utcnow())
            )

    def finish_ok(
        self,
        check_id: str,
        report_json: str,
        robot: str,
        verdict: str,
        summary: Mapping[str, int],
        has_matrix: bool,
        seconds: float,
    ) -> None:
        with self.engine.begin() as conn:
            conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id)
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
                    report=report_json,
                )
            )

    def finish_failed(self, check_id: str, http_status: int, reason: str, seconds: float | None = None) -> None:
        with self.engine.begin() as conn:
            conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id)
                .values(status="failed", finished_at=utcnow(), http_status=http_status, reason=reason, seconds=seconds)
            )

    def interrupt_unfinished(self, reason: str) -> int:
        """Mark every queued or running check failed with ``reason`` (after a restart); returns how many."""
        with self.engine.begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.status.in_(("queued", "running")))
                .values(status="failed", finished_at=utcnow(), http_status=503, reason=reason)
            )
            return int(result.rowcount or 0)

    def fail_unfinished(self, check_ids: list[str], http_status: int, reason: str) -> None:
        """Mark those of ``check_ids`` still queued or running failed with ``reason``."""
        if not check_ids:
            return
        with self.engine.begin() as conn:
            conn.execute(
                self.checks.update()
                .where(self.checks.c.id.in_(check_ids), self.checks.c.status.in_(("queued", "running")))
                .values(status="failed", finished_at=utcnow(), http_status=http_status, reason=reason)
            )

    def _columns(self) -> list[sa.Column[Any]]:
        return [c for c in self.checks.c if c.name != "report"]

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
        )

    def get(self, check_id: str) -> CheckRecord | None:
        with self.engine.connect() as conn:
            row = conn.execute(sa.select(*self._columns()).where(self.checks.c.id == check_id)).first()
        return self._record(row) if row is not None else None

    def report(self, check_id: str) -> str | None:
        """The stored JSON report text, exactly as written (None when there is none)."""
        with self.engine.connect() as conn:
            return conn.execute(sa.select(self.checks.c.report).where(self.checks.c.id == check_id)).scalar()

    def recent(
        self, limit: int, cursor: str | None = None, status: str | None = None
    ) -> tuple[list[CheckRecord], str | None]:
        """Newest checks first, ``limit`` per page; returns the page and the cursor of the next one."""
        query = sa.select(*self._columns()).order_by(self.checks.c.seq.desc()).limit(limit + 1)
        if cursor:
            query = query.where(self.checks.c.seq < decode_cursor(cursor))
        if status:
            if status not in STATUSES:
                raise UsageError.bad_choice("status", status, STATUSES)
            query = query.where(self.checks.c.status == status)
        with self.engine.connect() as conn:
            rows = conn.execute(query).all()
        page = rows[:limit]
        next_cursor = encode_cursor(page[-1].seq) if len(rows) > limit and page else None
        return [self._record(r) for r in page], next_cursor
