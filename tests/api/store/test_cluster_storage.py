"""The distributed mode's storage on PostgreSQL: claims, leases, recovery, guarded writes, schema races, retention."""

from __future__ import annotations

import datetime as dt
import json
import threading
from collections.abc import Iterator

import pytest
import sqlalchemy as sa
from apitools import database_at_version, unique_prefix
from clustertools import database_url

from api.store import SCHEMA_VERSION, CacheKeys, Store, exhausted_reason, utcnow


@pytest.fixture
def store() -> Iterator[Store]:
    s = Store(database_url(), unique_prefix())
    s.create_schema()
    yield s
    s.drop_schema()
    s.dispose()


def never_rerender(text: str, fail_on: str) -> tuple[str, str]:
    raise AssertionError("no report is re-rendered here")


def rerender_marked(text: str, fail_on: str) -> tuple[str, str]:
    return f'{{"fail_on": "{fail_on}", "of": {text}}}', "fail"


def test_share_answers_from_a_finished_check_across_keys(store: Store) -> None:
    keys = CacheKeys(request_key="r1", result_key="k1", fail_on="error", default_fail_on="error")
    store.create("origin", "robot.urdf", {"fail_on": "error"}, keys=keys)
    assert store.share("early", None, None, CacheKeys(request_key="r1"), "warning", never_rerender) is None
    follower = store.share("early", None, None, CacheKeys(request_key="r1"), None, never_rerender)
    assert follower is not None and follower.following and follower.record.status == "queued"
    assert store.claim("origin", "w", lease_s=60, max_attempts=3) is not None
    assert store.finish_ok("origin", '{"fail_on": "error"}', "robot", "pass", {"error": 0}, False, 2.0, owner="w")
    settled = store.get("early")
    assert settled is not None and (settled.status, settled.robot, settled.cached_from) == (
        "succeeded",
        "robot",
        "origin",
    )
    assert store.report("early") == '{"fail_on": "error"}'
    # by the result key alone (another body with the same files), with another fail_on
    shared = store.share(
        "later", "robot.urdf", {"fail_on": "warning"}, CacheKeys(result_key="k1"), "warning", rerender_marked
    )
    assert shared is not None and not shared.following
    assert (shared.record.status, shared.record.verdict, shared.record.cached_from) == ("succeeded", "fail", "origin")
    assert store.report("later") == '{"fail_on": "warning", "of": {"fail_on": "error"}}'
    # a cached check's request key leads to the origin too
    # an identical check in flight is shared only with the same fail_on (a follower takes its report as it is)
    store.create("third", "robot.urdf", {}, keys=CacheKeys(request_key="r2", fail_on="error", default_fail_on="error"))
    assert store.share("fourth", None, None, CacheKeys(request_key="r2"), "warning", never_rerender) is None
    with store.engine.begin() as conn:
        conn.execute(store.checks.update().where(store.checks.c.id == "later").values(request_key="r3"))
    via_cached = store.share("fifth", None, None, CacheKeys(request_key="r3"), None, never_rerender)
    assert via_cached is not None and via_cached.record.cached_from == "origin"
    assert via_cached.record.options == {"fail_on": "error"}


def test_a_finished_origin_is_preferred_and_names_the_report_holder(store: Store) -> None:
    keys = CacheKeys(request_key="r", result_key="k", fail_on="error", default_fail_on="error")
    store.create("origin", "robot.urdf", {}, keys=keys)
    assert store.claim("origin", "w", lease_s=60, max_attempts=3) is not None
    assert store.finish_ok("origin", '{"fail_on": "error"}', "robot", "pass", {"error": 0}, False, 2.0, owner="w")
    for n in range(60):  # every hit adds a row with the key; each still leads to the origin
        hit = store.share(f"hit{n}", None, None, CacheKeys(request_key="r"), None, never_rerender)
        assert hit is not None and (hit.following, hit.holder, hit.record.cached_from) == (False, "origin", "origin")
    # a newer run of the same request (cache=false) still in flight: the finished origin is preferred
    store.create("rerun", "robot.urdf", {}, keys=keys)
    hit = store.share("after", None, None, CacheKeys(request_key="r"), None, never_rerender)
    assert hit is not None and (hit.following, hit.holder) == (False, "origin")
    # found by the result key only while the request key has no finished origin
    store.create("other", "robot.urdf", {}, keys=CacheKeys(request_key="r9", fail_on="error"))
    hit = store.share("by-result", None, None, CacheKeys(request_key="r9", result_key="k"), None, never_rerender)
    assert hit is not None and (hit.following, hit.holder) == (False, "origin")
    # a re-rendered report is held by the new check itself
    hit = store.share("warn", None, None, CacheKeys(request_key="r"), "warning", rerender_marked)
    assert hit is not None and hit.holder == "warn" and hit.record.verdict == "fail"
    store.create("flight", "robot.urdf", {}, keys=CacheKeys(request_key="r8", fail_on="error"))
    follower = store.share("follow", None, None, CacheKeys(request_key="r8"), None, never_rerender)
    assert follower is not None and (follower.following, follower.holder) == (True, None)


