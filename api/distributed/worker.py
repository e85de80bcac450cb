"""``geomcheck worker``: a Celery worker that runs checks in the sandbox, with leases and recovery.

**Pool.** Celery's prefork children are daemonic and cannot start processes through
:mod:`multiprocessing`, which the sandbox needs. The worker uses the ``threads`` pool
instead: ``--concurrency N`` threads, each waiting on one check process forked from the
worker's forkserver (the library already imported), exactly as the embedded service runs
them. The checks' CPU work happens in those processes, so threads do not share a GIL with
it; starting a sandbox with ``subprocess`` instead would pay the library's import (about
2.5 s on the reference machine) on every check, against a few milliseconds for a fork.

**Leases.** A task claims its check in the database with a lease of ``lease_s`` and
renews it every third of that while the check runs; a cancelled check (or one taken over
after the lease expired) fails the renewal and its process is killed. Every worker runs
:class:`Recovery`: a check whose lease expired (its worker vanished) goes back to the queue,
or fails after ``max_attempts`` starts; a check queued for ``requeue_after_s`` is published
again in case the broker lost its message.
"""

from __future__ import annotations

import ctypes
import logging
import os
import re
import secrets
import shutil
import signal
import socket
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import sqlalchemy as sa
from celery import Celery
from celery.signals import beat_embedded_init

from api.checks.blobs import JobSpec, unpack
from api.checks.job import CheckJob, CheckResult, run_job
from api.checks.progress import ProgressWriter
from api.checks.sandbox import Outcome, ProcessLimits, SandboxRunner
from api.checks.service import ReportFirst, check_environment, delete_old_checks
from api.distributed.celery_app import RETENTION, RUN_CHECK, check_distributed, make_celery, publish
from api.distributed.deadletters import publish_dead_letter
from api.errors import one_line
from api.settings import Settings
from api.store import Claim, Store
from geomcheck.errors import GeomcheckError

log = logging.getLogger("geomcheck.worker")

_PR_SET_PDEATHSIG = 1  # prctl option: the signal a process gets when its parent dies
DB_RETRY_S = 10.0  # a task that could not reach the database runs again after [s]
DB_RETRIES = 60  # then the check stays queued and Recovery publishes it again later [count]
CHECK_ID = re.compile(r"[A-Za-z0-9_-]{1,32}")  # what the API's ids are made of (secrets.token_urlsafe)


def limits_of(settings: Settings) -> ProcessLimits:
    return ProcessLimits(
        cpu_s=settings.check_cpu_s,
        memory_bytes=settings.check_memory_bytes,
        wall_s=settings.check_timeout_s,
        file_bytes=settings.check_file_bytes,
    )


class Heartbeat:
    """Renews a lease every third of ``lease_s`` [s]; sets ``lost`` when the check is no longer ours."""

    def __init__(self, store: Store, check_id: str, owner: str, lease_s: float) -> None:
        self.store = store
        self.check_id = check_id
        self.owner = owner
        self.lease_s = lease_s
        self.lost = threading.Event()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, name=f"lease-{check_id[:8]}", daemon=True)

    def __enter__(self) -> Heartbeat:
        self._thread.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self._stop.set()
        self._thread.join(timeout=self.lease_s)

    def _loop(self) -> None:
        while not self._stop.wait(self.lease_s / 3):
            try:
                if not self.store.renew(self.check_id, self.owner, self.lease_s):
                    log.info("check %s was cancelled or taken over; stopping it", self.check_id)
                    self.lost.set()
                    return
            except sa.exc.SQLAlchemyError as err:  # keep trying; an expired lease lets another worker take over
                log.warning("renewing the lease of check %s failed: %s", self.check_id, one_line(err))


class CheckWorker:
    """What a worker process holds: the store, the sandbox runner and this process's name."""

    def __init__(self, settings: Settings, store: Store, name: str | None = None) -> None:
        self.settings = settings
        self.store = store
        self.name = name or f"{socket.gethostname()}:{os.getpid()}"
        self.runner = SandboxRunner(limits_of(settings))
        self.target: Callable[[CheckJob], CheckResult] = run_job  # what a check process runs

    def run(self, check_id: str) -> str:
        """Run ``check_id`` if this worker can claim it; returns what happened (for the log)."""
        owner = f"{self.name}:{secrets.token_hex(4)}"
        claim = self.store.claim(check_id, owner, self.settings.lease_s, self.settings.max_attempts)
        if claim is None:
            return "not claimed (finished, cancelled, unknown or held by a live lease)"
        workdir = self.settings.work_dir / f"{check_id}.{claim.attempt}.{owner.rsplit(':', 1)[-1]}"
        run = ReportFirst(self.store, check_id, owner)  # the report is stored as soon as it exists
        run.sink = ProgressWriter(self.store, check_id, owner)
        try:
            with Heartbeat(self.store, check_id, owner, self.settings.lease_s) as heartbeat:
                outcome = self._execute(claim, workdir, heartbeat.lost, run.sink, run.early)
        finally:
            shutil.rmtree(workdir, ignore_errors=True)
        if not outcome.ok and self.runner.stopping and not run.reported:
            return "stopped with the worker; the lease will expire and the check run again"
        return self._store(run, outcome)

    def _execute(
        self,
        claim: Claim,
        workdir: Path,
        lost: threading.Event,
        sink: ProgressWriter,
        early: Callable[[CheckResult], None] | None = None,
    ) -> Outcome:
        try:
            data = self.store.get_blob(claim.upload) if claim.upload else None
            if data is None:
                return Outcome(False, status=500, reason="the check's stored upload is missing")
            unpack(data, workdir)
            job = JobSpec.from_json(claim.spec).job(claim.check_id, workdir, self.settings.max_samples)
        except GeomcheckError as err:
            return Outcome(False, status=err.http_status, reason=one_line(err))
        env = check_environment(self.settings, workdir)
        return self.runner.run(self.target, job, workdir, env, lost, sink, early)

    def _store(self, run: ReportFirst, outcome: Outcome) -> str:
        if not run.finish(outcome):
            return "finished, but the check was cancelled or taken over meanwhile: result dropped"
        if run.reported:
            fixes = "verified" if outcome.ok else f"not verified ({outcome.status}): {outcome.reason}"
            return f"succeeded; its fixes {fixes}"
        return "succeeded" if outcome.ok else f"failed ({outcome.status}): {outcome.reason}"


