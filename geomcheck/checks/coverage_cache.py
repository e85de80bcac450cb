"""A link's coverage at rest kept across runs: the share of its visual surface within the
tolerance of its own collision elements or of an adjacent link's at the joint's zero
position (:func:`geomcheck.checks.fit.resting_coverage`), backed by the active store.

The share is a function of the link's visual and collision shapes, every neighbour's
collision and visual shapes (its elements, and which of its meshes repeat its visual) with
the neighbour's place at rest (rotation and translation), the content (sha256) of every mesh
file those shapes name and the thresholds (the run's, and the fit's with the link's own
protrusion tolerance); the store adds geomcheck's code and the libraries' versions. A link
with a mesh that did not load is measured afresh each run.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from geomcheck.cache import active_store, cached
from geomcheck.cache.keys import canonical, every_digest
from geomcheck.geometry.neighbours import Neighbour
from geomcheck.model import Link, Mesh, Shape

log = logging.getLogger("geomcheck.cache")

NAMESPACE = "resting-coverage"
FORMAT = 1


def _shapes(shapes: Iterable[Shape]) -> list[tuple[Any, Any]]:
    return [(s.geometry, s.origin) for s in shapes]


def coverage_key(
    link: Link,
    neighbours: Sequence[tuple[Link, Neighbour]],
    digest: Callable[[Mesh], str | None],
    settings: Any,
) -> list[Any] | None:
    """The key parts of ``link``'s coverage at rest, ``None`` when it is not to be stored (a
    mesh that did not load, or a part no key can hold)."""
    links = [link, *(other for other, _ in neighbours)]
    shapes = (s for other in links for s in (*other.visuals, *other.collisions))
    digests = every_digest((s.geometry for s in shapes if isinstance(s.geometry, Mesh)), digest)
    if digests is None:
        return None
    try:
        return [
            FORMAT,
            canonical(_shapes(link.visuals)),
            canonical(_shapes(link.collisions)),
            [
                [
                    canonical(_shapes(other.visuals)),
                    canonical(_shapes(other.collisions)),
                    n.rotation.tolist(),
                    n.translation.tolist(),
                ]
                for other, n in neighbours
            ],
            digests,
            canonical(settings),
        ]
    except TypeError as err:
        log.debug("cache: coverage at rest of %s not cached: %s", link.name, err)
        return None


def stored_resting_coverage(
    link: Link,
    neighbours: Sequence[tuple[Link, Neighbour]],
    compute: Callable[[], float],
    digest: Callable[[Mesh], str | None],
    settings: Any,
) -> float:
    """``compute()`` (``link``'s coverage at rest), read from the active store when it holds it."""
    if active_store() is None:
        return compute()
    key = coverage_key(link, neighbours, digest, settings)
    if key is None:
        return compute()
    return cached(NAMESPACE, key, compute, lambda share: repr(float(share)).encode(), lambda b: float(b.decode()))


__all__ = ["NAMESPACE", "coverage_key", "stored_resting_coverage"]
