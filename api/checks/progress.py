"""A running check's progress, from its sandboxed process into the store.

The check process sends its stages up its result pipe (:mod:`api.checks.sandbox`); the thread
waiting on it (the embedded service's, or a distributed worker's) hands them to a
:class:`ProgressWriter`, which writes the newest to the check's row at most once every
``min_interval_s``: any API process or replica reads it from there for ``GET /v1/checks/{id}``.
"""

from __future__ import annotations

import logging
import time
from typing import Any, Protocol

import sqlalchemy as sa

from api.errors import one_line

log = logging.getLogger("geomcheck.api")

PROGRESS_WRITE_S = 0.5  # the newest progress of a check is written at most this often [s]


class ProgressStore(Protocol):
    def set_progress(self, check_id: str, stage: dict[str, Any], owner: str | None = None) -> bool: ...


class ProgressWriter:
    """Writes the progress of ``check_id`` (held by ``owner`` in the distributed mode) to ``store``."""

    def __init__(
        self, store: ProgressStore, check_id: str, owner: str | None = None, min_interval_s: float = PROGRESS_WRITE_S
    ) -> None:
        self.store = store
        self.check_id = check_id
        self.owner = owner
        self.min_interval_s = min_interval_s
        self._pending: dict[str, Any] | None = None
        self._last = -float("inf")

    def report(self, stage: dict[str, Any]) -> None:
        """The check's newest stage; written now or at a later :meth:`flush`."""
        self._pending = stage
        self.flush()

    def discard(self) -> None:
        """Forget the stage not written yet (a phase of the run ended)."""
        self._pending = None

    def flush(self) -> None:
        """Write the newest stage not written yet, unless the last write was too recent."""
        if self._pending is None or time.monotonic() - self._last < self.min_interval_s:
            return
        stage, self._pending = self._pending, None
        self._last = time.monotonic()
        try:
            self.store.set_progress(self.check_id, stage, owner=self.owner)
        except sa.exc.SQLAlchemyError as err:  # progress is a courtesy: the check goes on without it
            log.warning("writing the progress of check %s failed: %s", self.check_id, one_line(err))
