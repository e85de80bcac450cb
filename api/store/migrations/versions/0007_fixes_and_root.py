"""Version 7: the state of a check's offered fixes, verified after its report (``fixes``, and
why a verification did not finish, ``fixes_reason``), and the root file chosen for it (``root``,
JSON: path, whether the request named it, why, the alternatives).

Revision ID: 0007
Revises: 0006
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

from api.store.migrations import record_version, table

revision = "0007"
down_revision = "0006"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column(table("checks"), sa.Column("fixes", sa.String(16)))
    op.add_column(table("checks"), sa.Column("fixes_reason", sa.Text))
    op.add_column(table("checks"), sa.Column("root", sa.Text))
    record_version(7)
