"""Link pictures kept across runs: the ``views`` section entry of a link, backed by the
active store.

An entry (:meth:`geomcheck.checks.views.Drawer.link_views`) is a function of the link's
visual and collision shapes (geometry, origin, order), the primitives the fit family
suggests for it, the content (sha256) of every mesh file the shapes name and the run's
thresholds (the views' precision; the load limits the meshes were read under); the store
adds geomcheck's code and the libraries' versions. A link with a mesh that did not load is
drawn afresh each run (its entry names the problem).
"""

from __future__ import annotations

import json
import logging
from collections.abc import Callable, Sequence
from typing import Any

from geomcheck.cache import active_store, cached
from geomcheck.cache.keys import canonical, every_digest
from geomcheck.model import Link, Mesh

log = logging.getLogger("geomcheck.cache")

NAMESPACE = "link-views"
FORMAT = 1


def views_key(
    link: Link, suggested: Sequence[Any], digest: Callable[[Mesh], str | None], settings: Any
) -> list[Any] | None:
    """The key parts of ``link``'s entry, ``None`` when it is not to be stored (a mesh that
    did not load, or a part no key can hold)."""
    shapes = (*link.visuals, *link.collisions)
    digests = every_digest((s.geometry for s in shapes if isinstance(s.geometry, Mesh)), digest)
    if digests is None:
        return None
    try:
        return [
            FORMAT,
            canonical([(s.geometry, s.origin) for s in link.visuals]),
            canonical([(s.geometry, s.origin) for s in link.collisions]),
            canonical(list(suggested)),
            digests,
            canonical(settings),
        ]
    except TypeError as err:
        log.debug("cache: views of %s not cached: %s", link.name, err)
        return None


def encode_entry(entry: dict[str, Any]) -> bytes:
    return json.dumps(entry, separators=(",", ":"), ensure_ascii=False).encode("utf-8")


def decode_entry(payload: bytes) -> dict[str, Any]:
    entry = json.loads(payload)
    if not isinstance(entry, dict):
        raise ValueError("a views entry is a JSON object")
    return entry


def stored_link_views(
    link: Link,
    suggested: Sequence[Any],
    draw: Callable[[], dict[str, Any]],
    digest: Callable[[Mesh], str | None],
    settings: Any,
) -> dict[str, Any]:
    """``draw()`` (``link``'s views entry), read from the active store when it holds it."""
    if active_store() is None:
        return draw()
    key = views_key(link, suggested, digest, settings)
    if key is None:
        return draw()
    return cached(NAMESPACE, key, draw, encode_entry, decode_entry)


__all__ = ["NAMESPACE", "stored_link_views", "views_key"]