class Recovery:
    """Every ``lease_s / 2`` [s]: requeue or fail abandoned checks, republish long-queued ones."""

    def __init__(self, settings: Settings, store: Store, app: Celery) -> None:
        self.settings = settings
        self.store = store
        self.app = app
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, name="geomcheck-recovery", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=10)

    def sweep(self) -> list[str]:
        """One pass; returns the ids published again."""
        ids, failed = self.store.recover_abandoned(self.settings.max_attempts, self.settings.requeue_after_s)
        if failed:
            log.warning("recovery: %d checks failed after %d lost workers", failed, self.settings.max_attempts)
        for check_id in ids:
            publish(self.app, self.settings, check_id)
        if ids:
            log.warning("recovery: published %d abandoned or long-queued checks again: %s", len(ids), ", ".join(ids))
        return ids

    def _loop(self) -> None:
        while not self._stop.wait(self.settings.lease_s / 2):
            try:
                self.sweep()
            except Exception as err:  # the database or the broker may be away for a while
                log.warning("recovery pass failed: %s", one_line(err))


def register_tasks(app: Celery, worker: CheckWorker) -> None:
    """The two tasks of a worker: run one check, and delete old checks (scheduled by beat)."""

    @app.task(name=RUN_CHECK, bind=True, max_retries=DB_RETRIES)  # type: ignore[untyped-decorator]
    def run_check(self: Any, check_id: str) -> str:
        if not isinstance(check_id, str) or not CHECK_ID.fullmatch(check_id):
            reason = f"the check id is not one: {check_id!r}"[:200]
            log.error("rejected a malformed message on queue %s (%s)", worker.settings.queue, reason)
            publish_dead_letter(app, worker.settings.queue, repr(check_id), reason, self.request.headers)
            return "rejected: " + reason
        try:
            what = worker.run(check_id)
        except sa.exc.OperationalError as err:  # the database is away: the message comes back later
            raise self.retry(countdown=DB_RETRY_S, exc=err) from None
        log.info("check %s: %s", check_id, what)
        return what

    @app.task(name=RETENTION)  # type: ignore[untyped-decorator]
    def retention() -> tuple[int, int]:
        return delete_old_checks(worker.settings, worker.store)


def remove_stale_folders(work_dir: Path, older_than_s: float) -> None:
    """Work folders left by a killed worker (on this machine) older than ``older_than_s`` [s]."""
    if not work_dir.is_dir():
        return
    cutoff = time.time() - older_than_s
    for entry in work_dir.iterdir():
        try:
            if entry.is_dir() and entry.stat().st_mtime < cutoff:
                shutil.rmtree(entry, ignore_errors=True)
        except OSError:
            continue


def beat_dies_with(worker: int) -> Callable[..., None]:
    """What the embedded beat runs as it starts: Celery forks it as a process of its own (the
    threads pool has no other way), which outlived a worker killed with SIGKILL; asked to get
    SIGKILL when its parent dies, it goes with the worker (``worker`` is the worker's pid: a
    parent already gone is no longer it)."""

    def die_with_worker(**_: Any) -> None:
        try:
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):  # elsewhere than on Linux: nothing to ask
            return
        if os.getppid() != worker:
            os.kill(os.getpid(), signal.SIGKILL)

    return die_with_worker


def run_worker(concurrency: int, beat: bool = False, loglevel: str = "INFO") -> None:
    """Run a worker until it is stopped (SIGTERM: finish the running checks first)."""
    settings = Settings()
    check_distributed(settings)
    store = Store(settings.database, settings.table_prefix)
    store.create_schema()
    settings.work_dir.mkdir(parents=True, exist_ok=True)
    remove_stale_folders(settings.work_dir, 2 * settings.check_timeout_s)
    app = make_celery(settings)
    worker = CheckWorker(settings, store)
    register_tasks(app, worker)
    worker.runner.warm()
    recovery = Recovery(settings, store, app)
    recovery.start()
    argv = [
        "worker",
        "--pool=threads",
        f"--concurrency={concurrency}",
        f"--queues={settings.queue}",
        f"--hostname=geomcheck-{os.getpid()}@%h",
        "--without-gossip",
        "--without-mingle",
        f"--loglevel={loglevel}",
    ]
    if beat:
        argv += ["--beat", f"--schedule={settings.data_dir / 'celerybeat-schedule'}"]
        beat_embedded_init.connect(beat_dies_with(os.getpid()), weak=False)
    try:
        app.worker_main(argv)
    finally:
        recovery.stop()
        worker.runner.stop()
        store.dispose()
