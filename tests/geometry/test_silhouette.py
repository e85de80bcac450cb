"""Silhouettes and outlines (geometry/silhouette.py) and the ``views`` section (checks/views.py)."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.checks import CheckContext
from geomcheck.checks import fit as fit_family
from geomcheck.checks import views as views_family
from geomcheck.geometry.raster import Grid, rasterize
from geomcheck.geometry.silhouette import (
    VIEWS,
    canonical_outline,
    mesh_silhouette,
    mesh_silhouettes,
    primitive_outline,
    round_rings,
    simplify_rings,
)
from geomcheck.load import ExpandedDocument, LoadedDescription, MeshStore, make_bundle
from geomcheck.model import Box, Cylinder, Link, Mesh, Pose, Robot, Shape, Sphere
from geomcheck.options import CheckOptions


def area(ring: np.ndarray) -> float:
    """Signed area of a ring, open or closed [m^2]."""
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def bounds(rings: list[np.ndarray]) -> list[float]:
    pts = np.concatenate(rings)
    return [*pts.min(axis=0).round(6).tolist(), *pts.max(axis=0).round(6).tolist()]


def box_mesh(extents: tuple[float, float, float], centre: tuple[float, float, float] = (0, 0, 0)) -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(centre)
    return mesh


# --- silhouettes of meshes ---------------------------------------------------------------


def test_box_silhouettes_are_its_exact_rectangles() -> None:
    mesh = box_mesh((0.66, 0.5, 0.9), (0.0, 0.0, 0.45))
    views = mesh_silhouettes(mesh.vertices, mesh.faces, 0.9 / 160)
    expected = {"front": [-0.25, 0.0, 0.25, 0.9], "side": [-0.33, 0.0, 0.33, 0.9], "top": [-0.33, -0.25, 0.33, 0.25]}
    for view, box in expected.items():
        (ring,) = simplify_rings(views[view], 0.9 * 0.004)
        assert len(ring) == 4, view
        assert bounds([ring]) == pytest.approx(box, abs=1e-9), view
        assert abs(area(ring)) == pytest.approx((box[2] - box[0]) * (box[3] - box[1]), rel=1e-9)


def test_annulus_from_above_has_a_hole_and_the_right_areas() -> None:
    mesh = trimesh.creation.annulus(r_min=0.05, r_max=0.1, height=0.02, sections=96)
    top = simplify_rings(mesh_silhouettes(mesh.vertices, mesh.faces, 0.2 / 160)["top"], 0.2 * 0.004)
    assert len(top) == 2
    outer, hole = sorted(top, key=lambda r: -abs(area(r)))
    pixel = 0.2 / 160
    assert abs(area(outer)) == pytest.approx(math.pi * 0.1**2, abs=2 * math.pi * 0.1 * pixel)
    assert abs(area(hole)) == pytest.approx(math.pi * 0.05**2, abs=2 * math.pi * 0.05 * pixel)
    # from the side the ring is a plain rectangle: 0.2 wide, 0.02 high
    (side,) = simplify_rings(mesh_silhouettes(mesh.vertices, mesh.faces, pixel)["side"], 0.2 * 0.004)
    assert bounds([side]) == pytest.approx([-0.1, -0.01, 0.1, 0.01], abs=1e-3)


def test_a_plate_seen_edge_on_stays_visible() -> None:
    plate = box_mesh((0.5, 0.5, 0.0004))  # far thinner than a raster cell (0.5 / 160 = 3 mm)
    front = mesh_silhouettes(plate.vertices, plate.faces, 0.5 / 160)["front"]
    (ring,) = simplify_rings(front, 0.5 * 0.004)
    lo_u, lo_v, hi_u, hi_v = bounds([ring])
    assert (lo_u, hi_u) == pytest.approx((-0.25, 0.25), abs=1e-9)
    assert hi_v - lo_v <= 0.0004 + 1e-9  # clipped to the plate's real thickness
    assert len(ring) >= 2


def test_union_of_overlapping_and_disjoint_meshes() -> None:
    a = box_mesh((0.2, 0.2, 0.2))
    b = box_mesh((0.2, 0.2, 0.2), (0.1, 0.1, 0.0))
    c = box_mesh((0.1, 0.1, 0.1), (0.6, 0.0, 0.0))
    merged = trimesh.util.concatenate([a, b, c])
    top = simplify_rings(mesh_silhouettes(merged.vertices, merged.faces, 0.75 / 160)["top"], 0.75 * 0.002)
    areas = sorted(abs(area(r)) for r in top)
    assert len(top) == 2
    assert areas[0] == pytest.approx(0.01, rel=0.05)  # the lone small box
    assert areas[1] == pytest.approx(0.04 + 0.04 - 0.01, rel=0.05)  # two boxes overlapping by a quarter


def test_rasterizing_ignores_face_order_and_is_deterministic() -> None:
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    grid = Grid.covering(np.array([-0.1, -0.1]), np.array([0.1, 0.1]), 0.2 / 64)
    projected = mesh.vertices[:, [1, 2]]
    shuffled = np.random.default_rng(0).permutation(len(mesh.faces))
    first = rasterize(projected[mesh.faces], grid)
    again = rasterize(projected[mesh.faces[shuffled]], grid)
    assert np.array_equal(first, again)
    rings = mesh_silhouette(mesh.vertices, mesh.faces, "front", grid)
    assert [r.tolist() for r in rings] == [
        r.tolist() for r in mesh_silhouette(mesh.vertices, mesh.faces, "front", grid)
    ]
    assert abs(area(rings[0])) == pytest.approx(math.pi * 0.1**2, rel=0.05)


def test_grid_puts_the_extremes_on_cell_centres() -> None:
    grid = Grid.covering(np.array([0.0, 0.0]), np.array([1.0, 0.5]), 0.1, pad=2)
    centre_of_first_used = grid.origin + 2.5 * grid.pixel
    assert centre_of_first_used == pytest.approx([0.0, 0.0])
    assert grid.shape == (6 + 4, 11 + 4)  # rows along v, columns along u: the span's cells and the padding
    last_centre = grid.origin + (np.array(grid.shape[::-1]) - 2.5) * grid.pixel
    assert last_centre == pytest.approx([1.0, 0.5])


# --- simplification and rounding ---------------------------------------------------------


def distance_to_polygon(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Distance of each point (n, 2) to the closed polygon (k, 2)."""
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("nkd,kd->nk", points[:, None] - a, ab) / np.einsum("kd,kd->k", ab, ab), 0, 1)
    nearest = a + t[..., None] * ab
    return np.min(np.linalg.norm(points[:, None] - nearest, axis=2), axis=1)


