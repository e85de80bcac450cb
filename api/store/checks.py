"""Checks' rows: recording a check, its state changes, its outcome, reading checks and reports.

Every result write is guarded by the check's current status (and, in the distributed mode,
by the lease owner: :meth:`CheckRows._writable`), so a late finisher never overwrites a
cancelled or re-run check. The report is read only through :meth:`CheckRows.report`: a
check answered from the result cache (``cached_from``) has no report of its own, or one
that differs from its origin's only in ``fail_on``, and reads its origin's through one join.
"""

from __future__ import annotations

import datetime as dt
import json
from collections.abc import Mapping
from typing import Any

import sqlalchemy as sa

from api.store.database import Database
from api.store.schema import (
    FINISHED,
    STATUSES,
    UNFINISHED,
    VERIFYING,
    CacheKeys,
    CheckRecord,
    decode_cursor,
    encode_cursor,
    record_of,
    utcnow,
)
from api.store.sharing import settle_followers
from geomcheck.errors import UsageError


class CheckRows(Database):
    """The checks of a store: created queued, run, finished, read, deleted when old."""

    def create(
        self,
        check_id: str,
        source: str,
        options: Mapping[str, Any],
        upload: str | None = None,
        spec: Mapping[str, Any] | None = None,
        keys: CacheKeys | None = None,
        client: str = "",
        root: Mapping[str, Any] | None = None,
    ) -> None:
        """Record a queued check owned by ``client``; ``upload`` (a blob digest) and ``spec`` are
        what a remote worker needs, ``keys`` what identical submissions will find it by, ``root``
        how its root file was chosen (:class:`api.uploads.roots.RootChoice`)."""
        now = utcnow()
        keys = keys or CacheKeys()
        with self._begin() as conn:
            conn.execute(
                self.checks.insert().values(
                    id=check_id,
                    status="queued",
                    created_at=now,
                    enqueued_at=now,
                    source=source,
                    options=json.dumps(options, sort_keys=True),
                    has_matrix=False,
                    upload=upload,
                    spec=json.dumps(spec, sort_keys=True) if spec is not None else None,
                    request_key=keys.request_key,
                    result_key=keys.result_key,
                    fail_on=keys.fail_on,
                    default_fail_on=keys.default_fail_on,
                    client=client,
                    root=json.dumps(dict(root), sort_keys=True) if root is not None else None,
                )
            )

    def mark_running(self, check_id: str) -> bool:
        """queued -> running (the embedded service); False when the check is no longer queued."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id, self.checks.c.status == "queued")
                .values(status="running", started_at=utcnow(), attempts=self.checks.c.attempts + 1)
            )
            return bool(result.rowcount)

    def _writable(self, check_id: str, owner: str | None) -> Any:
        """Rows a result may be written to: the check while unfinished, and held by ``owner`` when given."""
        condition = sa.and_(self.checks.c.id == check_id, self.checks.c.status.in_(UNFINISHED))
        if owner is not None:
            condition = sa.and_(condition, self.checks.c.owner == owner, self.checks.c.status == "running")
        return condition

    def _finish(self, conn: sa.Connection, check_id: str, owner: str | None, **values: Any) -> bool:
        """Write a check's final ``values``; a finished check holds no lease and no progress,
        unless its fixes are still being verified (its worker keeps the lease for that).
        False (nothing written) when it was finished, cancelled or taken over."""
        update = self.checks.update().where(self._writable(check_id, owner))
        if values.get("fixes") != VERIFYING:
            values = {**values, "lease_until": None}
        result = conn.execute(update.values(**values, finished_at=utcnow(), progress=None))
        return bool(result.rowcount)

    def finish_ok(
        self,
        check_id: str,
        report_json: str,
        robot: str,
        verdict: str,
        summary: Mapping[str, int],
        has_matrix: bool,
        seconds: float,
        owner: str | None = None,
        fixes: str | None = None,
    ) -> bool:
        """Store the report, and the state of its offered ``fixes`` (``verifying``: they are
        verified next, :meth:`finish_fixes` ends that); False (nothing written) when the check
        was finished, cancelled or taken over."""
        with self._begin() as conn:
            finished = self._finish(
                conn,
                check_id,
                owner,
                status="succeeded",
                fixes=fixes,
                robot=robot,
                verdict=verdict,
                errors=summary.get("error", 0),
                warnings=summary.get("warning", 0),
                infos=summary.get("info", 0),
                has_matrix=has_matrix,
                seconds=seconds,
            )
            if finished:
                conn.execute(self.reports.insert(), {"check_id": check_id, "report": report_json})
            settle_followers(conn, self.checks)
            return finished

    def finish_failed(
        self, check_id: str, http_status: int, reason: str, seconds: float | None = None, owner: str | None = None
    ) -> bool:
        """Record the failure; False (nothing written) when the check was finished, cancelled or taken over."""
        with self._begin() as conn:
            finished = self._finish(
                conn, check_id, owner, status="failed", http_status=http_status, reason=reason, seconds=seconds
            )
            settle_followers(conn, self.checks)
            return finished

    def finish_fixes(
        self,
        check_id: str,
        state: str,
        report_json: str | None = None,
        reason: str | None = None,
        owner: str | None = None,
    ) -> bool:
        """End the verification of a succeeded check's fixes: its ``state`` (verified, or failed
        with ``reason``) and, when verified, the report holding the verified patches in place of
        the planned ones. False (nothing written) when they were not being verified (by ``owner``)."""
        c = self.checks.c
        condition = sa.and_(c.id == check_id, c.status == "succeeded", c.fixes == VERIFYING)
        if owner is not None:
            condition = sa.and_(condition, c.owner == owner)
        with self._begin() as conn:
            done = conn.execute(
                self.checks.update()
                .where(condition)
                .values(fixes=state, fixes_reason=reason, lease_until=None, progress=None)
            ).rowcount
            if done and report_json is not None:
                conn.execute(
                    self.reports.update().where(self.reports.c.check_id == check_id).values(report=report_json)
                )
            return bool(done)

    def set_progress(self, check_id: str, stage: Mapping[str, Any], owner: str | None = None) -> bool:
        """Record how far a running check (or the verification of a succeeded one's fixes) has
        come, held by ``owner`` when given; False when it is no longer running (finished,
        cancelled, or taken over)."""
        c = self.checks.c
        running = sa.or_(c.status == "running", sa.and_(c.status == "succeeded", c.fixes == VERIFYING))
        condition = sa.and_(c.id == check_id, running)
        if owner is not None:
            condition = sa.and_(condition, c.owner == owner)
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update().where(condition).values(progress=json.dumps(dict(stage), sort_keys=True))
            )
            return bool(result.rowcount)

    def cancel(self, check_id: str) -> bool:
        """queued or running -> cancelled; False when the check had already finished."""
        with self._begin() as conn:
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.id == check_id, self.checks.c.status.in_(UNFINISHED))
                .values(
                    status="cancelled",
                    finished_at=utcnow(),
                    http_status=409,
                    reason="cancelled by a DELETE request",
                    lease_until=None,
                )
            )
            settle_followers(conn, self.checks)
            return bool(result.rowcount)

    def interrupt_unfinished(self, reason: str) -> int:
        """Mark every queued or running check failed with ``reason``, and every verification of
        fixes failed (after a restart); returns how many checks."""
        with self._begin() as conn:
            self._fail_verifications(conn, self.checks.c.fixes == VERIFYING, reason)
            result = conn.execute(
                self.checks.update()
                .where(self.checks.c.status.in_(UNFINISHED))
                .values(status="failed", finished_at=utcnow(), http_status=503, reason=reason)
            )
            return int(result.rowcount or 0)

    def _fail_verifications(self, conn: sa.Connection, where: Any, reason: str) -> None:
        """The verifications of fixes matching ``where`` end failed: their reports keep the planned patches."""
        c = self.checks.c
        conn.execute(
            self.checks.update()
            .where(where, c.status == "succeeded", c.fixes == VERIFYING)
            .values(fixes="failed", fixes_reason=reason, lease_until=None, progress=None)
        )

    def fail_unfinished(self, check_ids: list[str], http_status: int, reason: str) -> None:
        """Mark those of ``check_ids`` still queued or running failed with ``reason``, and the
        verification of their fixes when it was still going."""
        if not check_ids:
            return
        with self._begin() as conn:
            self._fail_verifications(conn, self.checks.c.id.in_(check_ids), reason)
            conn.execute(
                self.checks.update()
                .where(self.checks.c.id.in_(check_ids), self.checks.c.status.in_(UNFINISHED))
                .values(status="failed", finished_at=utcnow(), http_status=http_status, reason=reason)
            )
            settle_followers(conn, self.checks)

    def get(self, check_id: str) -> CheckRecord | None:
        with self.engine.connect() as conn:
            row = conn.execute(self._record_by_id, {"check_id": check_id}).first()
        return record_of(row) if row is not None else None

    def report(self, check_id: str) -> str | None:
        """The stored JSON report text, exactly as written (None when there is none): the
        check's own, or for a check answered from the cache the report of its origin."""
        c = self.checks.c
        own, shared = self.reports.alias("own"), self.reports.alias("shared")
        query = (
            sa.select(sa.func.coalesce(own.c.report, shared.c.report))
            .select_from(
                self.checks.outerjoin(own, own.c.check_id == c.id).outerjoin(shared, shared.c.check_id == c.cached_from)
            )
            .where(c.id == check_id)
        )
        with self.engine.connect() as conn:
            return conn.execute(query).scalar()

    def report_holder(self, check_id: str) -> str | None:
        """The id of the check whose row holds ``check_id``'s report text (itself, or its origin)."""
        with self.engine.connect() as conn:
            return conn.execute(self._holder_by_id, {"check_id": check_id}).scalar()

    def recent(
        self, limit: int, cursor: str | None = None, status: str | None = None, client: str | None = None
    ) -> tuple[list[CheckRecord], str | None]:
        """Newest checks first, ``limit`` per page, only ``client``'s when given; returns the page
        and the cursor of the next one."""
        query = self._with_origin_client(sa.select(*self._columns())).order_by(self.checks.c.seq.desc())
        query = query.limit(limit + 1)
        if client is not None:
            query = query.where(self.checks.c.client == client)
        if cursor:
            query = query.where(self.checks.c.seq < decode_cursor(cursor))
        if status is not None:  # an empty status is no status: refused, not ignored
            if status not in STATUSES:
                raise UsageError.bad_choice("status", status, STATUSES)
            query = query.where(self.checks.c.status == status)
        with self.engine.connect() as conn:
            rows = conn.execute(query).all()
        page = rows[:limit]
        next_cursor = encode_cursor(page[-1].seq) if len(rows) > limit and page else None
        return [record_of(r) for r in page], next_cursor

    def delete_older_than(self, age_s: float) -> tuple[int, int]:
        """Delete checks created more than ``age_s`` [s] ago (reports with them) and uploads no check
        refers to any more; returns (checks, uploads) deleted. Unfinished checks are kept."""
        cutoff = utcnow() - dt.timedelta(seconds=age_s)
        c = self.checks.c
        with self._begin() as conn:
            shared = sa.select(c.cached_from).where(c.cached_from.is_not(None), c.created_at >= cutoff)
            old = sa.and_(c.created_at < cutoff, c.status.in_(FINISHED), c.id.not_in(shared))
            conn.execute(self.reports.delete().where(self.reports.c.check_id.in_(sa.select(c.id).where(old))))
            checks = conn.execute(self.checks.delete().where(old)).rowcount
            referenced = sa.select(c.upload).where(c.upload.is_not(None))
            uploads = conn.execute(
                self.blobs.delete().where(self.blobs.c.digest.not_in(referenced), self.blobs.c.created_at < cutoff)
            ).rowcount
        return int(checks or 0), int(uploads or 0)