def test_followers_fail_with_their_origin(store: Store) -> None:
    keys = CacheKeys(result_key="k", fail_on="error", default_fail_on="error")
    store.create("origin", "robot.urdf", {}, keys=keys)
    assert store.share("follower", "robot.urdf", {}, CacheKeys(result_key="k"), None, never_rerender) is not None
    assert store.claim("origin", "w", lease_s=60, max_attempts=3) is not None
    assert store.finish_failed("origin", 422, "malformed", 1.0, owner="w")
    record = store.get("follower")
    assert record is not None and (record.status, record.http_status, record.reason) == ("failed", 422, "malformed")
    assert store.share("after", "robot.urdf", {}, CacheKeys(result_key="k"), None, never_rerender) is None


def test_recovery_does_not_republish_followers(store: Store) -> None:
    store.create("origin", "robot.urdf", {}, keys=CacheKeys(result_key="k", fail_on="error"))
    assert store.share("follower", "robot.urdf", {}, CacheKeys(result_key="k"), "error", never_rerender) is not None
    ids, failed = store.recover_abandoned(max_attempts=3, requeue_after_s=-1.0)
    assert (ids, failed) == (["origin"], 0)


def expire(store: Store, check_id: str) -> None:
    """Move the lease of ``check_id`` into the past, as if its worker vanished."""
    with store.engine.begin() as conn:
        conn.execute(
            store.checks.update()
            .where(store.checks.c.id == check_id)
            .values(lease_until=utcnow() - dt.timedelta(seconds=1))
        )


def test_a_claim_is_exclusive_while_its_lease_lives(store: Store) -> None:
    store.create("a", "r.urdf", {}, upload="d" * 64, spec={"root_file": "tree/r.urdf"})
    first = store.claim("a", "w1:1:x", lease_s=60, max_attempts=3)
    assert first is not None
    assert (first.attempt, first.upload, first.spec) == (1, "d" * 64, {"root_file": "tree/r.urdf"})
    assert store.claim("a", "w2:2:y", lease_s=60, max_attempts=3) is None  # a duplicate message does nothing
    assert store.get("a").status == "running"  # type: ignore[union-attr]
    assert store.renew("a", "w1:1:x", 60) and not store.renew("a", "w2:2:y", 60)


def test_a_late_finisher_cannot_overwrite_a_check_taken_over(store: Store) -> None:
    store.create("a", "r.urdf", {})
    assert store.claim("a", "old", lease_s=60, max_attempts=3) is not None
    expire(store, "a")
    second = store.claim("a", "new", lease_s=60, max_attempts=3)
    assert second is not None and second.attempt == 2
    assert not store.renew("a", "old", 60)  # the old run learns it lost the check
    assert not store.finish_ok("a", '{"late": true}', "r", "pass", {"error": 0}, False, 1.0, owner="old")
    assert store.finish_ok("a", '{"new": true}', "r", "fail", {"error": 1}, False, 2.0, owner="new")
    assert not store.finish_failed("a", 500, "too late", owner="new")  # written once
    done = store.get("a")
    assert done is not None and (done.status, done.verdict, done.seconds) == ("succeeded", "fail", 2.0)
    assert store.report("a") == '{"new": true}'


def test_a_cancelled_check_keeps_its_status(store: Store) -> None:
    store.create("q", "r.urdf", {})
    store.create("r", "r.urdf", {})
    assert store.claim("r", "w", lease_s=60, max_attempts=3) is not None
    assert store.cancel("q") and store.cancel("r")
    assert not store.cancel("q")  # already finished
    assert store.claim("q", "w", lease_s=60, max_attempts=3) is None
    assert not store.renew("r", "w", 60)
    assert not store.finish_ok("r", "{}", "r", "pass", {}, False, 1.0, owner="w")
    for check_id in ("q", "r"):
        record = store.get(check_id)
        assert record is not None
        assert (record.status, record.http_status, record.reason) == (
            "cancelled",
            409,
            "cancelled by a DELETE request",
        )


