"""The API replica of the distributed mode: store the upload, record the check, publish its id.

A replica keeps nothing of its own: the upload goes to the database (by content), the
check's state lives in the database, the queue in the broker. Starting or stopping a
replica touches no check, and any replica answers for any check.
"""

from __future__ import annotations

import logging
import shutil
from concurrent.futures import Future
from pathlib import Path

from api.checks.blobs import JobSpec, pack
from api.checks.job import CheckJob
from api.checks.options import RawOptions
from api.checks.service import Finished, asked_options, poll_finished
from api.distributed.celery_app import broker_reachable, make_celery, publish
from api.errors import Overloaded, one_line
from api.settings import Settings
from api.store import CacheKeys, Store
from geomcheck.errors import GeomcheckError

log = logging.getLogger("geomcheck.api")


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

    def submit(
        self,
        job: CheckJob,
        workdir: Path,
        raw: RawOptions | None = None,
        keys: CacheKeys | None = None,
        root: dict[str, object] | None = None,
    ) -> Future[Finished] | None:
        """Store the arranged upload of ``workdir`` (then removed), record the check queued
        (found by identical submissions through ``keys``; ``root``: how its root file was
        chosen) and publish it."""
        try:
            spec = JobSpec.of(job, raw or RawOptions(), workdir)
            digest = self.store.put_blob(pack(workdir))
        finally:
            shutil.rmtree(workdir, ignore_errors=True)
        source = job.root_file.relative_to(job.display_root).as_posix()
        self.store.create(
            job.check_id,
            source,
            asked_options(job),
            upload=digest,
            spec=spec.as_json(),
            keys=keys,
            client=job.client,
            root=root,
        )
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
        return await poll_finished(self.store, check_id, self.settings.wait_s)
