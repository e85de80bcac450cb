"""The store's schema as this service writes it, and the records read from it.

One table of checks (status, figures, lease, cache keys, progress), one of their JSON
reports as the CLI writes them (``reports``, kept apart so the checks' rows stay small), a
table of uploads stored by content (``blobs``, read by the workers of the distributed mode)
and ``schema_version``, the legacy version record (see :mod:`api.store.migrate`). Table
names carry an optional prefix so several services (or test runs) can share a database.
How a database of an earlier version becomes this one is in ``api/store/migrations``.
"""

from __future__ import annotations

import base64
import datetime as dt
import json
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import sqlalchemy as sa

from geomcheck.errors import GeomcheckError, UsageError

STATUSES = ("queued", "running", "succeeded", "failed", "cancelled")
FINISHED = ("succeeded", "failed", "cancelled")
UNFINISHED = ("queued", "running")
# what a check answered from the cache takes from the check whose report it shares
SHARED_FIGURES = ("robot", "verdict", "errors", "warnings", "infos", "has_matrix")


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


def describe(err: sa.exc.SQLAlchemyError) -> str:
    """The first line of the driver's message (no SQL, no parameters)."""
    return str(err.orig if isinstance(err, sa.exc.DBAPIError) else err).splitlines()[0]


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
    fixes: str | None = None  # the state of its offered fixes (api.checks.job FIXES_*), None: none offered
    fixes_reason: str | None = None  # why their verification did not finish
    root: dict[str, Any] | None = None  # how its root file was chosen (api.uploads.roots.RootChoice)


@dataclass(frozen=True)
class CacheKeys:
    """What a check is looked up by in the result cache (see :mod:`api.results.cache`).

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


@dataclass(frozen=True)
class Claim:
    """A check a worker run may execute: its attempt number, stored upload digest and spec."""

    check_id: str
    attempt: int
    upload: str | None
    spec: dict[str, Any]


# the stored report text and the fail_on asked for -> the report text with that fail_on, its verdict
Rerender = Callable[[str, str], tuple[str, str]]


def _check_columns() -> list[sa.Column[Any]]:
    """The columns of the checks table, in the order the table was created with."""
    big_id = sa.BigInteger().with_variant(sa.Integer(), "sqlite")
    return [
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
        # the distributed mode: queue, lease, upload stored by content
        sa.Column("attempts", sa.Integer, nullable=False, server_default="0"),
        sa.Column("owner", sa.String(160)),  # the worker run holding the lease
        sa.Column("lease_until", sa.DateTime(timezone=True)),
        sa.Column("enqueued_at", sa.DateTime(timezone=True)),
        sa.Column("upload", sa.String(64)),  # digest of the upload in blobs (distributed mode)
        sa.Column("spec", sa.Text),  # JSON: the upload's layout and the request's raw options
        # the result cache (api.results.cache)
        sa.Column("request_key", sa.String(64)),  # the request's body and options
        sa.Column("result_key", sa.String(64)),  # the canonical upload, options and versions
        sa.Column("cached_from", sa.String(32)),  # the check whose report this one shares
        sa.Column("fail_on", sa.String(8)),  # the report's fail_on
        sa.Column("default_fail_on", sa.String(8)),  # fail_on of a request that names none
        # the client (token name) owning each check, its checks listed newest first; NULL for
        # checks stored before clients were recorded (only an admin sees them)
        sa.Column("client", sa.String(64)),
        # JSON of geomcheck.progress.StageProgress.to_dict(), written while the check runs (and
        # while its fixes are verified)
        sa.Column("progress", sa.Text),
        # the offered fixes, verified after the report (api.checks.job FIXES_*), and why a verification
        # did not finish
        sa.Column("fixes", sa.String(16)),
        sa.Column("fixes_reason", sa.Text),
        # JSON of api.uploads.roots.RootChoice: the root file, whether the request named it, why, the alternatives
        sa.Column("root", sa.Text),
    ]


def _check_indexes(prefix: str) -> list[sa.Index]:
    """The indexes of the checks table: by status and age, by cache key, by client."""
    return [
        sa.Index(f"ix_{prefix}checks_status", "status"),
        sa.Index(f"ix_{prefix}checks_created", "created_at"),
        # a key's rows in submission order, so the newest origin is found without reading every
        # earlier answer that key had (each cache hit adds a row)
        sa.Index(f"ix_{prefix}checks_result_key_seq", "result_key", "seq"),
        sa.Index(f"ix_{prefix}checks_request_key_seq", "request_key", "seq"),
        sa.Index(f"ix_{prefix}checks_cached_from", "cached_from"),
        sa.Index(f"ix_{prefix}checks_client_seq", "client", "seq"),
    ]


def tables(prefix: str) -> tuple[sa.MetaData, sa.Table, sa.Table, sa.Table, sa.Table]:
    """The tables of a store whose names start with ``prefix``: checks, schema version, blobs, reports."""
    metadata = sa.MetaData()
    checks = sa.Table(f"{prefix}checks", metadata, *_check_columns(), *_check_indexes(prefix))
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
    # report texts (a megabyte or more) apart from the checks' rows: SQLite stores a
    # long value inline with overflow pages, so reading any column after it walked the whole
    # text, and every cache lookup reads the origin's row
    reports = sa.Table(
        f"{prefix}reports",
        metadata,
        sa.Column("check_id", sa.String(32), primary_key=True),
        sa.Column("report", sa.Text, nullable=False),
    )
    return metadata, checks, version, blobs, reports


VERIFYING = "verifying"  # the fixes state of a check whose report is out and whose fixes are being verified


def _fixes(row: Any) -> str | None:
    """The state of a check's offered fixes: its own, or for a check sharing another's report, that one's."""
    own: str | None = row.fixes
    return own if own is not None else getattr(row, "origin_fixes", None)


def _progress(row: Any) -> dict[str, Any] | None:
    """The stored progress of an unfinished check, or of one whose fixes are being verified:
    its own, or while it follows an identical check in flight, that check's."""
    if row.status not in UNFINISHED and _fixes(row) != VERIFYING:
        return None
    text = row.progress or getattr(row, "origin_progress", None)
    return json.loads(text) if text else None


def record_of(row: Any) -> CheckRecord:
    """The :class:`CheckRecord` of a row of the checks (with ``origin_client``)."""
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
        fixes=_fixes(row),
        fixes_reason=row.fixes_reason if row.fixes is not None else getattr(row, "origin_fixes_reason", None),
        root=json.loads(row.root) if row.root else None,
    )


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
