"""Leases of the distributed mode: a worker run claims a check, renews its lease while it runs,
and checks whose worker vanished are requeued (or failed after too many attempts)."""

from __future__ import annotations

import datetime as dt
import json

import sqlalchemy as sa

from api.store.database import Database
from api.store.schema import VERIFYING, Claim, utcnow
from api.store.sharing import settle_followers

KILLED_STATUS = 422  # as api.checks.sandbox: the input cannot be processed within the limits
LOST_VERIFIER = "the worker verifying the fixes was lost (killed, or out of memory); the planned patches stay"


def exhausted_reason(max_attempts: int) -> str:
    return (
        f"the check was started {max_attempts} times and its worker was lost each time "
        "(killed, or out of memory); it is not tried again"
    )


class Leases(Database):
    """Claims, renewals and recovery of checks run by ``geomcheck worker`` processes."""

    def _fail_exhausted(self, where: sa.ColumnElement[bool], max_attempts: int, now: dt.datetime) -> sa.Update:
        """The update failing the checks matching ``where`` already started ``max_attempts`` times."""
        return (
            self.checks.update()
            .where(where, self.checks.c.attempts >= max_attempts)
            .values(
                status="failed",
                finished_at=now,
                http_status=KILLED_STATUS,
                reason=exhausted_reason(max_attempts),
                lease_until=None,
            )
        )

    def claim(self, check_id: str, owner: str, lease_s: float, max_attempts: int) -> Claim | None:
        """Take ``check_id`` for ``owner`` with a lease of ``lease_s`` [s].

        Possible when it is queued, or running under a lease that expired (its worker
        vanished). None when there is nothing to do: finished, cancelled, unknown, or held
        by a live lease. A check already started ``max_attempts`` times is failed instead.
        """
        now = utcnow()
        c = self.checks.c
        takeable = sa.and_(
            c.id == check_id,
            sa.or_(c.status == "queued", sa.and_(c.status == "running", c.lease_until < now)),
        )
        with self._begin() as conn:
            exhausted = conn.execute(self._fail_exhausted(takeable, max_attempts, now)).rowcount
            if exhausted:
                settle_followers(conn, self.checks)
                return None
            row = conn.execute(
                self.checks.update()
                .where(takeable)
                .values(
                    status="running",
                    started_at=now,
                    owner=owner,
                    lease_until=now + dt.timedelta(seconds=lease_s),
                    attempts=c.attempts + 1,
                )
                .returning(c.attempts, c.upload, c.spec)
            ).first()
        if row is None:
            return None
        return Claim(check_id, int(row.attempts), row.upload, json.loads(row.spec) if row.spec else {})

    def renew(self, check_id: str, owner: str, lease_s: float) -> bool:
        """Extend ``owner``'s lease, while it runs the check or verifies its fixes; False when it
        lost the check (cancelled, or taken over after expiry)."""
        c = self.checks.c
        held = sa.or_(c.status == "running", sa.and_(c.status == "succeeded", c.fixes == VERIFYING))
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(c.id == check_id, c.owner == owner, held)
                .values(lease_until=utcnow() + dt.timedelta(seconds=lease_s))
            )
            return bool(result.rowcount)

    def recover_abandoned(self, max_attempts: int, requeue_after_s: float) -> tuple[list[str], int]:
        """Checks to publish again, and how many abandoned ones were failed.

        A running check whose lease expired lost its worker: back to ``queued`` (or
        ``failed`` once started ``max_attempts`` times). A succeeded check whose fixes were
        being verified under an expired lease keeps its report, with the planned patches: the
        verification failed. A check queued for longer than
        ``requeue_after_s`` [s] may have lost its message (a broker restarted without
        persistence): it is published again; a duplicate message finds it taken and does
        nothing. Each row changes in one statement, so of several recovering nodes only one
        acts on it.
        """
        now = utcnow()
        c = self.checks.c
        expired = sa.and_(c.status == "running", c.lease_until < now)
        with self._begin() as conn:
            conn.execute(
                self.checks.update()
                .where(c.status == "succeeded", c.fixes == VERIFYING, c.lease_until < now)
                .values(fixes="failed", fixes_reason=LOST_VERIFIER, lease_until=None, progress=None)
            )
            failed = conn.execute(self._fail_exhausted(expired, max_attempts, now)).rowcount
            requeued = conn.execute(
                self.checks.update()
                .where(expired)
                .values(status="queued", owner=None, lease_until=None, enqueued_at=now, progress=None)
                .returning(c.id)
            ).scalars()
            ids = list(requeued)
            stale = conn.execute(
                self.checks.update()
                .where(
                    c.status == "queued",
                    c.cached_from.is_(None),
                    c.enqueued_at < now - dt.timedelta(seconds=requeue_after_s),
                )
                .values(enqueued_at=now)
                .returning(c.id)
            ).scalars()
            ids.extend(stale)
            if failed:
                settle_followers(conn, self.checks)
        return sorted(set(ids)), int(failed or 0)
