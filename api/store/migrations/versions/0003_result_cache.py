"""Version 3: the result cache's keys, origin and fail_on columns and their indexes.

Revision ID: 0003
Revises: 0002
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

from api.store.migrations import create_index, record_version, table

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None


def upgrade() -> None:
    checks = table("checks")
    op.add_column(checks, sa.Column("request_key", sa.String(64)))
    op.add_column(checks, sa.Column("result_key", sa.String(64)))
    op.add_column(checks, sa.Column("cached_from", sa.String(32)))
    op.add_column(checks, sa.Column("fail_on", sa.String(8)))
    op.add_column(checks, sa.Column("default_fail_on", sa.String(8)))
    create_index("result_key", checks, "result_key")
    create_index("request_key", checks, "request_key")
    create_index("cached_from", checks, "cached_from")
    record_version(3)
