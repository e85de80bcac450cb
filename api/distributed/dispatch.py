"""The API replica of the distributed mode: store the upload, record the check, publish its id.

A replica keeps nothing of its own: the upload goes to the database (by content), the
check's state lives in the database, the queue in the broker. Starting or stopping a
replica touches no check, and any replica answers for any check.
"""

from __future__ import annotations

import asyncio
import logging
import shutil
import time
from concurrent.futures import Future
from pathlib import Path

from starlette.concurrency import run_in_threadpool

from api.blobs import JobSpec, pack
from api.distributed.celery_app import broker_reachable, make_celery, publish
from api.errors import Overloaded, one_line
from api.job import CheckJob, CheckResult
from api.options import RawOptions
from api.sandbox import CANCELLED_STATUS, Outcome
from api.service import Finished, asked_options
from api.settings import Settings
from api.storage import FINISHED, CheckRecord, Store
from geomcheck.errors import GeomcheckError

log = logging.getLogger("geomcheck.api")

POLL_FIRST_S = 0.05  # first wait between two looks at a check a POST waits for [s]
POLL_MAX_S = 0.5  # the wait doubles up to this [s]


class BrokerUnavailable(GeomcheckError):
    """The broker did not accept a check."""

    http_status = 503


class QueuedCheckService:
    """An API replica: checks are run by ``geomcheck worker`` processes on any machine."""

    def __init__(self, settings: Settings, store: Store) -> None:
        self.settings = settings
        self.store = store
        self.celery = make_celery(settings)

    def start(self) -> None:
        """Create or migrate the schema (safe when replicas start at once); nothing else: no lock, no recovery."""
        self.store.create_schema()
        self.settings.work_dir.mkdir(parents=True, exist_ok=True)

    def stop(self) -> None:
        self.celery.close()
        self.store.dispose()

    @property
    def pending(self) -> int:
        """Checks queued or running, in the whole deployment."""
        return self.store.count_unfinished()

    @property
    def running(self) -> int:
        return self.store.counts_by_status()["running"]

    def readiness(self) -> dict[str, bool]:
        return {"database": self.store.ping(), "broker": broker_reachable(self.settings)}

    def reserve(self) -> None:
        """:class:`Overloaded` when ``max_queued`` checks are already queued or running."""
        pending = self.store.count_unfinished()
        if pending >= self.settings.max_queued:
            raise Overloaded(f"{pending} checks are queued or running; try again shortly")

    def release(self) -> None:
        return None

    def submit(self, job: CheckJob, workdir: Path, raw: RawOptions | None = None) -> Future[Finished] | None:
        """Store the arranged upload of ``workdir`` (then removed), record the check queued and publish it."""
        try:
            spec = JobSpec.of(job, raw or RawOptions(), workdir)
            digest = self.store.put_blob(pack(workdir))
        finally:
            shutil.rmtree(workdir, ignore_errors=True)
        source = job.root_file.relative_to(job.display_root).as_posix()
        self.store.create(job.check_id, source, asked_options(job), upload=digest, spec=spec.as_json())
        try:
            publish(self.celery, self.settings, job.check_id)
        except Exception as err:
            reason = one_line(f"the broker did not accept the check: {type(err).__name__}: {err}")
            self.store.finish_failed(job.check_id, 503, reason)
            raise BrokerUnavailable(reason) from None
        return None

    def cancel(self, check_id: str) -> bool:
        """Cancel a queued or running check; its worker notices at its next lease renewal and kills it."""
        return self.store.cancel(check_id)

    async def wait_finished(self, check_id: str, future: Future[Finished] | None) -> Finished | None:
        """The finished check, or None when it has not finished within ``settings.wait_s``."""
        deadline = time.monotonic() + self.settings.wait_s
        pause = POLL_FIRST_S
        while True:
            record = await run_in_threadpool(self.store.get, check_id)
            if record is not None and record.status in FINISHED:
                return await run_in_threadpool(self._finished, record)
            if time.monotonic() + pause > deadline:
                return None
            await asyncio.sleep(pause)
            pause = min(pause * 2, POLL_MAX_S)

    def _finished(self, record: CheckRecord) -> Finished:
        if record.status == "succeeded":
            text = self.store.report(record.id) or "{}"
            result = CheckResult(
                report_json=text,
                robot=record.robot or "",
                source=record.source,
                verdict=record.verdict or "",
                summary=record.summary or {},
                has_matrix=record.has_matrix,
            )
            return Finished(record, Outcome(True, value=result, seconds=record.seconds or 0.0))
        status = CANCELLED_STATUS if record.status == "cancelled" else (record.http_status or 500)
        return Finished(
            record, Outcome(False, status=status, reason=record.reason or "", seconds=record.seconds or 0.0)
        )
