"""Alembic's environment: the connection and table prefix come from :func:`api.store.migrate.upgrade`."""

from __future__ import annotations

from alembic import context

connection = context.config.attributes["connection"]
context.configure(
    connection=connection,
    version_table=f"{context.config.attributes['prefix']}alembic_version",
    transactional_ddl=True,
)
with context.begin_transaction():
    context.run_migrations()
