"""Caches: never compute the same thing twice.

:class:`~geomcheck.cache.store.Store` keeps results on disk under a key over everything they
depend on (:mod:`geomcheck.cache.keys`). The library caches only while a store is active:
``with using_store(open_store()): ...`` (the CLI does this unless ``--no-cache``; tests and
library callers that activate nothing compute everything, as before). Stages that cache:
the xacro expansion (:mod:`geomcheck.cache.xacro`) and the base revision's findings in
``geomcheck diff`` (:mod:`geomcheck.cache.reports`); :mod:`geomcheck.cache.result_key` keys
a whole report for the service.

This package imports only the standard library at import time (the CLI's cold start).
"""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Iterator

from geomcheck.cache.store import Store, default_cache_dir, open_store

_ACTIVE: contextvars.ContextVar[Store | None] = contextvars.ContextVar("geomcheck_cache_store", default=None)


def active_store() -> Store | None:
    """The store stages read and write in this context, ``None`` when caching is off."""
    return _ACTIVE.get()


@contextlib.contextmanager
def using_store(store: Store | None) -> Iterator[Store | None]:
    """Make ``store`` the active store (``None``: caching off) inside the ``with`` block."""
    token = _ACTIVE.set(store)
    try:
        yield store
    finally:
        _ACTIVE.reset(token)


__all__ = ["Store", "active_store", "default_cache_dir", "open_store", "using_store"]
