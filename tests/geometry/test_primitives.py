"""Exact primitive geometry, frames and enclosing shapes (geomcheck.geometry.primitives,
frames, enclosing, surface)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import trimesh

from geomcheck.geometry.enclosing import _first_least, minimal_ball, minimum_box
from geomcheck.geometry.frames import canonical_box_frame, rotation_between
from geomcheck.geometry.primitives import (
    contains,
    extent_coverage,
    extent_gaps,
    least_signed_distance,
    signed_distance,
    volume,
    volume_samples,
)
from geomcheck.geometry.shapes import primitive_mesh
from geomcheck.geometry.surface import ConvexRegion, Solid, Surface, is_flat, unique_rows
from geomcheck.model import Box, Capsule, Cylinder, Pose, Sphere, rpy_from_matrix

BOX = Box((2.0, 4.0, 6.0))
CYLINDER = Cylinder(1.0, 2.0)
SPHERE = Sphere(1.5)


@pytest.mark.parametrize(
    ("point", "expected"),
    [
        ((0.0, 0.0, 0.0), -1.0),  # centre: nearest face is x at 1
        ((0.5, 0.0, 0.0), -0.5),
        ((2.0, 0.0, 0.0), 1.0),  # off the x face
        ((2.0, 1.0, 1.0), 1.0),  # beyond a face, within the others' span
        ((2.0, 3.0, 1.0), np.sqrt(2.0)),  # off an edge (half extents 1, 2, 3)
        ((2.0, 3.0, 4.0), np.sqrt(3.0)),  # off a corner
    ],
)
def test_box_signed_distance(point: tuple[float, float, float], expected: float) -> None:
    assert signed_distance(BOX, np.array([point]))[0] == pytest.approx(expected)


@pytest.mark.parametrize(
    ("point", "expected"),
    [
        ((0.0, 0.0, 0.0), -1.0),
        ((0.0, 0.0, 0.8), -0.2),  # nearer the cap than the side
        ((2.0, 0.0, 0.0), 1.0),
        ((0.0, 0.0, 1.5), 0.5),
        ((0.0, 2.0, 2.0), np.sqrt(2.0)),  # off the rim
        ((0.6, 0.8, 0.0), 0.0),  # on the side
    ],
)
def test_cylinder_signed_distance(point: tuple[float, float, float], expected: float) -> None:
    assert signed_distance(CYLINDER, np.array([point]))[0] == pytest.approx(expected, abs=1e-12)


def test_sphere_signed_distance_and_contains() -> None:
    pts = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 1.0, 1.0]])
    assert signed_distance(SPHERE, pts) == pytest.approx([-1.5, 1.5, np.sqrt(2.0) - 1.5])
    assert contains(SPHERE, pts).tolist() == [True, False, True]
    assert contains(SPHERE, pts, tolerance=1.5).tolist() == [True, True, True]


@pytest.mark.parametrize("primitive", [BOX, CYLINDER, SPHERE])
def test_surface_points_are_at_zero_and_volume_samples_inside(primitive: Box | Cylinder | Sphere) -> None:
    # vertices of the tessellation lie on the true surface
    vertices = np.asarray(primitive_mesh(primitive).vertices)
    assert np.abs(signed_distance(primitive, vertices)).max() < 1e-9
    inside = volume_samples(primitive, 4000, np.random.default_rng(0))
    assert signed_distance(primitive, inside).max() <= 1e-12
    assert np.abs(inside.mean(axis=0)).max() < 0.05 * volume(primitive) ** (1 / 3)


def test_signed_distance_matches_brute_force_box_distance() -> None:
    rng = np.random.default_rng(3)
    pts = rng.uniform(-5, 5, size=(500, 3))
    h = np.array(BOX.size) / 2
    nearest = np.clip(pts, -h, h)
    outside = np.linalg.norm(pts - nearest, axis=1)
    sd = signed_distance(BOX, pts)
    assert np.allclose(sd[outside > 0], outside[outside > 0])
    inner = outside == 0
    assert np.allclose(sd[inner], -np.min(h - np.abs(pts[inner]), axis=1))


def test_volumes() -> None:
    assert volume(BOX) == pytest.approx(48.0)
    assert volume(CYLINDER) == pytest.approx(2.0 * np.pi)
    assert volume(SPHERE) == pytest.approx(4.0 / 3.0 * np.pi * 1.5**3)


def test_extent_gaps_signs() -> None:
    pts = np.array([[-1.5, -1.0, -3.0], [0.5, 1.0, 2.0]])
    gaps = extent_gaps(BOX, pts)
    # positive: the box reaches beyond the points; negative: the points stick out
    assert gaps == pytest.approx({"x-": -0.5, "x+": 0.5, "y-": 1.0, "y+": 1.0, "z-": 0.0, "z+": 1.0})
    cyl = extent_gaps(CYLINDER, np.array([[1.2, 0.0, -1.0], [0.0, 0.0, 0.5]]))
    assert cyl == pytest.approx({"radial": -0.2, "z-": 0.0, "z+": 0.5})
    assert extent_gaps(SPHERE, np.array([[0.0, 2.0, 0.0]])) == pytest.approx({"radial": -0.5})


def test_extent_coverage_reports_share_and_interval() -> None:
    # a 0.04 m slab at z 0.19..0.23 against a mesh from z 0 to 0.9 (the 2009 PR2 base)
    slab = Box((0.65, 0.65, 0.04))
    mesh = np.array([[-0.33, -0.33, 0.0 - 0.21], [0.33, 0.33, 0.9 - 0.21]])
    share, box_extent, mesh_extent, lo, hi = extent_coverage(slab, mesh)["z"]
    assert share == pytest.approx(0.04 / 0.9)
    assert (box_extent, mesh_extent) == pytest.approx((0.04, 0.9))
    assert (lo, hi) == pytest.approx((-0.21, 0.69))
    assert extent_coverage(CYLINDER, np.array([[2.0, 0.0, 0.0]]))["radial"][0] == pytest.approx(0.5)


def test_rpy_round_trip_and_urdf_convention() -> None:
    rng = np.random.default_rng(1)
    for _ in range(50):
        rpy = (rng.uniform(-3, 3), rng.uniform(-1.5, 1.5), rng.uniform(-3, 3))
        rotation = Pose(rpy=rpy).rotation()
        assert np.allclose(Pose(rpy=rpy_from_matrix(rotation)).rotation(), rotation)
    # roll of pi/2 turns a cylinder's z axis onto -y: how URDF wheels are written
    assert np.allclose(Pose(rpy=(np.pi / 2, 0, 0)).rotation()[:, 2], [0, -1, 0])
    gimbal = Pose(rpy=(0.3, np.pi / 2, 0.0)).rotation()
    assert np.allclose(Pose(rpy=rpy_from_matrix(gimbal)).rotation(), gimbal)


def test_a_composed_pose_reads_the_same_whatever_noise_its_transforms_left() -> None:
    # a wheel's joint pose composed of an SDFormat frame chain: the rotation is the identity
    # but for ~1e-16 of float noise, which differs between BLAS kernels
    noisy = np.eye(3) + np.array([[0.0, 2e-17, -1e-16], [-2e-17, 0.0, 7e-17], [1e-16, -7e-17, 0.0]])
    pose = Pose.composed(np.array([0.1 + 1e-17, -2.7e-17, 0.25]), noisy)
    assert pose == Pose((0.1, 0.0, 0.25), (0.0, 0.0, 0.0))
    assert all(math.copysign(1.0, v) == 1.0 for v in (*pose.xyz, *pose.rpy))  # no -0.0 in the report
    # a half turn about x read through a -0.0 entry: arctan2(-0.0, -1) would give -pi, not pi
    flipped = Pose(rpy=(np.pi, 0.0, 0.0)).rotation()
    flipped[2, 1] = -1e-17
    assert Pose.composed(np.zeros(3), flipped).rpy == (round(np.pi, 12), 0.0, 0.0)
    # a written pose is kept to a picometre and a picoradian
    written = Pose((0.123456789012, -0.5, 1.0), (0.3, -0.2, 1.1))
    again = Pose.composed(np.array(written.xyz), written.rotation())
    assert again.xyz == written.xyz
    assert again.rpy == pytest.approx(written.rpy, abs=1e-12)


def test_rotation_between_including_opposite() -> None:
    for a, b in [((0, 0, 1), (0, 1, 0)), ((1, 0, 0), (1, 0, 0)), ((0, 0, 1), (0, 0, -1)), ((1, 2, 3), (-3, 1, 0))]:
        av, bv = np.array(a, float), np.array(b, float)
        r = rotation_between(av, bv)
        assert np.allclose(r @ (av / np.linalg.norm(av)), bv / np.linalg.norm(bv))
        assert np.linalg.det(r) == pytest.approx(1.0)


def test_canonical_box_frame_prefers_identity() -> None:
    turned = Pose(rpy=(0.0, 0.0, np.pi / 2)).rotation()
    rotation, size = canonical_box_frame(turned, np.array([1.0, 2.0, 3.0]))
    assert np.allclose(rotation, np.eye(3))
    assert size == pytest.approx([2.0, 1.0, 3.0])


def test_minimal_ball_matches_brute_force() -> None:
    rng = np.random.default_rng(7)
    for dim in (2, 3):
        for n in (1, 2, 3, 5, 40, 300):
            pts = rng.normal(size=(n, dim))
            centre, radius = minimal_ball(pts)
            assert np.linalg.norm(pts - centre, axis=1).max() <= radius + 1e-12
            # no smaller ball: the supporting points (on the sphere) surround the centre
            on = pts[np.abs(np.linalg.norm(pts - centre, axis=1) - radius) < 1e-9]
            if n > 1:
                assert len(on) >= 2
                assert np.linalg.norm(on.mean(axis=0) - centre) < radius
    circle = np.c_[2 * np.cos(np.linspace(0, 6, 40)) + 1, 2 * np.sin(np.linspace(0, 6, 40)) - 1]
    centre, radius = minimal_ball(circle)
    assert centre == pytest.approx([1.0, -1.0]) and radius == pytest.approx(2.0)


def test_minimal_ball_of_coplanar_and_repeated_points() -> None:
    square = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [1, 1, 0]], float)
    centre, radius = minimal_ball(square)
    assert centre == pytest.approx([0.5, 0.5, 0.0]) and radius == pytest.approx(np.sqrt(0.5))


def test_minimum_box_finds_a_turned_box_exactly() -> None:
    box = trimesh.creation.box(extents=[0.3, 0.2, 0.1])
    box.apply_transform(Pose((0.1, 0.2, 0.3), (0.3, 0.2, 0.1)).matrix())
    hull = ConvexRegion.of(np.asarray(box.vertices))
    rotation, centre, size = minimum_box(np.asarray(box.vertices), hull)
    assert sorted(size) == pytest.approx([0.1, 0.2, 0.3])
    assert centre == pytest.approx([0.1, 0.2, 0.3])
    assert np.linalg.det(rotation) == pytest.approx(1.0)


def test_surface_sampling_is_area_weighted_and_seeded() -> None:
    # two unit squares, one 4x larger: 4/5 of the samples land on it
    small = trimesh.creation.box(extents=[1, 1, 1e-3])
    big = trimesh.creation.box(extents=[2, 2, 1e-3])
    big.apply_translation([10, 0, 0])
    surface = Surface.merge([Surface.from_mesh(m, np.eye(3), np.zeros(3)) for m in (small, big)])
    a = surface.sample(20000, np.random.default_rng(0))
    b = surface.sample(20000, np.random.default_rng(0))
    assert np.array_equal(a, b)
    assert np.mean(a[:, 0] > 5) == pytest.approx(0.8, abs=0.02)


def test_unique_rows_keeps_first_occurrence_order() -> None:
    pts = np.array([[1, 0, 0], [0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0]], float)
    assert unique_rows(pts).tolist() == [[1, 0, 0], [0, 0, 0], [0, 1, 0]]


def test_convex_region_distance_and_motion() -> None:
    cube = trimesh.creation.box(extents=[2, 2, 2])
    region = ConvexRegion.of(np.asarray(cube.vertices))
    assert region is not None and region.volume == pytest.approx(8.0)
    assert region.signed_distance(np.array([[0, 0, 0], [3, 0, 0]], float)) == pytest.approx([-1.0, 2.0])
    pose = Pose((1.0, 2.0, 3.0), (0.1, 0.2, 0.3))
    solid = Solid.of(Surface.from_mesh(cube, np.eye(3), np.zeros(3))).moved(pose.rotation(), np.array(pose.xyz))
    assert solid.hull is not None
    assert solid.hull.signed_distance(np.array([pose.xyz])) == pytest.approx([-1.0])
    assert ConvexRegion.of(np.array(list(itertools.product([0, 1], [0, 1], [0.0])))) is None
    assert is_flat(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float))


@pytest.mark.parametrize("primitive", [Box((0.3, 0.1, 0.05)), Cylinder(0.04, 0.2), Sphere(0.07)])
@pytest.mark.parametrize("offset", [0.0, 0.05, 0.5])
def test_least_signed_distance_is_the_minimum_over_every_point(
    primitive: Box | Cylinder | Sphere, offset: float
) -> None:
    rng = np.random.default_rng(3)
    points = rng.normal(scale=0.3, size=(20_000, 3)) + np.array([offset, -offset, 2.0 * offset])
    assert least_signed_distance(primitive, points) == float(signed_distance(primitive, points).min())
    far = points[np.linalg.norm(points, axis=1) > 0.4]  # every point outside: the least distance is positive
    assert least_signed_distance(primitive, far) == float(signed_distance(primitive, far).min()) > 0.0
    # a batch at a time: the least of the batches before bounds the next
    least = float(signed_distance(primitive, points).min())
    assert least_signed_distance(primitive, far, at_most=least) == least
    assert least_signed_distance(primitive, points, at_most=least + 0.01) == least
    assert least_signed_distance(primitive, points, at_most=-1.0) == -1.0


def test_boxes_a_millionth_apart_in_volume_are_a_tie_decided_by_candidate_order() -> None:
    # a left-right symmetric torso has two mirror boxes of one volume: the last digits a CPU
    # gives them must not pick one
    assert _first_least(np.array([2.0, 1.0 + 1e-12, 1.0, 3.0])) == 1
    assert _first_least(np.array([[2.0, 1.0], [1.0 - 1e-9, 5.0]])) == 1
    assert _first_least(np.array([1.0, 1.0 - 1e-3])) == 1  # a real difference still decides


@pytest.mark.parametrize("shape", ["box", "cylinder"])
def test_an_ellipsoid_is_measured_as_itself(shape: str) -> None:
    """Semi-axes 0.1, 0.05, 0.03 m (a box marked ellipsoid) or 0.05, 0.05, 0.1 m (a cylinder):
    signed distances against a dense sampling of the surface, within its spacing."""
    ellipsoid = Box((0.2, 0.1, 0.06), ellipsoid=True) if shape == "box" else Cylinder(0.05, 0.2, ellipsoid=True)
    axes = np.array([0.1, 0.05, 0.03]) if shape == "box" else np.array([0.05, 0.05, 0.1])
    u, v = np.meshgrid(np.linspace(0.0, np.pi, 401), np.linspace(0.0, 2.0 * np.pi, 801))
    surface = np.stack([np.sin(u) * np.cos(v), np.sin(u) * np.sin(v), np.cos(u)], axis=-1).reshape(-1, 3) * axes
    rng = np.random.default_rng(2)
    points = np.concatenate([rng.uniform(-0.15, 0.15, (30, 3)), rng.uniform(-0.02, 0.02, (10, 3))])
    inside = ((points / axes) ** 2).sum(axis=1) <= 1.0
    nearest = np.array([np.linalg.norm(surface - p, axis=1).min() for p in points])
    assert inside.any() and (~inside).any()
    assert signed_distance(ellipsoid, points) == pytest.approx(np.where(inside, -nearest, nearest), abs=2e-4)
    assert volume(ellipsoid) == pytest.approx(4.0 / 3.0 * math.pi * float(np.prod(axes)))
    drawn = volume_samples(ellipsoid, 2000, rng)
    assert (((drawn / axes) ** 2).sum(axis=1) <= 1.0 + 1e-9).all()


def test_a_flat_ellipsoid_is_measured_as_its_flat_box() -> None:
    """A zero semi-axis (a file's error, reported by the structure rules) divides nothing by zero."""
    flat = Box((0.2, 0.1, 0.0), ellipsoid=True)
    points = np.array([[0.0, 0.0, 0.01], [0.3, 0.0, 0.0]])
    assert signed_distance(flat, points) == pytest.approx([0.01, 0.2])
    assert volume(flat) == 0.0


def test_a_capsules_volume_is_its_own() -> None:
    """Radius 0.05 m, 0.3 m long over its hemispherical ends: how much bigger than its part a
    capsule is (GC302) is the capsule's, not its enclosing cylinder's (12.5% more here)."""
    capsule = Capsule(0.05, 0.3)
    assert volume(capsule) == pytest.approx(math.pi * 0.05**2 * 0.2 + 4.0 / 3.0 * math.pi * 0.05**3)
    assert volume(Cylinder(0.05, 0.3)) / volume(capsule) == pytest.approx(1.125)
