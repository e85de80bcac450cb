"""A small process pool for the collision matrix: both cores, deterministic results.

Collision objects cannot be pickled, so the pool is forked after the shared state (robot,
scene, samples) is in place and every task reads it from :func:`shared`. Tasks are mapped in
order and their results come back in order, so the merge never depends on timing. Where
fork is unavailable, or one worker is asked for, tasks run in this process. The pool is
forked on the first map of two tasks or more: a matrix whose pairs are all settled before
sampling (certified, adjacent) pays no fork and no pool shutdown.
"""

from __future__ import annotations

import gc
import multiprocessing
from collections.abc import Callable, Iterable
from types import TracebackType
from typing import Any, TypeVar

T = TypeVar("T")
R = TypeVar("R")

_SHARED: Any = None


def shared() -> Any:
    """The state given to the running :class:`Workers` (in the parent and in every worker)."""
    return _SHARED


class Workers:
    """``with Workers(state, processes) as w: w.map(task, items)``."""

    def __init__(self, state: Any, processes: int) -> None:
        self.state = state
        self.processes = max(1, int(processes))
        self._pool: Any = None
        self._forkable = self.processes > 1 and "fork" in multiprocessing.get_all_start_methods()

    def __enter__(self) -> Workers:
        global _SHARED
        _SHARED = self.state
        return self

    def _start(self) -> None:
        # Frozen objects are skipped by the collector: the children do not touch (and so
        # copy) every page of the parent's heap on their first collection.
        gc.freeze()
        self._pool = multiprocessing.get_context("fork").Pool(self.processes)

    def __exit__(
        self, kind: type[BaseException] | None, value: BaseException | None, trace: TracebackType | None
    ) -> None:
        global _SHARED
        if self._pool is not None:
            self._pool.terminate()
            self._pool.join()
            self._pool = None
            gc.unfreeze()
        _SHARED = None

    @property
    def parallel(self) -> bool:
        return self._pool is not None

    def map(self, task: Callable[[T], R], items: Iterable[T]) -> list[R]:
        """``[task(item) for item in items]``, spread over the processes, in order."""
        items = list(items)
        if not self._forkable or len(items) < 2:
            return [task(item) for item in items]
        if self._pool is None:
            self._start()
        return list(self._pool.map(task, items, chunksize=1))
