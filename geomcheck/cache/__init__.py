"""Caches: never compute the same thing twice.

:class:`~geomcheck.cache.store.Store` keeps results on disk under a key over everything they
depend on (:mod:`geomcheck.cache.keys`). The library caches only while a store is active:
``with using_store(open_store()): ...`` (the CLI does this unless ``--no-cache``; tests and
library callers that activate nothing compute everything, as before). Stages that cache:
the xacro expansion (:mod:`geomcheck.load.xacro_cache`), each link's fit
(:mod:`geomcheck.geometry.fit_cache`, stored as :mod:`geomcheck.cache.records`) and the base
revision's findings in ``geomcheck diff`` (:mod:`geomcheck.diff_cache`);
:mod:`api.results.key` keys a whole report for the service. Other stages (mesh
triangles and hulls, tessellated primitives and their solids, the inertia family's hulls
(:mod:`geomcheck.geometry.hull_cache`), collision meshes' hulls
(:mod:`geomcheck.collision.support_cache`), the default pose's contacts
(:mod:`geomcheck.selfcollision.contacts_cache`), each link's coverage at rest and views
entry (:mod:`geomcheck.checks.coverage_cache`, :mod:`geomcheck.checks.views_cache`)) use
:func:`cached` or :func:`cached_arrays`.

This package imports only the standard library at import time (the CLI's cold start).
"""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Callable, Iterator, Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from geomcheck.cache.keys import code_fingerprint, library_versions
from geomcheck.cache.store import Store, decode_arrays, default_cache_dir, encode_arrays, open_store

if TYPE_CHECKING:
    import numpy as np

T = TypeVar("T")

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


def cached(
    namespace: str,
    key_parts: Any,
    compute: Callable[[], T],
    encode: Callable[[T], bytes],
    decode: Callable[[bytes], T],
) -> T:
    """A stage's result from the active store, keyed by ``key_parts`` (anything
    :func:`geomcheck.cache.keys.canonical` takes: the content digests and settings the result
    depends on) together with geomcheck's code and the libraries' versions; ``compute()``d
    (and stored) on a miss, and always when no store is active."""
    store = active_store()
    if store is None:
        return compute()
    return store.get_or_compute(namespace, stage_parts(key_parts), compute, encode, decode)


def stage_parts(key_parts: Any) -> list[Any]:
    """A stage's full key: ``key_parts`` with geomcheck's code and the libraries' versions."""
    return [code_fingerprint(), library_versions(), key_parts]


def cached_arrays(
    namespace: str, key_parts: Any, compute: Callable[[], Mapping[str, np.ndarray]]
) -> Mapping[str, np.ndarray]:
    """:func:`cached` for a result that is named numeric arrays (stored as ``.npz``, no pickles),
    e.g. a mesh's hull vertices and faces, bounding boxes and surface samples keyed by the
    mesh file's sha256 and the scale."""
    return cached(namespace, key_parts, compute, encode_arrays, decode_arrays)


__all__ = [
    "Store",
    "active_store",
    "cached",
    "cached_arrays",
    "default_cache_dir",
    "open_store",
    "stage_parts",
    "using_store",
]
