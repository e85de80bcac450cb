"""The result cache in the store: a new check answered from an identical earlier one, or
following an identical one still in flight and settled with it.

A finished origin's report is shared (re-rendered only when ``fail_on`` differs); a
follower is finished in the transaction that finishes its origin (:func:`settle_followers`,
called by every write that finishes a check). On PostgreSQL the lookup and the insert hold
an advisory lock on the key, so replicas agree.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from types import SimpleNamespace
from typing import Any

import sqlalchemy as sa
from sqlalchemy.engine import Connection

from api.store.database import Database
from api.store.schema import (
    FINISHED,
    SHARED_FIGURES,
    UNFINISHED,
    VERIFYING,
    CacheKeys,
    CheckRecord,
    Rerender,
    Shared,
    record_of,
    utcnow,
)


class ResultSharing(Database):
    """Finding the origin of a new check by its cache keys, and recording the new check."""

    def _find_origin(self, conn: Connection, keys: CacheKeys, client: str) -> Any:
        """The newest check with ``keys`` whose report can be shared: finished successfully
        (preferred, by either key, any client's) or still in flight (``client``'s own only: a
        check in flight can still be cancelled, and one client's cancel must not fail another
        client's check); a cached check leads to the check it came from.

        One indexed lookup per key and status group: each walks the key's rows newest first
        and stops at the first that leads to a usable origin, so its cost does not grow with
        the number of answers the key already had."""
        for finished in (True, False):
            for name, value in (("request_key", keys.request_key), ("result_key", keys.result_key)):
                if value is None:
                    continue
                found = conn.execute(self._origin_query(name, finished), {"key": value, "client": client}).first()
                if found is not None:
                    return found
        return None

    def _origin_query(self, key: str, finished: bool) -> Any:
        """The lookup of :meth:`_find_origin` by column ``key``, of succeeded (``finished``) or
        unfinished origins; built once: building a statement costs more than running it."""
        query = self._origin_queries.get((key, finished))
        if query is None:
            c, origin = self.checks.c, self.origin
            statuses = ("succeeded",) if finished else UNFINISHED
            query = self._origin_queries[(key, finished)] = (
                sa.select(
                    origin.c.id,
                    origin.c.status,
                    origin.c.fail_on,
                    origin.c.source,
                    origin.c.options,
                    origin.c.client,
                    origin.c.fixes,
                    origin.c.fixes_reason,
                    origin.c.root,
                    *(origin.c[name] for name in SHARED_FIGURES),
                    c.default_fail_on,
                )
                .join(origin, origin.c.id == sa.func.coalesce(c.cached_from, c.id))
                .where(c[key] == sa.bindparam("key"), origin.c.cached_from.is_(None), origin.c.status.in_(statuses))
                .order_by(c.seq.desc())
                .limit(1)
            )
            if not finished:
                query = self._origin_queries[(key, finished)] = query.where(origin.c.client == sa.bindparam("client"))
        return query

    def share(
        self,
        check_id: str,
        source: str | None,
        options: Mapping[str, Any] | None,
        keys: CacheKeys,
        fail_on: str | None,
        rerender: Rerender,
        client: str = "",
        root: Mapping[str, Any] | None = None,
        restamp: Callable[[str], str] | None = None,
    ) -> Shared | None:
        """Answer a new check ``check_id`` from the check with the same ``keys``, or None.

        A finished origin: the new check is recorded succeeded at once, sharing the origin's
        report (re-rendered by ``rerender`` when the effective ``fail_on``, the request's or
        else the upload's default, differs from the origin's). An origin in flight with the
        same ``fail_on``: the new check is recorded queued and settles with it. On PostgreSQL
        the lookup and the insert hold an advisory lock on the key, so replicas agree. The new
        check belongs to ``client``; an origin in flight is shared only with its own client.
        A finished origin whose fixes are still being verified is shared only where its report
        needs no re-rendering (the verified report replaces it; a copy would stay behind).
        ``root`` is how the new check's root file was chosen.
        ``source`` and ``options`` None (a request not unpacked yet): the origin's, with the
        asked ``fail_on``. A report of another client's check is written anew with this
        moment's time by ``restamp`` (that client's time is not shown).
        """
        with self._begin() as conn:
            self._lock_name(conn, f"geomcheck:{self.prefix}:{keys.result_key or keys.request_key or check_id}")
            found = self._find_origin(conn, keys, client)
            if found is None:
                return None
            effective = fail_on or found.default_fail_on or found.fail_on
            if effective != found.fail_on and (found.status != "succeeded" or found.fixes == VERIFYING):
                return None  # a check in flight, or a report about to be replaced, is not re-rendered
            if options is None:
                options = {**json.loads(found.options), "fail_on": fail_on or "error"}
            values = _new_check(check_id, found, source, options, keys, effective, client, root)
            if found.status != "succeeded":
                row, following, holder = {"status": "queued", "has_matrix": False, **values}, True, None
            else:
                foreign = restamp is not None and (found.client or "") != client
                report: str | None = None
                verdict, holder = found.verdict, found.id
                if effective != found.fail_on or foreign:  # the only cases that read the (large) report text
                    report, verdict = self._report_for(conn, found, effective, rerender, restamp if foreign else None)
                    holder = check_id
                row, following = _finished_row(found, values, verdict), False
            # parameters, not .values(): the compiled insert is then reused from SQLAlchemy's cache
            conn.execute(self.checks.insert(), row)
            if holder == check_id:
                conn.execute(self.reports.insert(), {"check_id": check_id, "report": report})
        return Shared(_shared_record(found, row), following, holder)

    def _report_for(
        self,
        conn: Connection,
        found: Any,
        fail_on: str,
        rerender: Rerender,
        restamp: Callable[[str], str] | None,
    ) -> tuple[str, str]:
        """The origin's report for a new check: re-rendered for its ``fail_on`` when that
        differs, written anew with this moment's time by ``restamp`` when given."""
        report = conn.execute(sa.select(self.reports.c.report).where(self.reports.c.check_id == found.id)).scalar_one()
        verdict = found.verdict
        if fail_on != found.fail_on:
            report, verdict = rerender(report, fail_on)
        if restamp is not None:
            report = restamp(report)
        return report, verdict


