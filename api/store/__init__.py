"""Persistence of checks and their reports: SQLAlchemy 2 Core over SQLite or PostgreSQL.

One module per job: :mod:`api.store.schema` (tables and records), :mod:`api.store.migrate`
and ``migrations/`` (Alembic revisions, one per schema version), :mod:`api.store.database`
(engine, write transactions, schema creation), :mod:`api.store.checks` (a check's rows from
queued to finished, reading them), :mod:`api.store.leases` (the distributed mode's claims),
:mod:`api.store.sharing` (the result cache), :mod:`api.store.metrics` and
:mod:`api.store.blobs` (uploads by content). :class:`Store` is all of them over one database.
"""

from __future__ import annotations

from api.store.blobs import Blobs, digest_of
from api.store.checks import CheckRows
from api.store.leases import KILLED_STATUS, Leases, exhausted_reason
from api.store.metrics import DURATION_BUCKETS, Metrics
from api.store.migrate import SCHEMA_VERSION
from api.store.schema import (
    FINISHED,
    STATUSES,
    UNFINISHED,
    CacheKeys,
    CheckRecord,
    Claim,
    Rerender,
    Shared,
    StorageError,
    normalise_url,
    utcnow,
)
from api.store.sharing import ResultSharing


class Store(CheckRows, Leases, ResultSharing, Metrics, Blobs):
    """Checks, their reports and uploads in a database at ``url`` (SQLAlchemy URL), tables named
    ``<prefix>checks`` etc."""


__all__ = [
    "DURATION_BUCKETS",
    "FINISHED",
    "KILLED_STATUS",
    "SCHEMA_VERSION",
    "STATUSES",
    "UNFINISHED",
    "CacheKeys",
    "CheckRecord",
    "Claim",
    "Rerender",
    "Shared",
    "StorageError",
    "Store",
    "digest_of",
    "exhausted_reason",
    "normalise_url",
    "utcnow",
]
