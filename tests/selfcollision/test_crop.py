"""Meshes cut to what the other link of a sweep can reach: same distances, fewer triangles."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.collision.base import SEPARATION_MARGIN, MeshArrays
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.selfcollision import crop, sweep
from geomcheck.selfcollision.crop import box_distances, kept_faces, part_mesh, reach, still_parts, turning_parts
from geomcheck.selfcollision.sweep import SweepSettings, sweep_joint
from geomcheck.selfcollision.sweep_plan import sweep_groups
from geomcheck.thresholds import SelfCollisionThresholds


def test_box_distances_are_from_the_point_to_each_triangle_box() -> None:
    triangles = np.array(
        [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],  # box [0, 1] x [0, 1] x [0, 0]
            [[2.0, 2.0, 1.0], [3.0, 2.0, 1.0], [2.0, 3.0, 2.0]],  # box [2, 3] x [2, 3] x [1, 2]
        ]
    )
    np.testing.assert_allclose(box_distances(triangles, np.array([0.5, 0.5, 2.0])), [2.0, np.hypot(1.5, 1.5)])
    # inside a box: 0, a lower bound of the distance to the triangle (0.5 here)
    assert box_distances(triangles[1:], np.array([2.5, 2.5, 1.5]))[0] == 0.0


def test_reach_keeps_a_fraction_of_the_sphere_and_at_least_the_margin() -> None:
    assert reach(np.zeros(3), 0.1, 0.005).keep == pytest.approx(crop.KEEP_FRACTION * 0.1)
    assert reach(np.zeros(3), 0.004, 0.005).keep == 0.005


def test_part_keeps_the_triangles_near_the_sphere_with_their_coordinates() -> None:
    plate = trimesh.creation.box(extents=(1.0, 1.0, 0.02))
    plate = plate.subdivide().subdivide().subdivide()  # 768 triangles, each at most 1/8 of a face
    triangles = plate.vertices[plate.faces]
    near = reach(np.array([0.3, 0.3, 0.06]), 0.04, 0.005)  # 0.05 above the top face (z = 0.01)
    faces = kept_faces(triangles, near)
    gaps = box_distances(triangles, near.centre) - near.radius
    assert set(faces) == set(np.flatnonzero(gaps < near.keep))
    assert 0 < len(faces) < len(triangles) / 10  # a few top triangles near (0.3, 0.3)
    assert (triangles[faces][..., 2] > 0).any(axis=1).all()  # none of the bottom face
    part = part_mesh(MeshArrays(np.asarray(plate.vertices), np.asarray(plate.faces)), faces)
    np.testing.assert_array_equal(part.vertices[part.faces], triangles[faces])  # the very same coordinates
    assert len(part.vertices) == len(np.unique(plate.faces[faces]))


PLATE_URDF = """<?xml version="1.0"?>
<robot name="plate">
  <link name="plate_link"><collision><geometry><mesh filename="plate.stl"/></geometry></collision></link>
  <joint name="spin" type="continuous">
    <parent link="plate_link"/><child link="wheel_link"/>
    <origin xyz="0.3 0.3 0.075" rpy="1.5707963 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <link name="wheel_link">
    <collision><origin xyz="0.01 0 0"/><geometry><mesh filename="wheel.stl"/></geometry></collision>
  </link>
