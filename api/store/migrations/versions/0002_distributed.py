"""Version 2: the distributed mode: queue and lease columns, uploads stored by content.

Revision ID: 0002
Revises: 0001
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

from api.store.migrations import create_index, existing_tables, record_version, table

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    checks = table("checks")
    op.add_column(checks, sa.Column("attempts", sa.Integer, nullable=False, server_default="0"))
    op.add_column(checks, sa.Column("owner", sa.String(160)))
    op.add_column(checks, sa.Column("lease_until", sa.DateTime(timezone=True)))
    op.add_column(checks, sa.Column("enqueued_at", sa.DateTime(timezone=True)))
    op.add_column(checks, sa.Column("upload", sa.String(64)))
    op.add_column(checks, sa.Column("spec", sa.Text))
    create_index("created", checks, "created_at")
    if table("blobs") not in existing_tables():
        op.create_table(
            table("blobs"),
            sa.Column("digest", sa.String(64), primary_key=True),
            sa.Column("size", sa.BigInteger, nullable=False),
            sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
            sa.Column("data", sa.LargeBinary, nullable=False),
        )
    record_version(2)
