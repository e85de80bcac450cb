"""The check service: queue, sandboxed runs, results into the store, work folders cleaned.

``submit`` takes an upload already arranged on disk; a bounded thread pool (one thread
per worker slot) runs each check in its own limited process through :class:`SandboxRunner`
and writes the outcome to the :class:`Store` before the returned future completes.
"""

from __future__ import annotations

import fcntl
import logging
import shutil
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import IO

from api.errors import Overloaded
from api.job import CheckJob, CheckResult, run_job
from api.options import check_options
from api.sandbox import Outcome, ProcessLimits, SandboxRunner, clean_environment
from api.settings import Settings
from api.storage import CheckRecord, Store
from geomcheck.errors import UsageError
from geomcheck.pipeline import options_summary

log = logging.getLogger("geomcheck.api")

RESTART_REASON = "the service restarted before this check finished; submit it again"
LOCK_FILE = "service.lock"


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
        self._lock_file: IO[bytes] | None = None

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
        except BaseException:
            self._lock_file.close()
            self._lock_file = None
            raise

    def stop(self) -> None:
        """Kill running checks, drop queued ones, record them failed, release the database and the data folder."""
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

    def reserve(self) -> None:
        """Take a queue place for a new check; :class:`Overloaded` when the queue is full."""
        with self._lock:
            if self._pending >= self.settings.workers + self.settings.max_queued:
                raise Overloaded(f"{self._pending} checks are queued or running; try again shortly")
            self._pending += 1

    def release(self) -> None:
        with self._lock:
            self._pending -= 1

    def submit(self, job: CheckJob, workdir: Path) -> Future[Finished]:
        """Record ``job`` as queued and start it when a worker is free.

        Call :meth:`reserve` first. Once this returns, the check owns the reservation and
        ``workdir`` (both released when it ends); when it raises, the caller still does.
        """
        try:
            self.store.create(job.check_id, job.root_file.relative_to(job.display_root).as_posix(), self._asked(job))
            with self._lock:
                self._active.add(job.check_id)
            future = self._threads.submit(self._run, job, workdir)
        except BaseException:  # the caller still owns the reservation and the work folder
            with self._lock:
                self._active.discard(job.check_id)
            raise
        future.add_done_callback(lambda _f: self.release())
        return future

    @staticmethod
    def _asked(job: CheckJob) -> dict[str, object]:
        """The options the request asked for (a configuration file in the upload may add to them)."""
        options = check_options(job.config)
        asked = options_summary(options)
        asked["fail_on"] = options.fail_on.value
        asked["select"] = list(options.selection.select)
        asked["ignore"] = list(options.selection.ignore)
        if options.srdf is not None:
            asked["srdf"] = options.srdf.relative_to(job.display_root).as_posix()
        return asked

    def _run(self, job: CheckJob, workdir: Path) -> Finished:
        try:
            self.store.mark_running(job.check_id)
            # temporary files and caches of the check land in its work folder, removed with it
            env = clean_environment({"HOME": str(workdir), "TMPDIR": str(workdir)})
            outcome = self.runner.run(self.target, job, workdir, env)
            if outcome.ok:
                result: CheckResult = outcome.value
                self.store.finish_ok(
                    job.check_id,
                    result.report_json,
                    result.robot,
                    result.verdict,
                    result.summary,
                    result.has_matrix,
                    outcome.seconds,
                )
            else:
                log.info("check %s failed (%d): %s", job.check_id, outcome.status, outcome.reason)
                self.store.finish_failed(job.check_id, outcome.status, outcome.reason, outcome.seconds)
            record = self.store.get(job.check_id)
            assert record is not None
            return Finished(record, outcome)
        finally:
            with self._lock:
                self._active.discard(job.check_id)
            shutil.rmtree(workdir, ignore_errors=True)
