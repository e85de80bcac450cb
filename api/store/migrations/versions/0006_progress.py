"""Version 6: the progress of a running check (its stage and the fraction done, as JSON).

Revision ID: 0006
Revises: 0005
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

from api.store.migrations import record_version, table

revision = "0006"
down_revision = "0005"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column(table("checks"), sa.Column("progress", sa.Text))
    record_version(6)
