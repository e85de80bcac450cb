"""Bounded convex hulls, blockwise signed distances and welded vertices of large surfaces."""

from __future__ import annotations

import numpy as np
import trimesh
from scipy.spatial import ConvexHull

from geomcheck.geometry.surface import ConvexRegion, Surface, bounded_hull, enclosing_vertices, unique_rows
from geomcheck.thresholds import AnalysisThresholds


def bumpy_sphere(subdivisions: int, seed: int = 1) -> np.ndarray:
    """Vertices of an icosphere of radius 0.1 m with 2 % radial noise: every one a hull vertex."""
    vertices = np.asarray(trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.1).vertices)
    return vertices * (1.0 + 0.02 * np.random.default_rng(seed).random((len(vertices), 1)))


def planar_excess(points: np.ndarray, region: ConvexRegion) -> float:
    """Largest height [m] of any point above any facet plane of ``region`` (brute force)."""
    return float((points @ region.equations[:, :3].T + region.equations[:, 3]).max())


def test_small_point_sets_get_the_exact_hull() -> None:
    points = bumpy_sphere(3)
    region = ConvexRegion.of(points)
    assert region is not None
    exact = ConvexHull(points)
    assert region.tolerance == 0.0
    assert len(region.vertices) == len(exact.vertices) == 555
    assert region.volume == float(exact.volume)
    assert planar_excess(points, region) <= 1e-12


def test_large_point_sets_get_a_bounded_hull_within_its_tolerance() -> None:
    analysis = AnalysisThresholds(hull_exact_points=1000)
    for subdivisions in (4, 5):
        points = bumpy_sphere(subdivisions)
        region = ConvexRegion.of(points, analysis)
        assert region is not None
        diagonal = float(np.linalg.norm(np.ptp(points, axis=0)))
        assert region.tolerance == analysis.hull_tolerance_fraction * diagonal
        assert planar_excess(points, region) <= region.tolerance * (1.0 + 1e-6)
        # inside the exact hull, and short of it by no more than a shell of the tolerance
        exact = ConvexHull(points).volume
        assert exact * (1.0 - 6.0 * region.tolerance / 0.1) <= region.volume <= exact


def test_the_hull_of_a_finer_tessellation_keeps_its_size() -> None:
    analysis = AnalysisThresholds(hull_exact_points=1000)
    sizes = []
    for subdivisions in (5, 6, 7):  # 10,242 to 163,842 vertices, every one on the exact hull
        points = np.asarray(trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.1).vertices)
        region = ConvexRegion.of(points, analysis)
        assert region is not None
        sizes.append(len(region.vertices))
    assert max(sizes) < 1.1 * min(sizes)
    assert max(sizes) < 4000


def test_interior_points_are_dropped_before_the_hull_exactly() -> None:
    rng = np.random.default_rng(3)
    cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    points = np.concatenate([rng.random((30_000, 3)) * 0.98 + 0.01, cube])
    region = ConvexRegion.of(points, AnalysisThresholds(hull_exact_points=100))
    assert region is not None
    assert sorted(map(tuple, region.vertices.tolist())) == sorted(map(tuple, cube.tolist()))
    assert abs(region.volume - 1.0) < 1e-12


def test_signed_distance_in_blocks_equals_one_product() -> None:
    points = bumpy_sphere(3)
    region = ConvexRegion.of(points)
    assert region is not None
    probes = np.random.default_rng(5).normal(scale=0.15, size=(5000, 3))
    whole = (probes @ region.equations[:, :3].T + region.equations[:, 3]).max(axis=1)
    assert np.array_equal(region.signed_distance(probes), whole)


def test_unique_rows_merges_to_a_nanometre_in_first_appearance_order() -> None:
    points = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0 + 1e-12], [0.5, 0.5, 0.5], [1.0, 0.0, 0.0]])
    assert unique_rows(points).tolist() == [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.5, 0.5, 0.5]]


def test_areas_and_samples_of_a_surface_without_its_corner_array() -> None:
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=0.2)
    surface = Surface(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    assert np.allclose(surface.face_areas(), mesh.area_faces, rtol=1e-12, atol=0.0)
    samples = surface.sample(2000, np.random.default_rng(0))
    assert samples.shape == (2000, 3)
    assert np.allclose(np.linalg.norm(samples, axis=1), 0.2, atol=2e-3)
    assert np.array_equal(samples, surface.sample(2000, np.random.default_rng(0)))


def test_the_pushed_out_hull_holds_every_point_even_at_sharp_edges() -> None:
    # a thin wedge, finely tessellated: its 10 degree edge is where a bounded hull cuts deepest
    wedge = trimesh.Trimesh(
        vertices=[[0, 0, 0], [1, 0, 0], [0, 0.1, 0], [1, 0.1, 0], [0, 0, 0.0875], [1, 0, 0.0875]],
        faces=[[0, 2, 1], [1, 2, 3], [0, 1, 4], [1, 5, 4], [2, 4, 5], [2, 5, 3], [0, 4, 2], [1, 3, 5]],
    )
    for _ in range(4):
        wedge = wedge.subdivide()
    points = np.asarray(wedge.vertices) + np.random.default_rng(2).normal(scale=1e-5, size=wedge.vertices.shape)
    analysis = AnalysisThresholds(hull_exact_points=500)
    found = bounded_hull(points, analysis)
    assert found is not None
    pts, hull, tolerance = found
    assert tolerance > 0.0
    outer = ConvexHull(enclosing_vertices(pts, hull, tolerance))
    assert float((points @ outer.equations[:, :3].T + outer.equations[:, 3]).max()) <= 1e-9
    exact = bounded_hull(points, AnalysisThresholds(hull_exact_points=10**6))
    assert exact is not None and exact[2] == 0.0
    assert np.array_equal(enclosing_vertices(*exact), exact[0][exact[1].vertices])


def test_a_hull_of_many_facets_skips_planes_that_cannot_be_the_farthest_with_the_same_result() -> None:
    from geomcheck.geometry.surface import PRUNE_MIN_FACETS, farthest_plane

    # a CAD-like part: a box with filleted edges, thousands of small facets on its rounds
    rng = np.random.default_rng(11)
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.02).vertices
    corners = np.array([[x, y, z] for x in (-0.05, 0.05) for y in (-0.03, 0.03) for z in (-0.01, 0.01)])
    points = (corners[:, None, :] + sphere[None, :, :]).reshape(-1, 3)
    hull = ConvexRegion.of(points)
    assert hull is not None and len(hull.equations) >= PRUNE_MIN_FACETS
    assert hull.facet_groups is not None
    probes = np.concatenate([points, rng.uniform(-0.12, 0.12, size=(5000, 3)), rng.uniform(-0.03, 0.03, (5000, 3))])
    pruned = hull.signed_distance(probes)
    whole = farthest_plane(probes, hull.equations)
    # the same planes' values: a skipped farthest plane would be off by the gap to the next one;
    # a picometre leaves room for how another CPU's kernel rounds products of other shapes
    np.testing.assert_allclose(pruned, whole, rtol=0, atol=1e-12)
    assert (pruned < 0).sum() > 4000 and (pruned > 0).sum() > 4000  # inside and outside both probed