</robot>
"""


def plate_robot(tmp_path: Path, backend: str = "coal") -> tuple[Kinematics, CollisionScene, np.ndarray]:
    """A wheel (radius 0.04, 2 cm wide, off its horizontal axis by 1 cm) spinning with its axis
    0.065 above the top (z = 0.01) of a 1 m plate of 768 triangles: 0.015 to 0.035 apart."""
    plate = trimesh.creation.box(extents=(1.0, 1.0, 0.02)).subdivide().subdivide().subdivide()
    plate.export(tmp_path / "plate.stl")
    trimesh.creation.cylinder(radius=0.04, height=0.02, sections=48).export(tmp_path / "wheel.stl")
    (tmp_path / "robot.urdf").write_text(PLATE_URDF)
    bundle = make_bundle(tmp_path / "robot.urdf", display_root=tmp_path)
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    return kin, CollisionScene(robot, MeshStore(bundle), get_backend(backend)), kin.default_configuration()


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_distance_to_the_part_is_the_distance_to_the_whole_mesh(tmp_path: Path, backend: str) -> None:
    kin, scene, q0 = plate_robot(tmp_path, backend)
    near = reach(np.array([0.3, 0.3, 0.075]), 0.06, 0.005)  # holds the wheel over the whole turn
    [part] = still_parts(scene, "plate_link", np.eye(4), near)
    assert part is not None and part.exact_below == near.keep - SEPARATION_MARGIN
    plate = scene.scene_shapes("plate_link")[0]
    [pb] = scene.placements("plate_link", np.eye(4)[None])[0]
    for angle in np.linspace(-np.pi, np.pi, 9):
        q = q0.copy()
        q[kin.index("spin")] = angle
        [pa] = scene.placements("wheel_link", kin.link_transforms(q[None], ["wheel_link"])[0])[0]
        whole = scene.backend.placed_distance(scene.scene_shapes("wheel_link")[0].obj, pa, plate.obj, pb)
        on_part = scene.backend.placed_distance(scene.scene_shapes("wheel_link")[0].obj, pa, part.obj, pb)
        # the wheel's centre runs 0.065 +- 0.01 above the top (sin: the offset is across the axis)
        assert whole == pytest.approx(0.065 - 0.04 + 0.01 * abs(np.sin(angle)) * np.sign(whole - 0.025), abs=3e-4)
        assert on_part == whole  # the same closest triangles: the same number
        assert scene.placed_closest("wheel_link", [pa], "plate_link", [pb], parts=[part]) == (whole, 0, 0)


def test_beyond_the_part_the_whole_mesh_is_asked(tmp_path: Path) -> None:
    _, scene, _ = plate_robot(tmp_path)
    near = reach(np.array([0.3, 0.3, 0.075]), 0.06, 0.005)
    [part] = still_parts(scene, "plate_link", np.eye(4), near)
    assert part is not None
    far = np.eye(4)
    far[:3, 3] = (-0.4, -0.4, 0.2)  # lying flat far from the part: its nearest plate triangles were dropped
    [pa] = scene.placements("wheel_link", far[None])[0]
    [pb] = scene.placements("plate_link", np.eye(4)[None])[0]
    wheel, plate = scene.scene_shapes("wheel_link")[0].obj, scene.scene_shapes("plate_link")[0].obj
    assert scene.backend.placed_distance(wheel, pa, part.obj, pb) >= part.exact_below
    whole = scene.backend.placed_distance(wheel, pa, plate, pb)
    assert whole == pytest.approx(0.2 - 0.01 - 0.01, abs=1e-9)  # the wheel's bottom face above the top
    assert scene.placed_closest("wheel_link", [pa], "plate_link", [pb], parts=[part])[0] == whole


def test_a_primitive_or_a_mesh_kept_whole_gets_no_part(tmp_path: Path) -> None:
    _, scene, _ = plate_robot(tmp_path)
    everywhere = reach(np.zeros(3), 1.0, 0.005)  # the whole plate is near
    assert still_parts(scene, "plate_link", np.eye(4), everywhere) is None
    nowhere = reach(np.array([0.0, 0.0, 5.0]), 0.05, 0.005)  # nothing near: the whole mesh is asked
    assert still_parts(scene, "plate_link", np.eye(4), nowhere) is None


def test_sweep_finds_the_same_with_and_without_parts(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    kin, scene, q0 = plate_robot(tmp_path)
    settings = replace(SweepSettings.from_thresholds(SelfCollisionThresholds()), clearance_margin=0.02)
    [group] = sweep_groups(kin, scene, q0)
    adjacent = adjacent_pairs(scene.robot, scene.links)
    made = []

    def spy(*args):
        made.append(turning_parts(*args))
        return made[-1]

    # one joint turns the wheel past the still plate: both are cut in (r, z) about its axis
    monkeypatch.setattr(sweep, "turning_parts", spy)
    with_parts = sweep_joint(kin, scene, q0, adjacent, settings, group)
    [([wheel_part], [plate_part])] = made
    assert plate_part is not None and len(plate_part.obj.mesh.faces) < 768 / 10
    assert plate_part.exact_below == settings.clearance_margin - SEPARATION_MARGIN
    # the plate is 65 mm from the axis: the wheel's triangles within 45 mm of it (all but the side
    # its 1 cm offset carries out) never come within the 20 mm margin of it
    assert wheel_part is not None
    assert len(wheel_part.obj.mesh.faces) < len(scene.scene_shapes("wheel_link")[0].mesh.faces)
    monkeypatch.setattr(sweep, "turning_parts", lambda *args: (None, None))
    without = sweep_joint(kin, scene, q0, adjacent, settings, group)
    [found] = with_parts.pairs
    assert with_parts == without
    assert found.proven and not found.colliding and found.links == ("wheel_link", "plate_link")
    assert found.min_clearance == pytest.approx(0.015, abs=settings.clearance_resolution)  # the wheel's dip
    assert found.queries > settings.screen_points  # closer than the margin: exact queries were made


NESTED_URDF = """<?xml version="1.0"?>
<robot name="nested">
  <link name="housing_link"><collision><geometry><mesh filename="housing.stl"/></geometry></collision></link>
  <joint name="turn" type="continuous">
    <parent link="housing_link"/><child link="rotor_link"/><axis xyz="0 0 1"/>
  </joint>
  <link name="rotor_link"><collision><geometry><mesh filename="rotor.stl"/></geometry></collision></link>
