"""The closest points of triangles are trimesh's, to the last bit."""

from __future__ import annotations

import numpy as np
import trimesh

from geomcheck.geometry.closest import closest_points


def test_closest_points_are_trimeshs() -> None:
    rng = np.random.default_rng(11)
    triangles = rng.normal(size=(3000, 3, 3))
    triangles[:50, 1] = triangles[:50, 0]  # a first edge of no length
    triangles[50:60] = 0.0  # a triangle collapsed to a point
    points = rng.normal(size=(3000, 3)) * 2.0
    points[100:200] = triangles[100:200].mean(axis=1)  # on the face
    ours = closest_points(triangles, points)
    assert np.array_equal(ours, trimesh.triangles.closest_point(triangles, points))


def test_each_region_of_a_triangle() -> None:
    triangle = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    points = np.array([[-1.0, -1.0, 0.5], [2.0, -0.5, 0.0], [0.5, -1.0, 0.0], [0.2, 0.2, 3.0], [1.0, 1.0, 0.0]])
    nearest = closest_points(np.repeat(triangle[None], len(points), axis=0), points)
    assert np.allclose(nearest, [[0, 0, 0], [1, 0, 0], [0.5, 0, 0], [0.2, 0.2, 0], [0.5, 0.5, 0]])
