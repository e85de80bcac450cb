"""Alembic revisions of the store's schema, one per schema version (``versions/``), and what
they share: the table prefix of the store being migrated and the legacy version record.

Revisions run only through :func:`api.store.migrate.upgrade`, which hands ``env.py`` the
connection (inside the store's transaction and advisory lock) and the table prefix.
"""

from __future__ import annotations

import datetime as dt

import sqlalchemy as sa
from alembic import context, op


def prefix() -> str:
    """The table prefix of the store being migrated."""
    return str(context.config.attributes["prefix"])


def table(name: str) -> str:
    return f"{prefix()}{name}"


def existing_tables() -> set[str]:
    return set(sa.inspect(op.get_bind()).get_table_names())


def create_index(name: str, table_name: str, *columns: str) -> None:
    """Index ``ix_<prefix><table_name>_<name>`` unless a database written before Alembic has it."""
    bind = op.get_bind()
    checks = sa.Table(table_name, sa.MetaData(), autoload_with=bind)
    sa.Index(f"ix_{table_name}_{name}", *(checks.c[c] for c in columns)).create(bind, checkfirst=True)


def drop_index(name: str, table_name: str) -> None:
    bind = op.get_bind()
    checks = sa.Table(table_name, sa.MetaData(), autoload_with=bind)
    index = next((i for i in checks.indexes if i.name == f"ix_{table_name}_{name}"), None)
    if index is not None:
        index.drop(bind)


def record_version(version: int) -> None:
    """Write ``version`` to the legacy ``schema_version`` table: a service from before Alembic
    reads it and refuses a database newer than itself instead of misreading it."""
    versions = sa.table(table("schema_version"), sa.column("version"), sa.column("applied_at"))
    op.execute(versions.insert().values(version=version, applied_at=dt.datetime.now(tz=dt.UTC)))


__all__ = ["create_index", "drop_index", "existing_tables", "prefix", "record_version", "table"]