</robot>
"""


def nested(
    folder: Path, rotor: trimesh.Trimesh, housing: trimesh.Trimesh
) -> tuple[Kinematics, CollisionScene, np.ndarray]:
    """The kinematics, coal scene and default configuration of ``rotor`` turning in ``housing``
    about z (:data:`NESTED_URDF`), written in ``folder``."""
    rotor.export(folder / "rotor.stl")
    housing.export(folder / "housing.stl")
    (folder / "robot.urdf").write_text(NESTED_URDF)
    bundle = make_bundle(folder / "robot.urdf", display_root=folder)
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    return kin, CollisionScene(robot, MeshStore(bundle), get_backend("coal")), kin.default_configuration()


def test_both_links_turned_by_one_joint_are_cut_to_what_keeps_near_in_r_and_z(tmp_path: Path) -> None:
    # a rotor (a tall tube, off centre) turning inside a housing (a tube 2 mm outside its reach
    # at the top, far at the bottom): the two meshes near each other in (r, z) are the tops
    rotor = trimesh.creation.annulus(0.02, 0.03, 0.2, sections=48).subdivide().subdivide()
    rotor.apply_translation((0.005, 0.0, 0.1))
    housing = trimesh.creation.annulus(0.037, 0.05, 0.05, sections=48).subdivide().subdivide()
    housing.apply_translation((0.0, 0.0, 0.18))
    kin, scene, q0 = nested(tmp_path, rotor, housing)
    axis = (np.zeros(3), np.array([0.0, 0.0, 1.0]))
    [rotor_part], [housing_part] = turning_parts(
        scene, ("rotor_link", "housing_link"), np.stack([np.eye(4)] * 2), axis, 0.005
    )
    assert rotor_part is not None and housing_part is not None
    assert len(rotor_part.obj.mesh.faces) < len(rotor.faces) / 2  # the rotor's bottom is dropped
    assert len(housing_part.obj.mesh.faces) < len(housing.faces) * 3 / 4  # the housing's outside too
    [pb] = scene.placements("housing_link", np.eye(4)[None])[0]
    rotor_obj, housing_obj = scene.scene_shapes("rotor_link")[0].obj, scene.scene_shapes("housing_link")[0].obj
    for angle in np.linspace(-np.pi, np.pi, 7):
        q = q0.copy()
        q[kin.index("turn")] = angle
        [pa] = scene.placements("rotor_link", kin.link_transforms(q[None], ["rotor_link"])[0])[0]
        whole = scene.backend.placed_distance(rotor_obj, pa, housing_obj, pb)
        on_parts = scene.backend.placed_distance(rotor_part.obj, pa, housing_part.obj, pb)
        assert whole == pytest.approx(0.002, abs=3e-4)  # the housing's inside 2 mm beyond the rotor's reach
        assert on_parts == whole  # the same closest triangles: the same number
        found = scene.placed_closest("rotor_link", [pa], "housing_link", [pb], None, [housing_part], [rotor_part])
        assert found == (whole, 0, 0)


def test_a_flange_turning_in_its_housing_is_settled_by_the_screen_and_the_turn_bound(tmp_path: Path) -> None:
    # a tube turning about its own axis 2 mm inside a housing tube: the same clearance all round,
    # which the first grid's 360 exact queries found before; the screen's 24 and the turn bound
    # now prove the whole turn, to the clearance resolution
    rotor = trimesh.creation.annulus(0.02, 0.03, 0.1, sections=48)
    housing = trimesh.creation.annulus(0.032, 0.05, 0.06, sections=48)
    kin, scene, q0 = nested(tmp_path, rotor, housing)
    [group] = sweep_groups(kin, scene, q0)
    adjacent = adjacent_pairs(scene.robot, scene.links)
    settings = SweepSettings.from_thresholds(SelfCollisionThresholds())
    [screened] = sweep_joint(kin, scene, q0, adjacent, settings, group).pairs
    whole_grid = replace(settings, screen_points=settings.grid_points)  # every cell asked: no screen
    [asked] = sweep_joint(kin, scene, q0, adjacent, whole_grid, group).pairs
    assert screened.proven and asked.proven and not screened.colliding
    # the faceted tubes' gap: 32 mm * cos(pi / 48) - 30 mm at a facet's middle, 2 mm at its corners
    assert 0.0019 < asked.min_clearance < 0.0020
    assert screened.min_clearance == pytest.approx(asked.min_clearance, abs=settings.clearance_resolution)
    assert screened.clearance_bound <= screened.min_clearance
    assert screened.clearance_bound >= asked.min_clearance - settings.clearance_resolution
    assert asked.queries >= settings.grid_points
    assert screened.queries <= 2 * settings.screen_points
    assert len(screened.chart_angles) >= settings.screen_points
