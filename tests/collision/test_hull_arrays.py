"""The collision layer's convex hull is trimesh's for arrays and trimesh objects alike
(:mod:`tests.geometry.test_hull_mesh` holds the hull itself to trimesh's)."""

from __future__ import annotations

import numpy as np
import trimesh

from geomcheck.collision.base import MeshArrays, convex_hull


def test_convex_hull_of_arrays_equals_that_of_a_trimesh_object() -> None:
    mesh = trimesh.creation.capsule(radius=0.04, height=0.2)
    arrays = MeshArrays(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64))
    a, b = convex_hull(arrays), convex_hull(mesh)
    assert np.array_equal(a.vertices, mesh.convex_hull.vertices) and np.array_equal(a.faces, mesh.convex_hull.faces)
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
