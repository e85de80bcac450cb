"""coal's mesh collisions are screened by a convex guard holding each mesh: the answers are
exactly those of the meshes' own BVH query."""

from __future__ import annotations

import coal
import numpy as np
import trimesh
from scipy.spatial import ConvexHull

from geomcheck.collision import get_backend
from geomcheck.collision.base import SEPARATION_MARGIN, is_exact_hull, support_points
from geomcheck.model import Box, Cylinder
from tests.collision.poses import random_pose

POSES = 400


def bvh_collide(a, ta: np.ndarray, b, tb: np.ndarray) -> bool:
    """The unscreened query: the BVHs (or primitives) themselves."""
    request = coal.CollisionRequest()
    request.enable_contact = True
    request.num_max_contacts = 1
    result = coal.CollisionResult()
    place = get_backend("coal").placement
    coal.collide(a.geometry, place(ta), b.geometry, place(tb), request, result)
    return bool(result.isCollision())


def test_screened_collisions_equal_the_bvh_query() -> None:
    backend = get_backend("coal")
    # non-convex: a ring's hull covers its bore, where a small box is free yet inside the guard
    ring = backend.make(trimesh.creation.annulus(r_min=0.03, r_max=0.08, height=0.1, sections=24))
    ball = backend.make(trimesh.creation.icosphere(subdivisions=2, radius=0.05))
    box, cylinder = backend.make(Box((0.02, 0.02, 0.02))), backend.make(Cylinder(0.01, 0.3))
    rng = np.random.default_rng(7)
    outcomes = {"hit": 0, "screened": 0, "free inside the guard": 0}
    # the box near the ring's axis: often in its bore, free although inside the guard
    for a, b, reach in [(ring, ball, 0.15), (ring, box, 0.04), (ball, cylinder, 0.15), (ring, ring, 0.15)]:
        for _ in range(POSES):
            ta, tb = np.eye(4), random_pose(rng, reach)
            hit, depth = backend.collide(a, ta, b, tb)
            assert hit == bvh_collide(a, ta, b, tb)
            hull = backend.hull_distance(a, ta, b, tb)
            if hit:
                outcomes["hit"] += 1
                assert depth == max(0.0, -hull)  # the hulls' depth, as before the screen
            else:
                assert depth == 0.0
                outcomes["screened" if hull > SEPARATION_MARGIN else "free inside the guard"] += 1
    # every branch was taken, so the equality above covers each
    assert min(outcomes.values()) >= 20, outcomes


def test_guard_is_the_hull_when_exact_and_holds_every_vertex_otherwise() -> None:
    backend = get_backend("coal")
    coarse = trimesh.creation.icosphere(subdivisions=2, radius=0.05)
    assert is_exact_hull(coarse)
    made = backend.make(coarse)
    assert made.guard is made.hull
    fine = trimesh.creation.icosphere(subdivisions=6, radius=0.05)  # 40,962 vertices
    assert not is_exact_hull(fine)
    made = backend.make(fine)
    assert made.guard is not made.hull
    # the guard is the hull of the support points, which hold every vertex
    # (test_collision_backends.py::test_a_mesh_too_fine_for_an_exact_hull_gets_bounded_sound_support)
    support = support_points(fine)
    corners = np.array([np.asarray(p) for p in made.guard.points()])
    extreme = support[ConvexHull(support).vertices]
    assert len(corners) == len(extreme)
    assert np.allclose(np.sort(corners, axis=0), np.sort(extreme, axis=0), atol=1e-12)
    # while the bounded hull leaves some of the sphere's vertices out: the guard is needed
    planes = ConvexHull(np.array([np.asarray(p) for p in made.hull.points()])).equations
    assert (fine.vertices[::8] @ planes[:, :3].T + planes[:, 3]).max() > 1e-9
