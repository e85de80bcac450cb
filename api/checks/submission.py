"""What ``POST /v1/checks`` does with a request, from its body to a check in the queue.

A :class:`Submission` reads the body into a work folder of its own (made only for a body that
must be unpacked), answers from the result cache when it can (by the request's bytes before
unpacking, by the canonical upload after), and otherwise queues the check. Whatever fails on
the way, the place it took in the queue is given back and its work folder removed.
"""

from __future__ import annotations

import secrets
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fastapi import Request
from starlette.concurrency import run_in_threadpool

from api.checks.job import CheckJob
from api.checks.options import REQUEST_ONLY, RawOptions, request_config
from api.checks.service import Service, asked_options
from api.results.cache import fail_on_value, request_key, rerender, restamp, upload_keys
from api.store import CacheKeys, Shared
from api.uploads.body import Received, Upload, discard, receive, unpack_received
from api.uploads.layout import arrange
from api.uploads.tree import UploadLimits, UploadTree
from geomcheck.config import Config
from geomcheck.option_spec import parse_bool


@dataclass(frozen=True)
class Queued:
    """A check submitted to the service: its id and the future its outcome completes."""

    check_id: str
    future: Any


@dataclass
class Submission:
    """One ``POST /v1/checks``: its options (from the query string, before the body is read),
    its work folder and what the request asked of the cache and the fixes."""

    service: Service
    client: str
    root: str | None
    cache: bool
    verify_fixes: bool
    raw: RawOptions = field(default_factory=RawOptions)
    check_id: str = field(default_factory=lambda: secrets.token_urlsafe(16))
    _asked: Config | None = None
    _tree: UploadTree | None = None
    _reserved: bool = False

    @classmethod
    def from_query(
        cls, service: Service, query: Any, root: str | None, cache: bool, verify_fixes: bool, client: str
    ) -> Submission:
        """A submission with the query string's options; bad options are refused before the body is read."""
        submission = cls(service, client, root, cache, verify_fixes)
        submission.raw.add_pairs(((k, v) for k, v in query.multi_items() if k not in REQUEST_ONLY), "query")
        settings = service.settings
        submission._asked = request_config(submission.raw, settings.max_samples, settings.work_dir)
        return submission

    @property
    def workdir(self) -> Path:
        return self.service.settings.work_dir / self.check_id

    def tree(self) -> UploadTree:
        """The upload's tree, made the first time a body must be unpacked into it."""
        if self._tree is None:
            s = self.service.settings
            limits = UploadLimits(s.max_files, s.max_unpacked_bytes, s.max_ratio, s.max_path_length)
            self._tree = UploadTree(self.workdir / "tree", limits)
        return self._tree

    async def submit(self, request: Request) -> Shared | Queued:
        """The check answered from the cache (:class:`Shared`) or queued (:class:`Queued`)."""
        queued = None
        try:
            outcome = await self._submit(request)
            queued = outcome if isinstance(outcome, Queued) else None
            return outcome
        finally:
            if queued is None and self._reserved:
                self.service.release()
            if queued is None and self.workdir.exists():
                await run_in_threadpool(discard, self.workdir)

    async def _submit(self, request: Request) -> Shared | Queued:
        received = await receive(request, self.workdir, self.tree, self.raw, self.root)
        use_cache = self.cache and (received.cache is None or parse_bool(received.cache, "cache"))
        fast_key = self._request_key(received)
        if use_cache and fast_key is not None:
            shared = await self._share(CacheKeys(request_key=fast_key), fail_on_value(self._asked or Config()))
            if shared is not None:
                return shared
        upload = await unpack_received(received, self.tree, self.raw, self.root)
        job, keys, chosen = await run_in_threadpool(self._prepare, upload, fast_key)
        if use_cache and keys.result_key is not None:
            source = job.root_file.relative_to(job.display_root).as_posix()
            shared = await self._share(keys, fail_on_value(job.config), source, asked_options(job), chosen)
            if shared is not None:
                return shared
        # a place in the queue is taken once the body has arrived, so slow uploads hold none
        self.service.reserve()
        self._reserved = True
        future = await run_in_threadpool(self.service.submit, job, self.workdir, self.raw, keys, chosen)
        return Queued(self.check_id, future)

    def _request_key(self, received: Received) -> str | None:
        """The request key of a document or archive (its query holds every option); None for a form."""
        if received.sha256 is None:
            return None
        settings = self.service.settings
        return request_key(received.kind, received.sha256, self.root, self.raw, settings, self.verify_fixes)

    def _prepare(self, upload: Upload, fast_key: str | None) -> tuple[CheckJob, CacheKeys, dict[str, Any] | None]:
        """The check of an unpacked upload (its root chosen, its folders arranged), its cache
        keys and how its root was chosen."""
        settings = self.service.settings
        layout = arrange(upload.tree.root, upload.root, upload.srdf, settings.max_path_length)
        config = request_config(self.raw, settings.max_samples, layout.display_root, layout.srdf)
        job = CheckJob(
            self.check_id,
            layout.root_file,
            layout.display_root,
            layout.search_root,
            config,
            self.client,
            verify_fixes=self.verify_fixes,
        )
        chosen = layout.root_choice.to_dict() if layout.root_choice is not None else None
        return job, upload_keys(job, fast_key), chosen

    async def _share(
        self,
        keys: CacheKeys,
        fail_on: str | None,
        source: str | None = None,
        options: dict[str, object] | None = None,
        chosen: dict[str, Any] | None = None,
    ) -> Shared | None:
        """The check answered from an identical one the store knows by ``keys``, or None."""
        store = self.service.store
        return await run_in_threadpool(
            store.share, self.check_id, source, options, keys, fail_on, rerender, self.client, chosen, restamp
        )


__all__ = ["Queued", "Submission"]