def test_recovery_requeues_expired_leases_and_fails_after_max_attempts(store: Store) -> None:
    store.create("a", "r.urdf", {})
    for attempt in (1, 2):
        claim = store.claim("a", f"w{attempt}", lease_s=60, max_attempts=2)
        assert claim is not None and claim.attempt == attempt
        expire(store, "a")
        ids, failed = store.recover_abandoned(max_attempts=2, requeue_after_s=3600)
        if attempt == 1:
            assert (ids, failed) == (["a"], 0)
            assert store.get("a").status == "queued"  # type: ignore[union-attr]
    assert (ids, failed) == ([], 1)  # started twice, its worker lost twice: failed, never looping
    record = store.get("a")
    assert record is not None
    assert (record.status, record.http_status, record.reason) == ("failed", 422, exhausted_reason(2))
    assert store.claim("a", "w3", lease_s=60, max_attempts=2) is None


def test_recovery_republishes_long_queued_checks_once_per_period(store: Store) -> None:
    store.create("old", "r.urdf", {})
    store.create("new", "r.urdf", {})
    with store.engine.begin() as conn:
        conn.execute(
            store.checks.update()
            .where(store.checks.c.id == "old")
            .values(enqueued_at=utcnow() - dt.timedelta(seconds=120))
        )
    assert store.recover_abandoned(max_attempts=3, requeue_after_s=60) == (["old"], 0)
    assert store.recover_abandoned(max_attempts=3, requeue_after_s=60) == ([], 0)


def test_schema_creation_is_safe_when_replicas_start_at_once() -> None:
    url, prefix = database_url(), unique_prefix()
    stores = [Store(url, prefix) for _ in range(4)]
    found: list[int] = []
    errors: list[BaseException] = []
    start = threading.Barrier(len(stores))

    def create(store: Store) -> None:
        start.wait()
        try:
            found.append(store.create_schema())
        except BaseException as err:
            errors.append(err)

    threads = [threading.Thread(target=create, args=(s,)) for s in stores]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=60)
    try:
        assert errors == []
        assert sorted(found) == [0, SCHEMA_VERSION, SCHEMA_VERSION, SCHEMA_VERSION]  # created once
        with stores[0].engine.connect() as conn:
            versions = conn.execute(sa.select(stores[0].version_table.c.version)).scalars().all()
        assert versions == list(range(1, SCHEMA_VERSION + 1))  # every revision ran once, in order
    finally:
        stores[0].drop_schema()
        for s in stores:
            s.dispose()


def test_a_version_1_database_is_migrated() -> None:
    url, prefix = database_url(), unique_prefix()
    tables = database_at_version(url, prefix, 1)
    old = tables["checks"]
    engine = sa.create_engine(url)
    with engine.begin() as conn:
        conn.execute(
            old.insert().values(
                id="kept",
                status="succeeded",
                created_at=utcnow(),
                source="r.urdf",
                has_matrix=False,
                options="{}",
                report='{"kept": true}',
            )
        )
    engine.dispose()
    store = Store(url, prefix)
    try:
        assert store.create_schema() == 1
        assert store.schema_version() == SCHEMA_VERSION == 7
        columns = {c["name"] for c in sa.inspect(store.engine).get_columns(f"{prefix}checks")}
        assert "progress" in columns  # version 6
        assert {"fixes", "fixes_reason", "root"} <= columns  # version 7
        indexes = {i["name"]: i["column_names"] for i in sa.inspect(store.engine).get_indexes(f"{prefix}checks")}
        # version 4: the cache keys are indexed with the submission order, the key-only indexes are gone
        assert indexes[f"ix_{prefix}checks_request_key_seq"] == ["request_key", "seq"]
        assert indexes[f"ix_{prefix}checks_result_key_seq"] == ["result_key", "seq"]
        assert f"ix_{prefix}checks_request_key" not in indexes and f"ix_{prefix}checks_result_key" not in indexes
        kept = store.get("kept")
        assert kept is not None and kept.status == "succeeded"
        # version 5: the owning client; a check stored before it has none (only an admin sees it)
        assert kept.client is None
        assert indexes[f"ix_{prefix}checks_client_seq"] == ["client", "seq"]
        assert store.recent(10, client="alice") == ([], None)
        # version 4: the report text moved to its own table, the column is gone
        assert store.report("kept") == '{"kept": true}'
        assert "report" not in {c["name"] for c in sa.inspect(store.engine).get_columns(f"{prefix}checks")}
        store.create("new", "r.urdf", {}, upload="e" * 64, spec={})
        claim = store.claim("new", "w", lease_s=60, max_attempts=3)
        assert claim is not None and claim.attempt == 1 and claim.upload == "e" * 64
        store.finish_ok("new", '{"fail_on": "error"}', "r", "pass", {}, False, 1.0, owner="w")
        # version 3: the result cache's columns; a check of version 2 has no key and is never shared
        assert store.share("again", "r.urdf", {}, CacheKeys(request_key="k"), None, never_rerender) is None
    finally:
        store.drop_schema()
        store.dispose()


