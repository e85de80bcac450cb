"""Bringing a database to this service's schema: Alembic revisions run programmatically.

The revisions (``api/store/migrations/versions``) are the schema versions 1 to
:data:`SCHEMA_VERSION`; an empty database goes through all of them, and Alembic's table
``<prefix>alembic_version`` says where a database stands. A database written before Alembic
has only the legacy ``<prefix>schema_version`` table: it is stamped at its version's
revision, then upgraded. Each revision still records its number in ``schema_version``, so
a service older than the database refuses it rather than misreading it, and so does this
one with a database newer than itself.

:func:`upgrade` runs on the caller's connection, inside its transaction (Alembic's
connection-sharing recipe: ``Config.attributes['connection']`` read by ``env.py``).
"""

from __future__ import annotations

from pathlib import Path

import sqlalchemy as sa
from alembic import command
from alembic.config import Config
from alembic.util import CommandError
from sqlalchemy.engine import Connection

from api.store.schema import StorageError

SCHEMA_VERSION = 7
MIGRATIONS = Path(__file__).resolve().parent / "migrations"


def revision_of(version: int) -> str:
    """The Alembic revision of schema version ``version`` (``0001`` for 1)."""
    return f"{version:04d}"


def alembic_config(conn: Connection, prefix: str) -> Config:
    config = Config()
    config.set_main_option("script_location", str(MIGRATIONS))
    config.attributes["connection"] = conn
    config.attributes["prefix"] = prefix
    return config


def found_version(conn: Connection, prefix: str) -> int:
    """The newest schema version recorded in the database; 0 when it has none (empty)."""
    if not sa.inspect(conn).has_table(f"{prefix}schema_version"):
        return 0
    versions = sa.table(f"{prefix}schema_version", sa.column("version"))
    return int(conn.execute(sa.select(sa.func.max(versions.c.version))).scalar() or 0)


def upgrade(conn: Connection, prefix: str, display_url: str) -> int:
    """Migrate the tables named with ``prefix`` to :data:`SCHEMA_VERSION`; the version found before.

    :class:`StorageError` when the database is newer than this service.
    """
    found = found_version(conn, prefix)
    if found > SCHEMA_VERSION:
        raise StorageError(
            f"database {display_url} has schema version {found}, newer than this service's "
            f"{SCHEMA_VERSION}; upgrade geomcheck"
        )
    config = alembic_config(conn, prefix)
    try:
        if found and not sa.inspect(conn).has_table(f"{prefix}alembic_version"):
            command.stamp(config, revision_of(found))  # written before Alembic: its version is its revision
        command.upgrade(config, "head")
    except CommandError as err:
        raise StorageError(f"cannot migrate database {display_url}: {err}") from None
    return found
