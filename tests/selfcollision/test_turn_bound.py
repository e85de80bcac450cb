"""The turn bound: cylindrical boxes of triangles, its soundness, and a sweep it shortens."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.selfcollision.sweep import JointSweep, SweepSettings, sweep_joint
from geomcheck.selfcollision.sweep_plan import sweep_groups
from geomcheck.selfcollision.turn_bound import pair_bound, refined_bound, triangle_boxes
from geomcheck.thresholds import SelfCollisionThresholds

Z_AXIS = (np.zeros(3), np.array([0.0, 0.0, 1.0]))


def test_triangle_box_off_the_axis_has_its_radii_heights_and_azimuths() -> None:
    [box] = triangle_boxes(np.array([[[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 0.0, 1.0]]]), *Z_AXIS)
    r_min, r_max, z_min, z_max, start, width = box
    assert r_min == pytest.approx(1.0) and r_max == pytest.approx(2.0)
    assert (z_min, z_max) == (0.0, 1.0)
    # azimuths from the basis' first vector, y for the z axis (x at -90 degrees)
    assert start == pytest.approx(1.5 * math.pi) and width == pytest.approx(math.pi / 4)


def test_triangle_around_the_axis_reaches_it_at_every_azimuth() -> None:
    [box] = triangle_boxes(np.array([[[1.0, -1.0, 0.2], [1.0, 1.0, 0.2], [-1.0, 0.0, 0.3]]]), *Z_AXIS)
    assert box[0] == 0.0 and box[5] == pytest.approx(2 * math.pi)
    assert box[1] == pytest.approx(math.sqrt(2)) and (box[2], box[3]) == (0.2, 0.3)


def sampled_distance(a: np.ndarray, b: np.ndarray, n: int = 24) -> float:
    """Smallest distance between points spread over each triangle of ``a`` and ``b`` (k, 3, 3):
    at least the true distance."""
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    keep = (u + v) <= 1
    w = np.stack([1 - u[keep] - v[keep], u[keep], v[keep]], axis=1)  # barycentric (m, 3)
    pa = np.einsum("mi,kij->kmj", w, a).reshape(-1, 3)
    pb = np.einsum("mi,kij->kmj", w, b).reshape(-1, 3)
    return float(np.sqrt(((pa[:, None] - pb[None]) ** 2).sum(-1).min()))


def rotated(triangles: np.ndarray, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return triangles @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).T


def test_a_cell_proven_clear_is_never_closer_than_the_threshold() -> None:
    rng = np.random.default_rng(3)
    moving = rng.normal([0.3, 0.0, 0.0], 0.05, (4, 3, 3))
    still = rng.normal([0.0, 0.32, 0.02], 0.05, (4, 3, 3))
    bound = pair_bound(triangle_boxes(moving, *Z_AXIS), triangle_boxes(still, *Z_AXIS), 1.0, 1.0, 0.0)
    proven = 0
    for angle in np.linspace(-math.pi, math.pi, 73):
        true_at_most = sampled_distance(rotated(moving, angle), still)
        # claiming more than a distance the triangles reach would be wrong
        assert not bound.clear(np.array([angle]), np.zeros(1), true_at_most + 1e-9)[0]
        proven += bool(bound.clear(np.array([angle]), np.zeros(1), 0.5 * true_at_most)[0])
    assert proven > 36  # and it proves something: half the distance at most of the angles


def test_wider_cells_are_proven_less_often() -> None:
    moving = np.array([[[0.3, -0.01, 0.0], [0.3, 0.01, 0.0], [0.32, 0.0, 0.0]]])
    still = np.add(rotated(moving, math.pi / 2), [0.0, 0.0, 0.001])
    bound = pair_bound(triangle_boxes(moving, *Z_AXIS), triangle_boxes(still, *Z_AXIS), 0.1, 1.0, 0.0)
    # a quarter turn brings the triangles 1 mm apart; far from it they are 0.2 m apart
    assert bound.clear(np.array([0.0]), np.array([0.5]), 0.05)[0]
    assert not bound.clear(np.array([0.0]), np.array([1.5]), 0.05)[0]
    assert not bound.clear(np.array([math.pi / 2]), np.zeros(1), 0.0011)[0]
    assert bound.clear(np.array([math.pi / 2]), np.zeros(1), 0.0009)[0]


def test_cutting_large_slanted_triangles_tightens_their_boxes() -> None:
    # two strips on the cone z = r, 5 cm apart along z: their boxes overlap, their pieces do not
    moving = np.array([[[0.1, -0.01, 0.1], [0.1, 0.01, 0.1], [0.2, 0.0, 0.2]]])
    still = np.add(moving, [0.0, 0.0, 0.05])
    assert pair_bound(triangle_boxes(moving, *Z_AXIS), triangle_boxes(still, *Z_AXIS), 0.1, 1.0, 0.0).whole_turn == 0
    refined = refined_bound(moving, still, *Z_AXIS, 0.1, 1.0, 0.0)
    assert 0.005 < refined.whole_turn <= 0.05 / math.sqrt(2)


def ring_urdf() -> str:
    return """<?xml version="1.0"?>
