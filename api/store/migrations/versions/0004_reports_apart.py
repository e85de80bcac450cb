"""Version 4: report texts in their own table; the cache keys indexed with the submission order.

A report text (a megabyte or more) in the checks' row made SQLite walk it to read any column
after it, and every cache lookup reads the origin's row. The key-only indexes give way to
(key, seq) ones, so the newest origin of a key is found without reading its earlier answers.

Revision ID: 0004
Revises: 0003
"""

from __future__ import annotations

import sqlite3

import sqlalchemy as sa
from alembic import op

from api.store.migrations import create_index, drop_index, existing_tables, record_version, table

revision = "0004"
down_revision = "0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    checks, reports = table("checks"), table("reports")
    if reports not in existing_tables():
        op.create_table(
            reports,
            sa.Column("check_id", sa.String(32), primary_key=True),
            sa.Column("report", sa.Text, nullable=False),
        )
    bind = op.get_bind()
    quote = bind.dialect.identifier_preparer.quote
    op.execute(
        f"INSERT INTO {quote(reports)} (check_id, report) "
        f"SELECT id, report FROM {quote(checks)} WHERE report IS NOT NULL"
    )
    if bind.dialect.name != "sqlite" or sqlite3.sqlite_version_info >= (3, 35):
        op.drop_column(checks, "report")
    else:  # no DROP COLUMN before SQLite 3.35: the column stays, empty and unused
        op.execute(f"UPDATE {quote(checks)} SET report = NULL")
    for key in ("result_key", "request_key"):
        drop_index(key, checks)
        create_index(f"{key}_seq", checks, key, "seq")
    record_version(4)
