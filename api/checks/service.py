"""The check service: queue, sandboxed runs, results into the store, work folders cleaned.

Two implementations answer the routers (:class:`Service`): :class:`CheckService`, the
embedded default, and :class:`api.distributed.dispatch.QueuedCheckService`, an API replica
of the distributed mode that enqueues checks for ``geomcheck worker`` processes.

In the embedded service, ``submit`` takes an upload already arranged on disk; a bounded
thread pool (one thread per worker slot) runs each check in its own limited process
through :class:`SandboxRunner` and writes the outcome to the :class:`Store` before the
returned future completes. A background thread deletes checks older than the retention.
"""

from __future__ import annotations

import asyncio
import fcntl
import logging
import shutil
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Protocol

from starlette.concurrency import run_in_threadpool

from api.checks.job import FIXES_FAILED, FIXES_VERIFIED, CheckJob, CheckResult, run_job
from api.checks.options import RawOptions, check_options
from api.checks.progress import ProgressWriter
from api.checks.sandbox import (
    CANCELLED_REASON,
    CANCELLED_STATUS,
    Outcome,
    ProcessLimits,
    SandboxRunner,
    clean_environment,
)
from api.errors import Overloaded
from api.settings import Settings
from api.store import FINISHED, CacheKeys, CheckRecord, Store
from geomcheck.cache.store import CACHE_DIR_ENV
from geomcheck.errors import UsageError
from geomcheck.pipeline import options_summary

log = logging.getLogger("geomcheck.api")

RESTART_REASON = "the service restarted before this check finished; submit it again"
LOCK_FILE = "service.lock"
POLL_FIRST_S = 0.05  # first wait between two looks at a check a POST waits for [s]
POLL_MAX_S = 0.5  # the wait doubles up to this [s]


def lock_data_dir(data_dir: Path) -> IO[bytes]:
    """Hold an exclusive lock on ``data_dir`` for as long as the returned file stays open.

    One service per data folder: a second one would delete the first one's uploads and
    record its checks as interrupted. :class:`UsageError` when another service holds it.
    """
    data_dir.mkdir(parents=True, exist_ok=True)
    handle = (data_dir / LOCK_FILE).open("ab")
    try:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        handle.close()
        raise UsageError(f"another geomcheck service is using the data folder {data_dir}") from None
    return handle


@dataclass(frozen=True)
class Finished:
    """A check that ran: its stored record and, when it failed, the HTTP status and reason."""

    record: CheckRecord
    outcome: Outcome


class Service(Protocol):
    """What the routers need of a check service, embedded or distributed."""

    settings: Settings
    store: Store

    def start(self) -> None: ...
    def stop(self) -> None: ...
    def reserve(self) -> None: ...
    def release(self) -> None: ...
    def submit(
        self,
        job: CheckJob,
        workdir: Path,
        raw: RawOptions,
        keys: CacheKeys | None = None,
        root: dict[str, object] | None = None,
    ) -> Future[Finished] | None: ...
    async def wait_finished(self, check_id: str, future: Future[Finished] | None) -> Finished | None: ...
    def cancel(self, check_id: str) -> bool: ...
    def readiness(self) -> dict[str, bool]: ...

    @property
    def pending(self) -> int: ...
    @property
    def running(self) -> int: ...


def asked_options(job: CheckJob) -> dict[str, object]:
    """The options the request asked for (a configuration file in the upload may add to them)."""
    options = check_options(job.config)
    asked = options_summary(options)
    asked["fail_on"] = options.fail_on.value
    asked["select"] = list(options.selection.select)
    asked["ignore"] = list(options.selection.ignore)
    if options.srdf is not None:
        asked["srdf"] = options.srdf.relative_to(job.display_root).as_posix()
    return asked


def check_environment(settings: Settings, workdir: Path) -> dict[str, str]:
    """The environment of a check process: its temporary files land in its work folder
    (removed with it), its stage caches in ``settings.stage_cache_dir`` when one is set."""
    extra = {"HOME": str(workdir), "TMPDIR": str(workdir)}
    if settings.stage_cache_dir is not None:
        extra[CACHE_DIR_ENV] = str(settings.stage_cache_dir.absolute())
    return clean_environment(extra)


def finished_of(store: Store, record: CheckRecord) -> Finished:
    """The :class:`Finished` of a stored finished check (its report read from the store)."""
    if record.status == "succeeded":
        result = CheckResult(
            report_json=store.report(record.id) or "{}",
            robot=record.robot or "",
            source=record.source,
            verdict=record.verdict or "",
            summary=record.summary or {},
            has_matrix=record.has_matrix,
        )
        return Finished(record, Outcome(True, value=result, seconds=record.seconds or 0.0))
    status = CANCELLED_STATUS if record.status == "cancelled" else (record.http_status or 500)
    return Finished(record, Outcome(False, status=status, reason=record.reason or "", seconds=record.seconds or 0.0))