<robot name="ring">
  <link name="tube_link"><collision><geometry><mesh filename="tube.stl"/></geometry></collision></link>
  <joint name="spin" type="continuous">
    <parent link="tube_link"/><child link="ring_link"/><axis xyz="0 0 1"/>
  </joint>
  <link name="ring_link"><collision><geometry><mesh filename="ring.stl"/></geometry></collision></link>
</robot>
"""


def ring_in_tube(folder: Path, urdf: str) -> tuple[list[JointSweep], SweepSettings]:
    """Every sweep of ``urdf`` written in ``folder`` beside a 64-gon ring of radius 0.05 and a
    tube of inner radius 0.052 (``ring.stl``, ``tube.stl``): about 1.94 mm apart at every angle."""
    import trimesh

    trimesh.creation.annulus(0.03, 0.05, 0.02, sections=64).export(folder / "ring.stl")
    trimesh.creation.annulus(0.052, 0.07, 0.04, sections=64).export(folder / "tube.stl")
    (folder / "robot.urdf").write_text(urdf)
    bundle = make_bundle(folder / "robot.urdf", display_root=folder)
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    scene = CollisionScene(robot, MeshStore(bundle), get_backend("coal"))
    q0 = kin.default_configuration()
    settings = SweepSettings.from_thresholds(SelfCollisionThresholds())
    adjacent = adjacent_pairs(robot, scene.links)
    return [sweep_joint(kin, scene, q0, adjacent, settings, g) for g in sweep_groups(kin, scene, q0)], settings


def test_ring_turning_in_a_tube_is_proven_on_its_first_grid(tmp_path: Path) -> None:
    # the Lipschitz bound alone could only prove the ring clear by halving the turn to 0.1 mm
    [swept], settings = ring_in_tube(tmp_path, ring_urdf())
    [found] = swept.pairs
    apothem = 0.052 * math.cos(math.pi / 64)
    assert found.proven and not found.colliding
    # hulls overlap: one hull and one mesh query per cell of the screen; the turn bound proves the rest
    assert found.queries == 2 * settings.screen_points
    assert apothem - 0.05 <= found.min_clearance <= apothem - 0.05 + settings.clearance_resolution
    assert found.min_clearance - settings.clearance_resolution <= found.clearance_bound <= found.min_clearance


def test_a_caster_housing_is_proven_on_its_first_grid_while_its_wheel_turns_too(tmp_path: Path) -> None:
    # the ring above as a caster's housing, with a wheel that is not round (a box: the sweep
    # searches the housing's and the wheel's angles together); the wheel's angle does not move
    # the housing, so the housing's turn bound still holds at every angle of the wheel
    wheel = """  <joint name="wheel" type="continuous">
    <parent link="ring_link"/><child link="wheel_link"/><origin xyz="0.02 0 -0.3"/><axis xyz="0 1 0"/>
  </joint>
  <link name="wheel_link"><collision><geometry><box size="0.04 0.02 0.04"/></geometry></collision></link>
</robot>"""
    swept, settings = ring_in_tube(tmp_path, ring_urdf().replace("</robot>", wheel))
    caster = swept[0]
    assert caster.group.dimensions == ("spin", "wheel")
    housing = {p.links: p for p in caster.pairs}[("ring_link", "tube_link")]
    apothem = 0.052 * math.cos(math.pi / 64)
    assert housing.proven and not housing.colliding
    assert housing.queries == 2 * settings.grid_points
    assert apothem - 0.05 <= housing.min_clearance <= apothem - 0.05 + settings.clearance_resolution
