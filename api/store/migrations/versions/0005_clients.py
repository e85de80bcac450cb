"""Version 5: the client (token name) owning each check, its checks listed newest first.

Checks stored before it have none: only an admin sees them.

Revision ID: 0005
Revises: 0004
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

from api.store.migrations import create_index, record_version, table

revision = "0005"
down_revision = "0004"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column(table("checks"), sa.Column("client", sa.String(64)))
    create_index("client_seq", table("checks"), "client", "seq")
    record_version(5)
