"""The solid-of-revolution bound of a wheel spinning on a swivelling caster: its soundness, and
the two-angle sweep it settles without searching the spin."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.selfcollision.revolution import (
    cross_section,
    goes_round,
    polytope_points,
    revolution_bound,
    spinning_joints,
)
from geomcheck.selfcollision.sweep import SweepSettings, sweep_joint
from geomcheck.selfcollision.sweep_plan import plan_pairs, sweep_groups
from geomcheck.thresholds import SelfCollisionThresholds

TRAIL = 0.03  # wheel axle behind the swivel axis [m]
RADIUS = 0.025  # wheel [m]
WIDTH = 0.02  # wheel [m]
GAP = 0.002  # wall beyond the furthest reach of the wheel's rim circle [m]


def caster_urdf(wheel: str = "wheel.stl") -> str:
    # the furthest the rim circle reaches from the swivel axis: the rim's outer corner
    reach = math.hypot(TRAIL + RADIUS, WIDTH / 2)
    return f"""<robot name="caster">
  <link name="base_link">
    <collision><origin xyz="{reach + GAP + 0.005} 0 0.05"/><geometry><box size="0.01 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="caster_joint" type="continuous">
    <parent link="base_link"/><child link="caster_link"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
  </joint>
  <link name="caster_link">
    <collision><geometry><box size="0.01 0.01 0.01"/></geometry></collision>
  </link>
  <joint name="wheel_joint" type="continuous">
    <parent link="caster_link"/><child link="wheel_link"/><origin xyz="{TRAIL} 0 -0.05"/><axis xyz="0 1 0"/>
  </joint>
  <link name="wheel_link">
    <collision><origin rpy="1.5707963267948966 0 0"/><geometry><mesh filename="{wheel}"/></geometry></collision>
  </link>