def test_douglas_peucker_stays_within_tolerance() -> None:
    angle = np.linspace(0, 2 * np.pi, 1001)
    wobbly = np.stack([np.cos(angle), 0.6 * np.sin(angle) + 0.05 * np.sin(9 * angle)], axis=1)
    (simple,) = simplify_rings([wobbly], 0.01)
    assert 10 < len(simple) < 200
    assert distance_to_polygon(wobbly, simple).max() <= 0.01 + 1e-12
    # every simplified point is an original point, in the original order
    index = [int(np.flatnonzero((wobbly == p).all(axis=1))[0]) for p in simple]
    assert index == sorted(index)


def test_a_collapsing_ring_is_replaced_by_its_hull() -> None:
    strip = np.array([[0.0, 0.0], [0.5, 0.0004], [1.0, 0.0], [1.0, 0.001], [0.5, 0.0006], [0.0, 0.001], [0.0, 0.0]])
    (simple,) = simplify_rings([strip], 0.01)
    assert len(simple) >= 3
    assert abs(area(simple)) >= 0.25 * abs(area(strip))


def test_round_rings_to_a_tenth_of_a_millimetre() -> None:
    ring = np.array([[0.123456, -0.0000001], [0.12346, 0.0], [0.2, 0.2], [0.0, 0.2]])
    (rounded,) = round_rings([ring], 0.0001)
    assert rounded.tolist() == [[0.1235, 0.0], [0.2, 0.2], [0.0, 0.2]]
    assert round_rings([np.array([[0.0, 0.0], [0.00001, 0.0]])], 0.0001) == []


# --- outlines of primitives --------------------------------------------------------------


def test_rotated_box_seen_from_above_is_a_diamond() -> None:
    outline = primitive_outline(Box((0.2, 0.2, 0.1)), Pose((1.0, 0.0, 0.0), (0.0, 0.0, math.pi / 4)), "top", 48)
    half_diagonal = 0.1 * math.sqrt(2)
    assert len(outline) == 4
    assert bounds([outline]) == pytest.approx(
        [1 - half_diagonal, -half_diagonal, 1 + half_diagonal, half_diagonal], abs=1e-6
    )