def test_retention_deletes_old_finished_checks_and_unused_uploads(store: Store) -> None:
    kept_blob = store.put_blob(b"kept upload")
    old_blob = store.put_blob(b"old upload")
    assert store.put_blob(b"kept upload") == kept_blob  # stored once by content
    assert store.get_blob(kept_blob) == b"kept upload"
    store.create("old", "r.urdf", {}, upload=old_blob)
    store.finish_failed("old", 422, "x")
    store.create("old-running", "r.urdf", {}, upload=old_blob)
    store.create("new", "r.urdf", {}, upload=kept_blob)
    store.finish_failed("new", 422, "x")
    long_ago = utcnow() - dt.timedelta(days=40)
    with store.engine.begin() as conn:
        conn.execute(
            store.checks.update().where(store.checks.c.id.in_(["old", "old-running"])).values(created_at=long_ago)
        )
        conn.execute(store.blobs.update().values(created_at=long_ago))
    assert store.delete_older_than(30 * 86400.0) == (1, 0)  # the unfinished one still uses the old upload
    assert store.get("old") is None and store.get("new") is not None
    assert store.cancel("old-running")
    assert store.delete_older_than(30 * 86400.0) == (1, 1)
    assert store.get_blob(old_blob) is None and store.get_blob(kept_blob) == b"kept upload"


def test_metrics_figures_come_from_the_database(store: Store) -> None:
    for i, seconds in enumerate((0.3, 1.5, 7.0)):
        store.create(f"c{i}", "r.urdf", {})
        store.finish_ok(f"c{i}", "{}", "r", "pass", {}, False, seconds)
    store.create("q", "r.urdf", {})
    counts = store.counts_by_status()
    assert counts == {"queued": 1, "running": 0, "succeeded": 3, "failed": 0, "cancelled": 0}
    cumulative, count, total = store.duration_histogram((1.0, 5.0))
    assert (cumulative, count) == ([1, 2, 3], 3)
    assert total == pytest.approx(8.8)


def test_a_worker_keeps_its_lease_while_it_verifies_the_fixes_and_a_lost_one_ends_them_failed(store: Store) -> None:
    """The report is stored succeeded with fixes 'verifying': the worker holds the lease (it
    renews it, writes progress, and ends the verification); when it vanishes, recovery ends
    the verification failed and leaves the report, and the check is not run again."""
    store.create("a", "r.urdf", {}, upload="u" * 64, spec={})
    assert store.claim("a", "w1", 60, 3) is not None
    assert store.finish_ok("a", '{"planned": true}', "r", "pass", {}, False, 1.0, owner="w1", fixes="verifying")
    record = store.get("a")
    assert record is not None and (record.status, record.fixes, record.progress) == ("succeeded", "verifying", None)
    assert store.renew("a", "w1", 60) and not store.renew("a", "w2", 60)
    assert store.set_progress("a", {"stage": "verifying safe fixes", "phase": "fixes"}, owner="w1")
    assert store.get("a").progress == {"stage": "verifying safe fixes", "phase": "fixes"}  # type: ignore[union-attr]
    assert store.claim("a", "w2", 60, 3) is None  # the check itself is done
    expire(store, "a")
    assert store.recover_abandoned(3, 3600) == ([], 0)  # nothing to run again
    record = store.get("a")
    assert record is not None and (record.status, record.fixes, record.progress) == ("succeeded", "failed", None)
    assert record.fixes_reason is not None and record.fixes_reason.startswith("the worker verifying the fixes was lost")
    assert json.loads(store.report("a") or "{}") == {"planned": True}  # the report stays, with the planned patches
    assert not store.finish_fixes("a", "verified", '{"verified": true}', owner="w1")  # too late: ended
    assert not store.renew("a", "w1", 60)


def test_a_follower_reads_its_origins_fixes_and_a_restart_ends_a_verification(store: Store) -> None:
    store.create("a", "r.urdf", {}, keys=CacheKeys(request_key="k", fail_on="error"))
    assert store.mark_running("a")
    assert store.finish_ok("a", '{"fail_on": "error"}', "r", "pass", {}, False, 1.0, fixes="verifying")
    shared = store.share("b", None, None, CacheKeys(request_key="k"), None, never_rerender)
    assert shared is not None and shared.record.fixes == "verifying"
    # a request asking another fail_on waits for no verification: it is checked on its own
    assert store.share("c", None, None, CacheKeys(request_key="k"), "warning", rerender_marked) is None
    assert store.interrupt_unfinished("the service restarted") == 0  # no check was unfinished...
    for check_id in ("a", "b"):  # ...but the verification was: its followers read it
        record = store.get(check_id)
        assert record is not None and (record.fixes, record.fixes_reason) == ("failed", "the service restarted")