async def poll_finished(store: Store, check_id: str, wait_s: float) -> Finished | None:
    """The check once the store says it finished, or None when it has not within ``wait_s`` [s]."""
    deadline = time.monotonic() + wait_s
    pause = POLL_FIRST_S
    while True:
        record = await run_in_threadpool(store.get, check_id)
        if record is not None and record.status in FINISHED:
            return await run_in_threadpool(finished_of, store, record)
        if time.monotonic() + pause > deadline:
            return None
        await asyncio.sleep(pause)
        pause = min(pause * 2, POLL_MAX_S)


def store_outcome(store: Store, check_id: str, outcome: Outcome, owner: str | None = None) -> bool:
    """Record how a check process ended (by the embedded service, or by the worker run holding
    the lease, ``owner``); False (nothing written) when the check was finished, cancelled or
    taken over meanwhile."""
    if outcome.ok:
        result: CheckResult = outcome.value
        return store.finish_ok(
            check_id,
            result.report_json,
            result.robot,
            result.verdict,
            result.summary,
            result.has_matrix,
            outcome.seconds,
            owner=owner,
            fixes=result.fixes,
        )
    log.info("check %s failed (%d): %s", check_id, outcome.status, outcome.reason)
    return store.finish_failed(check_id, outcome.status, outcome.reason, outcome.seconds, owner=owner)


class ReportFirst:
    """A check run's two results: the report, stored (and answered) as soon as the check
    process hands it over while the offered fixes are verified, and then how the
    verification ended. Used by the embedded service and by the distributed workers alike."""

    def __init__(self, store: Store, check_id: str, owner: str | None = None) -> None:
        self.store = store
        self.check_id = check_id
        self.owner = owner
        self.started = time.monotonic()
        self.reported = False
        self.on_report: Callable[[Outcome], None] | None = None
        self.sink: ProgressWriter | None = None

    def early(self, result: CheckResult) -> None:
        """The report, before the verification of its fixes: stored with fixes ``verifying``."""
        outcome = Outcome(True, value=result, seconds=time.monotonic() - self.started)
        if self.sink is not None:
            self.sink.discard()  # the check's last stage is not the verification's progress
        self.reported = store_outcome(self.store, self.check_id, outcome, self.owner)
        if self.reported and self.on_report is not None:
            self.on_report(outcome)

    def finish(self, outcome: Outcome) -> bool:
        """Record how the run ended: the check's outcome, or once its report is out the end of
        its fixes' verification (verified: the report with the verified patches; anything else
        leaves the planned patches, with why)."""
        if not self.reported:
            return store_outcome(self.store, self.check_id, outcome, self.owner)
        if outcome.ok:
            result: CheckResult = outcome.value
            return self.store.finish_fixes(
                self.check_id, result.fixes or FIXES_VERIFIED, result.report_json, owner=self.owner
            )
        log.info("verifying the fixes of check %s failed (%d): %s", self.check_id, outcome.status, outcome.reason)
        return self.store.finish_fixes(self.check_id, FIXES_FAILED, reason=outcome.reason, owner=self.owner)


class RetentionLoop:
    """Deletes checks older than ``settings.retention_days`` every ``retention_interval_s`` in a thread."""

    def __init__(self, settings: Settings, store: Store) -> None:
        self.settings = settings
        self.store = store
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self) -> None:
        if self.settings.retention_days <= 0:
            return
        self._thread = threading.Thread(target=self._loop, name="geomcheck-retention", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=10)

    def _loop(self) -> None:
        while True:
            try:
                delete_old_checks(self.settings, self.store)
            except Exception:  # the database may be away for a while; try again next time
                log.exception("retention: deleting old checks failed")
            if self._stop.wait(self.settings.retention_interval_s):
                return


def delete_old_checks(settings: Settings, store: Store) -> tuple[int, int]:
    """Delete finished checks (and unused uploads) older than the retention; returns (checks, uploads)."""
    checks, uploads = store.delete_older_than(settings.retention_days * 86400.0)
    if checks or uploads:
        log.info(
            "retention: deleted %d checks and %d uploads older than %g days", checks, uploads, settings.retention_days
        )
    return checks, uploads