def test_cylinder_and_sphere_outlines() -> None:
    wheel = Cylinder(radius=0.079, length=0.034)
    axis_y = Pose(rpy=(math.pi / 2, 0.0, 0.0))  # the wheel's axis along the link's y
    side = primitive_outline(wheel, axis_y, "side", 48)  # looking along y: a circle
    assert len(side) == 48
    assert np.linalg.norm(side, axis=1) == pytest.approx(np.full(48, 0.079))
    front = primitive_outline(wheel, axis_y, "front", 48)  # looking along x: a rectangle 0.034 x 0.158
    assert bounds([front]) == pytest.approx([-0.017, -0.079, 0.017, 0.079], abs=1e-9)
    ball = primitive_outline(Sphere(0.05), Pose((0.0, 0.2, 0.3)), "front", 36)
    assert np.linalg.norm(ball - [0.2, 0.3], axis=1) == pytest.approx(np.full(36, 0.05))


# --- the views section -------------------------------------------------------------------


def make_context(tmp_path: Path, robot: Robot) -> CheckContext:
    root = tmp_path / "robot.urdf"
    root.write_text('<robot name="r"/>', encoding="utf-8")
    bundle = make_bundle(root, display_root=tmp_path)
    loaded = LoadedDescription(bundle, robot, ExpandedDocument("", "robot.urdf", {}, False), ())
    return CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions())


@pytest.fixture
def base_robot(tmp_path: Path) -> CheckContext:
    """A base shell 0.66 x 0.66 x 0.9 m with a 4 cm collision slab, two identical wheels, a
    link whose mesh is missing, a link with only a collision sphere, a frame without geometry."""
    box_mesh((0.66, 0.66, 0.9), (0.0, 0.0, 0.45)).export(tmp_path / "base.stl")
    wheel = trimesh.creation.cylinder(radius=0.079, height=0.034, sections=64)
    wheel.apply_transform(trimesh.transformations.rotation_matrix(math.pi / 2, [1, 0, 0]))
    wheel.export(tmp_path / "wheel.stl")
    wheel_collision = Shape("collision", 0, Cylinder(0.079, 0.034), Pose(rpy=(math.pi / 2, 0.0, 0.0)))
    robot = Robot(
        "r",
        links=(
            Link(
                "base_link",
                visuals=(Shape("visual", 0, Mesh("base.stl")),),
                collisions=(Shape("collision", 0, Box((0.65, 0.65, 0.04)), Pose((0.0, 0.0, 0.071))),),
            ),
            Link("l_wheel", visuals=(Shape("visual", 0, Mesh("wheel.stl")),), collisions=(wheel_collision,)),
            Link("r_wheel", visuals=(Shape("visual", 0, Mesh("wheel.stl")),), collisions=(wheel_collision,)),
            Link("lost", visuals=(Shape("visual", 0, Mesh("missing.stl")),)),
            Link("bumper", collisions=(Shape("collision", 0, Sphere(0.05), Pose((0.1, 0.0, 0.0))),)),
            Link("frame"),
        ),
    )
    return make_context(tmp_path, robot)


def views_of(ctx: CheckContext) -> dict[str, dict]:
    fit_family.run(ctx)
    section = views_family.run(ctx).sections["views"]
    return {entry["link"]: entry for entry in section}


def test_views_section_draws_every_link_with_geometry(base_robot: CheckContext) -> None:
    views = views_of(base_robot)
    assert list(views) == ["base_link", "l_wheel", "r_wheel", "lost", "bumper"]  # document order, no "frame"
    base = views["base_link"]
    assert base["scale_m"] == 0.9
    front = base["front"]
    assert front["axes"] == ["y", "z"] and base["side"]["axes"] == ["x", "z"] and base["top"]["axes"] == ["x", "y"]
    assert bounds([np.array(r) for r in front["mesh"]]) == [-0.33, 0.0, 0.33, 0.9]
    # the thin collision slab: 4 cm of the base's 90 cm
    assert bounds([np.array(r) for r in front["collision"]]) == pytest.approx([-0.325, 0.051, 0.325, 0.091])
    # the fit family's suggested box encloses the shell
    assert bounds([np.array(r) for r in front["suggested"]]) == pytest.approx([-0.33, 0.0, 0.33, 0.9], abs=2e-3)
    assert front["bounds"] == pytest.approx([-0.33, 0.0, 0.33, 0.9], abs=2e-3)