</robot>
"""


def setup(tmp_path: Path, backend: str, wheel: str = "wheel.stl") -> tuple[Kinematics, CollisionScene, np.ndarray]:
    import trimesh

    # a faceted tread: the distance to the wall changes with the spin by the facets' sagitta
    trimesh.creation.cylinder(radius=RADIUS, height=WIDTH, sections=24).export(tmp_path / "wheel.stl")
    trimesh.creation.box(extents=(2 * RADIUS, 2 * RADIUS, WIDTH)).export(tmp_path / "paddle.stl")
    path = tmp_path / "robot.urdf"
    path.write_text(caster_urdf(wheel))
    bundle = make_bundle(path, display_root=tmp_path)
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    return kin, CollisionScene(robot, MeshStore(bundle), get_backend(backend)), kin.default_configuration()


def wheel_plan(kin: Kinematics, scene: CollisionScene, q0: np.ndarray):
    [group] = [g for g in sweep_groups(kin, scene, q0) if g.joint.name == "caster_joint"]
    _, plans = plan_pairs(kin, scene, group, q0, adjacent_pairs(kin.robot, scene.links))
    return group, next(p for p in plans if p.links == ("wheel_link", "base_link"))


def test_the_polytope_holds_the_points_turned_to_any_spin() -> None:
    rng = np.random.default_rng(5)
    points = rng.normal(0.0, 0.03, (40, 3))
    point, direction = np.array([0.01, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    hull = ConvexHull(polytope_points(cross_section(points, 0.001, point, direction), point, direction))
    for angle in np.linspace(0.0, 2 * math.pi, 37):
        c, s = math.cos(angle), math.sin(angle)
        turn = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # about y
        turned = (points - point) @ turn.T + point
        # each point and the pad's reach along every axis stay inside every facet of the hull
        for pad in np.concatenate([np.eye(3), -np.eye(3)]) * 0.001:
            inside = hull.equations[:, :3] @ (turned + pad).T + hull.equations[:, 3:]
            assert inside.max() <= 1e-12


def test_only_a_rim_that_goes_round_is_a_wheel() -> None:
    t = np.linspace(0.0, 2 * math.pi, 24, endpoint=False)
    rim = np.stack([np.cos(t), np.zeros_like(t), np.sin(t)], axis=1)
    y_axis = (np.zeros(3), np.array([0.0, 1.0, 0.0]))
    assert goes_round(rim, 0.0, *y_axis)
    bar = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.1, 0.0]])  # spinning about one end
    assert not goes_round(bar, 0.0, *y_axis)


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_the_bound_is_below_the_distance_at_every_spin(tmp_path: Path, backend: str) -> None:
    kin, scene, q0 = setup(tmp_path, backend)
    group, plan = wheel_plan(kin, scene, q0)
    assert spinning_joints(kin, group, plan) is not None
    bound = revolution_bound(kin, scene, q0, group, plan, 0.05)
    assert bound is not None
    swivel, spin = kin.index("caster_joint"), kin.index("wheel_joint")
    rng = np.random.default_rng(7)
    angles = rng.uniform(-math.pi, math.pi, (200, 2))
    q = np.repeat(q0[None], len(angles), axis=0)
    q[:, swivel], q[:, spin] = angles[:, 0], angles[:, 1]
    frames = kin.link_transforms(q, ["wheel_link", "base_link"])
    found = bound.at(angles[:, 0], frames[:, 0])
    exact = np.array([scene.pair_distance("wheel_link", f[0], "base_link", f[1]) for f in frames])
    assert (found <= exact + 1e-6).all()  # the engines' distances are good to about 1e-6 m (GJK)
    # and it is tight: within the facets' sagitta (and the polytope's bulge) of the closest spin
    facing = np.abs(np.abs(angles[:, 0]) - math.atan2(WIDTH / 2, TRAIL + RADIUS)) < 0.05
    assert facing.any() and (exact[facing] - found[facing]).min() < 3e-4


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_the_caster_sweep_proves_the_wheel_without_searching_the_spin(tmp_path: Path, backend: str) -> None:
    kin, scene, q0 = setup(tmp_path, backend)
    settings = SweepSettings.from_thresholds(SelfCollisionThresholds())
    [group] = [g for g in sweep_groups(kin, scene, q0) if g.joint.name == "caster_joint"]
    assert group.dimensions == ("caster_joint", "wheel_joint")  # a faceted mesh wheel is not round
    result = sweep_joint(kin, scene, q0, adjacent_pairs(kin.robot, scene.links), settings, group)
    wheel = next(p for p in result.pairs if p.links == ("wheel_link", "base_link"))
    assert wheel.proven and not wheel.colliding
    assert wheel.queries < 4 * settings.grid_points  # the spin is never searched
    # the rim's outer corner passes the wall GAP away, facing it (minus the facets' sagitta)
    assert wheel.clearance_bound <= GAP <= wheel.min_clearance + RADIUS * (1 - math.cos(math.pi / 24))
    assert wheel.min_clearance - wheel.clearance_bound <= settings.clearance_resolution
    # closest where a rim corner faces the wall square on
    assert abs(wheel.min_angle) == pytest.approx(math.atan2(WIDTH / 2, TRAIL + RADIUS), abs=0.03)


def test_a_paddle_is_not_bounded_by_its_solid_of_revolution(tmp_path: Path) -> None:
    kin, scene, q0 = setup(tmp_path, "coal", wheel="paddle.stl")
    group, plan = wheel_plan(kin, scene, q0)
    assert revolution_bound(kin, scene, q0, group, plan, 0.05) is None  # corners, no rim all round


def test_no_bound_when_the_engines_would_not_hold_the_polytope_exactly(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import dataclasses

    from geomcheck.collision import base

    kin, scene, q0 = setup(tmp_path, "coal")
    group, plan = wheel_plan(kin, scene, q0)
    assert revolution_bound(kin, scene, q0, group, plan, 0.05) is not None
    # a polytope of more corners than an exact hull takes would get a bounded hull, inside it
    monkeypatch.setattr(base, "ANALYSIS", dataclasses.replace(base.ANALYSIS, hull_exact_points=100))
    assert revolution_bound(kin, scene, q0, group, plan, 0.05) is None