class CheckService:
    """Accepts checks up to ``workers + max_queued`` at once and runs ``workers`` of them side by side."""

    def __init__(self, settings: Settings, store: Store) -> None:
        self.settings = settings
        self.store = store
        self.runner = SandboxRunner(
            ProcessLimits(
                cpu_s=settings.check_cpu_s,
                memory_bytes=settings.check_memory_bytes,
                wall_s=settings.check_timeout_s,
                file_bytes=settings.check_file_bytes,
            )
        )
        self.target: Callable[[CheckJob], CheckResult] = run_job  # what a check process runs
        self._threads = ThreadPoolExecutor(max_workers=settings.workers, thread_name_prefix="geomcheck-check")
        self._lock = threading.Lock()
        self._pending = 0
        self._active: set[str] = set()  # ids of the checks this service accepted and has not finished
        self._cancels: dict[str, threading.Event] = {}  # of the checks running now
        self._lock_file: IO[bytes] | None = None
        self.retention = RetentionLoop(settings, store)

    def start(self) -> None:
        """Lock the data folder, prepare storage (schema, interrupted checks), the work folder and the forkserver."""
        self._lock_file = lock_data_dir(self.settings.data_dir)
        try:
            self.store.create_schema()
            interrupted = self.store.interrupt_unfinished(RESTART_REASON)
            if interrupted:
                log.warning("marked %d unfinished checks failed after a restart", interrupted)
            work = self.settings.work_dir
            if work.exists():
                shutil.rmtree(work, ignore_errors=True)
            work.mkdir(parents=True, exist_ok=True)
            self.runner.warm()
            self.retention.start()
        except BaseException:
            self._lock_file.close()
            self._lock_file = None
            raise

    def stop(self) -> None:
        """Kill running checks, drop queued ones, record them failed, release the database and the data folder."""
        self.retention.stop()
        self.runner.stop()
        self._threads.shutdown(wait=True, cancel_futures=True)
        with self._lock:
            unfinished = sorted(self._active)
        self.store.fail_unfinished(unfinished, 503, RESTART_REASON)
        self.store.dispose()
        if self._lock_file is not None:
            self._lock_file.close()
            self._lock_file = None

    @property
    def pending(self) -> int:
        """Checks queued or running."""
        with self._lock:
            return self._pending

    @property
    def running(self) -> int:
        """Check processes running now."""
        return self.runner.running

    def readiness(self) -> dict[str, bool]:
        return {"database": self.store.ping()}

    def cancel(self, check_id: str) -> bool:
        """Cancel a queued or running check (its process is killed); False when it had finished."""
        if not self.store.cancel(check_id):
            return False
        with self._lock:
            event = self._cancels.get(check_id)
        if event is not None:
            event.set()
        return True

    async def wait_finished(self, check_id: str, future: Future[Finished] | None) -> Finished | None:
        """The check once it finished: its future, or for a check that follows an identical one
        (no future of its own) the store, for at most ``settings.wait_s``."""
        if future is None:
            return await poll_finished(self.store, check_id, self.settings.wait_s)
        return await asyncio.wrap_future(future)

    def reserve(self) -> None:
        """Take a queue place for a new check; :class:`Overloaded` when the queue is full."""
        with self._lock:
            if self._pending >= self.settings.workers + self.settings.max_queued:
                raise Overloaded(f"{self._pending} checks are queued or running; try again shortly")
            self._pending += 1

    def release(self) -> None:
        with self._lock:
            self._pending -= 1

    def submit(
        self,
        job: CheckJob,
        workdir: Path,
        raw: RawOptions | None = None,
        keys: CacheKeys | None = None,
        root: dict[str, object] | None = None,
    ) -> Future[Finished]:
        """Record ``job`` as queued (found by identical submissions through ``keys``; ``root``:
        how its root file was chosen) and start it when a worker is free. The future is done
        once the check has its report (its fixes may still be verified) or failed.

        Call :meth:`reserve` first. Once this returns, the check owns the reservation and
        ``workdir`` (both released when it ends); when it raises, the caller still does.
        """
        answered: Future[Finished] = Future()
        try:
            source = job.root_file.relative_to(job.display_root).as_posix()
            self.store.create(job.check_id, source, asked_options(job), keys=keys, client=job.client, root=root)
            with self._lock:
                self._active.add(job.check_id)
            future = self._threads.submit(self._run, job, workdir, answered)
        except BaseException:  # the caller still owns the reservation and the work folder
            with self._lock:
                self._active.discard(job.check_id)
            raise
        future.add_done_callback(lambda _f: self.release())
        return answered

    def _run(self, job: CheckJob, workdir: Path, answered: Future[Finished] | None = None) -> Finished:
        answered = answered if answered is not None else Future()
        cancel = threading.Event()
        with self._lock:
            self._cancels[job.check_id] = cancel
        try:
            if not self.store.mark_running(job.check_id):  # cancelled while it waited
                outcome = Outcome(False, status=CANCELLED_STATUS, reason=CANCELLED_REASON)
            else:
                env = check_environment(self.settings, workdir)
                sink = ProgressWriter(self.store, job.check_id)
                run = ReportFirst(self.store, job.check_id)
                run.on_report = lambda early: self._answer(answered, job.check_id, early)
                run.sink = sink
                outcome = self.runner.run(self.target, job, workdir, env, cancel, sink, run.early)
                run.finish(outcome)  # once the report is out, answered already: this ends its fixes' verification
            self._answer(answered, job.check_id, outcome)
            return answered.result()
        except BaseException as err:
            if not answered.done():
                answered.set_exception(err)
            raise
        finally:
            with self._lock:
                self._active.discard(job.check_id)
                self._cancels.pop(job.check_id, None)
            shutil.rmtree(workdir, ignore_errors=True)

    def _answer(self, answered: Future[Finished], check_id: str, outcome: Outcome) -> None:
        """Settle the check's future with ``outcome`` and its stored record (once: the report, or how it ended)."""
        if answered.done():
            return
        record = self.store.get(check_id)
        assert record is not None
        if record.status == "cancelled":
            outcome = Outcome(False, status=CANCELLED_STATUS, reason=CANCELLED_REASON, seconds=outcome.seconds)
        answered.set_result(Finished(record, outcome))
