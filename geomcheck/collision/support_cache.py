"""Collision meshes' hulls and support points kept across runs, backed by the active store.

:func:`geomcheck.collision.base.hull_and_support` (qhull through scipy, trimesh for the rare
hull it does not reproduce itself) is a pure function of a mesh's vertices; it is keyed by
the exact bytes of those vertices (their sha256, with their shape), and the store adds
geomcheck's code and the libraries' versions. A warm collision scene then builds its engine
objects from stored hulls without importing scipy. Without an active store it is computed,
as before.
"""

from __future__ import annotations

import numpy as np

from geomcheck.cache import cached_arrays
from geomcheck.collision.base import MeshArrays, hull_and_support
from geomcheck.geometry.hull_cache import points_digest
from geomcheck.geometry.surface import TriangleMesh

NAMESPACE = "mesh-hull-support"
FORMAT = 1


def vertices_key(vertices: np.ndarray) -> list[object]:
    """The key of a vertex array: its shape and the sha256 of its float64 bytes."""
    return [FORMAT, *points_digest(vertices)]


def stored_hull_and_support(mesh: TriangleMesh) -> tuple[MeshArrays, np.ndarray]:
    """:func:`geomcheck.collision.base.hull_and_support` of ``mesh``, read from the active
    store when it holds it."""

    def compute() -> dict[str, np.ndarray]:
        hull, support = hull_and_support(mesh)
        return {"vertices": hull.vertices, "faces": hull.faces, "support": support}

    arrays = cached_arrays(NAMESPACE, vertices_key(np.asarray(mesh.vertices)), compute)
    return MeshArrays(arrays["vertices"], arrays["faces"]), arrays["support"]


def stored_support_points(mesh: TriangleMesh) -> np.ndarray:
    """:func:`geomcheck.collision.base.support_points` of ``mesh`` through the store."""
    return stored_hull_and_support(mesh)[1]


__all__ = ["NAMESPACE", "stored_hull_and_support", "stored_support_points"]