def test_views_of_identical_links_are_shared_and_rounded(base_robot: CheckContext) -> None:
    views = views_of(base_robot)
    left, right = dict(views["l_wheel"]), dict(views["r_wheel"])
    assert left.pop("link") == "l_wheel" and right.pop("link") == "r_wheel"
    assert left == right
    side = np.array(left["side"]["collision"][0])
    assert np.linalg.norm(side, axis=1) == pytest.approx(np.full(48, 0.079), abs=1e-4)
    coordinates = np.array([c for v in VIEWS for key in ("mesh", "collision") for r in left[v][key] for c in r])
    assert np.allclose(coordinates * 1e4, np.round(coordinates * 1e4), atol=1e-6)  # 0.1 mm steps


def test_views_note_missing_meshes_and_fall_back_to_collision_geometry(base_robot: CheckContext) -> None:
    views = views_of(base_robot)
    lost = views["lost"]
    assert lost["scale_m"] == 0.0 and lost["front"]["mesh"] == [] and lost["front"]["bounds"] is None
    assert lost["unavailable"][0].startswith("visual[0]: mesh file not found")
    bumper = views["bumper"]
    assert bumper["scale_m"] == pytest.approx(0.1, abs=1e-3)
    assert bounds([np.array(r) for r in bumper["top"]["collision"]]) == pytest.approx([0.05, -0.05, 0.15, 0.05])


def test_views_section_is_deterministic_json(base_robot: CheckContext) -> None:
    first = json.dumps(views_of(base_robot), allow_nan=False)
    again = CheckContext(loaded=base_robot.loaded, meshes=base_robot.meshes, options=base_robot.options)
    assert json.dumps(views_of(again), allow_nan=False) == first  # fitted and drawn anew


def test_silhouettes_of_a_dense_mesh_are_fast() -> None:
    sphere = trimesh.creation.icosphere(subdivisions=6, radius=0.2)  # 81920 faces
    start = time.process_time()
    views = mesh_silhouettes(sphere.vertices, sphere.faces, 0.4 / 160)
    simplify_rings([r for v in VIEWS for r in views[v]], 0.4 * 0.004)
    assert time.process_time() - start < 3.0
    assert all(len(views[v]) == 1 for v in VIEWS)


@pytest.mark.corpus
def test_full_pr2_views_are_small_and_quick(pr2_root: Path) -> None:
    from geomcheck.checks import family_runners
    from geomcheck.load import load_description

    bundle = make_bundle(pr2_root / "pr2_description/robots/pr2.urdf.xacro", search=[pr2_root])
    options = CheckOptions(sweep=False)
    loaded = load_description(bundle, {}, options.thresholds.limits)
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=options)
    for name, run in family_runners():
        if name in ("meshes", "fit"):
            run(ctx)
    start = time.process_time()
    section = views_family.run(ctx).sections["views"]
    elapsed = time.process_time() - start
    size = len(json.dumps(section))
    print(f"\nviews of the full 2009 PR2: {len(section)} links, {elapsed:.3f} s CPU, {size / 1024:.0f} KiB JSON")
    assert elapsed < 1.5  # target 0.5 s; generous for a loaded CI machine
    assert size < 600_000
    base = next(e for e in section if e["link"] == "base_link")
    mesh = bounds([np.array(r) for r in base["front"]["mesh"]])
    slab = bounds([np.array(r) for r in base["front"]["collision"]])
    assert mesh[3] - mesh[1] == pytest.approx(0.903, abs=0.01)
    assert slab[3] - slab[1] == pytest.approx(0.04, abs=0.002)


def test_a_convex_outline_is_written_one_way_whatever_the_last_digits() -> None:
    square = np.array([[0.01, 0.01], [-0.01, 0.01], [-0.01, -0.01], [0.01, -0.01], [0.0, 0.01]])
    noisy = square[[2, 4, 0, 3, 1]] + np.array([1e-13, -1e-13])  # another order, other last digits
    expected = [[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]]  # from the smallest, ccw
    assert canonical_outline(square, 0.0001).tolist() == expected
    assert canonical_outline(noisy, 0.0001).tolist() == expected  # the point on the top edge is dropped


def test_a_flat_outline_is_its_two_ends() -> None:
    segment = np.array([[0.02, 0.0], [0.0, 0.0], [0.01, 0.0]])
    assert canonical_outline(segment, 0.0001).tolist() == [[0.0, 0.0], [0.02, 0.0]]
