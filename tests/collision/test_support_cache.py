"""Collision meshes' hulls and support points kept in the cache by their vertices' bytes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

from geomcheck.cache import Store, using_store
from geomcheck.collision.base import MeshArrays, hull_and_support
from geomcheck.collision.support_cache import NAMESPACE, stored_hull_and_support, stored_support_points


def entries(store: Store) -> int:
    return sum(1 for p in (store.root / NAMESPACE).rglob("*") if p.is_file())


def test_a_stored_hull_and_support_equal_the_computed_ones_and_an_edit_misses(tmp_path: Path) -> None:
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.1)
    mesh = MeshArrays(np.asarray(sphere.vertices, dtype=float), np.asarray(sphere.faces, dtype=np.int64))
    expected_hull, expected_support = hull_and_support(mesh)
    store = Store(tmp_path)
    with using_store(store):
        for _ in range(2):
            hull, support = stored_hull_and_support(mesh)
            assert np.array_equal(hull.vertices, expected_hull.vertices)
            assert np.array_equal(hull.faces, expected_hull.faces) and hull.faces.dtype == np.int64
            assert np.array_equal(support, expected_support)
        assert store.hits == 1 and entries(store) == 1
        moved = MeshArrays(mesh.vertices + np.array([0.0, 0.0, 0.01]), mesh.faces)
        support = stored_support_points(moved)
    assert np.array_equal(support, hull_and_support(moved)[1])
    assert abs(float(support[:, 2].max()) - 0.11) < 1e-12
    assert entries(store) == 2
