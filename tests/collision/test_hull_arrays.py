"""The collision layer's convex hull is trimesh's, bit for bit, computed without trimesh."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from geomcheck.collision.base import MeshArrays, _qhull_hull, convex_hull


def clouds() -> list[np.ndarray]:
    rng = np.random.default_rng(7)
    grid = np.stack(np.meshgrid(*[np.linspace(0.0, 0.1, 4)] * 3), axis=-1).reshape(-1, 3)
    near = rng.normal(size=(60, 3))
    flat = rng.normal(size=(40, 3)) * [1.0, 1.0, 0.0]
    return [
        np.asarray(trimesh.creation.box(extents=(0.2, 0.1, 0.05)).vertices),
        np.asarray(trimesh.creation.cylinder(radius=0.05, height=0.3, sections=33).vertices),
        np.asarray(trimesh.creation.icosphere(subdivisions=3, radius=0.01).vertices) + 5.0,
        rng.normal(size=(500, 3)) * 1e-3,
        grid,  # coplanar points on every face: zero-area and unused vertices
        np.concatenate([near, near + rng.normal(size=near.shape) * 1e-10]),  # vertices merged by trimesh
        flat,  # qhull fails, then joggles: left to trimesh
    ]


@pytest.mark.parametrize("index", range(len(clouds())))
def test_hull_arrays_equal_trimesh_hull(index: int) -> None:
    points = np.ascontiguousarray(clouds()[index], dtype=np.float64)
    with np.errstate(invalid="ignore"):  # trimesh's centre of mass of the flat cloud's hull divides by zero volume
        expected = trimesh.convex.convex_hull(points)
        found = _qhull_hull(points)
    assert found.vertices.dtype == np.float64 and found.faces.dtype == np.int64
    assert found.vertices.tobytes() == np.asarray(expected.vertices).tobytes()
    assert found.faces.tobytes() == np.asarray(expected.faces).tobytes()


def test_convex_hull_of_arrays_equals_that_of_a_trimesh_object() -> None:
    mesh = trimesh.creation.capsule(radius=0.04, height=0.2)
    arrays = MeshArrays(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64))
    a, b = convex_hull(arrays), convex_hull(mesh)
    assert np.array_equal(a.vertices, mesh.convex_hull.vertices) and np.array_equal(a.faces, mesh.convex_hull.faces)
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
