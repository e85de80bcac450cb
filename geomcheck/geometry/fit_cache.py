"""Link fits kept across runs: the fit family's table of fits of links drawn alike, backed
by the active store.

The fit family keys a link's fit (:class:`geomcheck.geometry.fit.LinkFit`) by what it is
a function of: the link's visual and collision shapes (geometry and origin), which
collision meshes repeat the visual, and the neighbours' elements it borrows in their places
(:func:`geomcheck.checks.fit.alike_fit`). On disk that key is completed by the content
(sha256) of every mesh file it names, the run's thresholds, geomcheck's code and the
libraries' versions, so a warm re-check after an edit fits again only the links whose
shapes (or borrowed neighbours) changed. A key naming a mesh that did not load, or a part
no key can hold, is kept in memory only, as before.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterator
from typing import Any

from geomcheck.cache import Store, stage_parts
from geomcheck.cache.keys import canonical, digest_key, every_digest
from geomcheck.cache.records import decode_record, encode_record

log = logging.getLogger("geomcheck.cache")

NAMESPACE = "link-fit"
FORMAT = 3  # 2: ElementFit.better_kind, capsules; 3: own_kind_volume


def fit_classes() -> tuple[type, ...]:
    """The classes a stored fit is made of (the only ones decoding rebuilds)."""
    from geomcheck.geometry.elements import CollisionElement
    from geomcheck.geometry.fit import AxisAlternative, ElementFit, LinkFit
    from geomcheck.geometry.meshfit import MeshComparison
    from geomcheck.geometry.suggest import Suggestion
    from geomcheck.geometry.surface import ConvexRegion, Solid, Surface
    from geomcheck.model import Box, Capsule, Cylinder, Sphere

    return (
        LinkFit,
        ElementFit,
        AxisAlternative,
        CollisionElement,
        Solid,
        Surface,
        ConvexRegion,
        Suggestion,
        MeshComparison,
        Box,
        Capsule,
        Cylinder,
        Sphere,
    )


def _meshes_in(value: Any) -> Iterator[Any]:
    """Every :class:`geomcheck.model.Mesh` inside a fit key (nested tuples of shapes)."""
    from geomcheck.model import Mesh

    if isinstance(value, Mesh):
        yield value
    elif isinstance(value, tuple):
        for item in value:
            yield from _meshes_in(item)


class StoredFits(dict[Any, Any]):
    """``{fit key: LinkFit}`` that also reads and writes the fits in ``store``.

    ``digest(mesh)`` gives the sha256 of a ``<mesh>``'s file (``None`` when it did not
    load); ``settings`` is what else every fit depends on (the run's thresholds)."""

    def __init__(self, store: Store, digest: Callable[[Any], str | None], settings: Any) -> None:
        super().__init__()
        self.store = store
        self.digest = digest
        self.settings = settings

    def disk_key(self, key: Any) -> str | None:
        """The store key of a fit key, ``None`` when it is not to be stored."""
        digests = every_digest(_meshes_in(key), self.digest)
        if digests is None:
            return None
        try:
            return digest_key(NAMESPACE, stage_parts([FORMAT, canonical(key), digests, self.settings]))
        except TypeError as err:
            log.debug("cache: link fit not cached: %s", err)
            return None

    def __contains__(self, key: object) -> bool:
        if super().__contains__(key):
            return True
        stored = self.disk_key(key)
        if stored is None:
            return False
        found = self.store.get_decoded(NAMESPACE, stored, lambda payload: decode_record(payload, fit_classes()))
        if found is None:
            return False
        super().__setitem__(key, found)
        return True

    def __setitem__(self, key: Any, value: Any) -> None:
        super().__setitem__(key, value)
        stored = self.disk_key(key)
        if stored is None:
            return
        try:
            payload = encode_record(value)
        except TypeError as err:
            log.debug("cache: link fit not cached: %s", err)
            return
        self.store.put_bytes(NAMESPACE, stored, payload)


__all__ = ["NAMESPACE", "StoredFits", "fit_classes"]