def _new_check(
    check_id: str,
    found: Any,
    source: str | None,
    options: Mapping[str, Any],
    keys: CacheKeys,
    fail_on: str,
    client: str,
    root: Mapping[str, Any] | None,
) -> dict[str, Any]:
    """The columns of a new check answered from origin ``found``, whatever its status."""
    now = utcnow()
    return {
        "id": check_id,
        "created_at": now,
        "enqueued_at": now,
        "source": source if source is not None else found.source,
        "options": json.dumps(options, sort_keys=True),
        "cached_from": found.id,
        "request_key": keys.request_key,
        "result_key": keys.result_key,
        "fail_on": fail_on,
        "default_fail_on": keys.default_fail_on or found.default_fail_on,
        "client": client,
        # the root of a request answered before its upload was unpacked: the origin's
        "root": json.dumps(dict(root), sort_keys=True) if root is not None else found.root,
    }


def _finished_row(found: Any, values: Mapping[str, Any], verdict: str) -> dict[str, Any]:
    """The row of a new check finished at once with origin ``found``'s figures."""
    now = values["created_at"]
    return {
        "status": "succeeded",
        "started_at": now,
        "finished_at": now,
        **{name: getattr(found, name) for name in SHARED_FIGURES},
        "verdict": verdict,
        **values,
    }


def _shared_record(found: Any, row: Mapping[str, Any]) -> CheckRecord:
    """The :class:`CheckRecord` of the new check just inserted as ``row``."""
    unset = dict.fromkeys(
        ("started_at", "finished_at", "robot", "verdict", "errors", "http_status", "reason", "progress", "fixes")
    )
    origin = {"origin_client": found.client, "origin_fixes": found.fixes, "origin_fixes_reason": found.fixes_reason}
    return record_of(SimpleNamespace(**{**unset, "seconds": None, "fixes_reason": None, **origin, **row}))


def settle_followers(conn: Connection, checks: sa.Table) -> None:
    """Finish the checks that follow an origin which has finished, as it finished."""
    c = checks.c
    origin = checks.alias("origin")
    rows = conn.execute(
        sa.select(
            c.id,
            origin.c.id.label("origin_id"),
            origin.c.status,
            *(origin.c[name] for name in SHARED_FIGURES),
            origin.c.http_status,
            origin.c.reason,
        )
        .join(origin, origin.c.id == c.cached_from)
        .where(c.status.in_(UNFINISHED), origin.c.status.in_(FINISHED))
    ).all()
    now = utcnow()
    for row in rows:
        values: dict[str, Any] = {
            "started_at": sa.func.coalesce(c.started_at, now),
            "finished_at": now,
            "lease_until": None,
        }
        if row.status == "succeeded":
            values.update(status="succeeded", **{name: getattr(row, name) for name in SHARED_FIGURES})
        elif row.status == "failed":
            values.update(status="failed", http_status=row.http_status, reason=row.reason)
        else:
            reason = f"the identical check {row.origin_id} this one shared was cancelled; submit it again"
            values.update(status="failed", http_status=503, reason=reason)
        conn.execute(checks.update().where(c.id == row.id, c.status.in_(UNFINISHED)).values(**values))
