"""Figures of the stored checks for ``/metrics`` and the queue limit: counts and run times."""

from __future__ import annotations

import sqlalchemy as sa

from api.store.database import Database
from api.store.schema import STATUSES, UNFINISHED

# check-duration histogram buckets of /metrics [s]
DURATION_BUCKETS = (0.5, 1.0, 2.0, 5.0, 10.0, 30.0, 60.0, 120.0, 300.0)


class Metrics(Database):
    """Counts of checks by status and the histogram of their run times."""

    def count_unfinished(self) -> int:
        with self.engine.connect() as conn:
            return int(
                conn.execute(
                    sa.select(sa.func.count()).select_from(self.checks).where(self.checks.c.status.in_(UNFINISHED))
                ).scalar()
                or 0
            )

    def counts_by_status(self) -> dict[str, int]:
        """Number of stored checks per status (every status present, zeros included)."""
        with self.engine.connect() as conn:
            rows = conn.execute(sa.select(self.checks.c.status, sa.func.count()).group_by(self.checks.c.status)).all()
        counts = dict.fromkeys(STATUSES, 0)
        counts.update({str(status): int(n) for status, n in rows})
        return counts

    def duration_histogram(self, buckets: tuple[float, ...] = DURATION_BUCKETS) -> tuple[list[int], int, float]:
        """Finished checks' run times [s]: cumulative counts at ``buckets`` (then +Inf), the count and the sum."""
        seconds = self.checks.c.seconds
        columns = [sa.func.sum(sa.case((seconds <= b, 1), else_=0)) for b in buckets]
        with self.engine.connect() as conn:
            row = conn.execute(
                sa.select(*columns, sa.func.count(seconds), sa.func.coalesce(sa.func.sum(seconds), 0.0)).where(
                    seconds.is_not(None)
                )
            ).one()
        counts = [int(v or 0) for v in row[: len(buckets)]]
        return [*counts, int(row[-2])], int(row[-2]), float(row[-1])
