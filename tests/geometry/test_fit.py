"""Fit metrics, suggested primitives, collision-mesh comparison, unit inference and shared
geometry across joints (geomcheck.geometry.fit, suggest, meshfit, units, neighbours)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from geomcheck.geometry.fit import CollisionElement, VisualCloud, fit_link, percentile
from geomcheck.geometry.neighbours import invariant, moved, neighbours
from geomcheck.geometry.suggest import fmt, suggest
from geomcheck.geometry.surface import Solid, Surface
from geomcheck.geometry.units import infer_unit_factor, match_factor, median, plausible_factor
from geomcheck.model import Box, Cylinder, Joint, Link, Pose, Robot, Sphere
from geomcheck.thresholds import FitThresholds

TH = FitThresholds()
BOX_SIZE = (0.3, 0.2, 0.1)  # [m]
WHEEL_RADIUS, WHEEL_WIDTH = 0.079, 0.034  # the 2009 PR2 wheel [m]
Z_ONTO_Y = Pose(rpy=(np.pi / 2, 0.0, 0.0))


def cloud(mesh: trimesh.Trimesh, pose: Pose = Pose()) -> VisualCloud:
    solid = Solid.of(Surface.from_mesh(mesh, pose.rotation(), np.array(pose.xyz)))
    return VisualCloud.of([solid], TH.surface_samples, TH.seed)


def element(primitive: Box | Cylinder | Sphere, pose: Pose = Pose(), index: int = 0) -> CollisionElement:
    return CollisionElement(index, pose.rotation(), np.array(pose.xyz, dtype=float), primitive)


def box_cloud() -> VisualCloud:
    return cloud(trimesh.creation.box(extents=BOX_SIZE))


def wheel_cloud() -> VisualCloud:
    return cloud(trimesh.creation.cylinder(radius=WHEEL_RADIUS, height=WHEEL_WIDTH, sections=64), Z_ONTO_Y)


def test_matching_box_fits_exactly() -> None:
    fit = fit_link(box_cloud(), [element(Box(BOX_SIZE))], TH)
    f = fit.elements[0]
    assert f.coverage == 1.0 and f.protrusion_max == pytest.approx(0.0, abs=1e-12)
    assert f.gaps == pytest.approx(dict.fromkeys(("x-", "x+", "y-", "y+", "z-", "z+"), 0.0), abs=1e-12)
    assert f.slack == pytest.approx(1.0)
    assert f.covers(TH) and not f.disjoint(TH)
    assert f.suggested is not None and f.suggested.frame == "element"
    assert f.suggested.urdf() == '<origin xyz="0 0 0" rpy="0 0 0"/>\n<geometry><box size="0.3 0.2 0.1"/></geometry>'
    assert fit.coverage == 1.0


def test_box_shrunk_on_one_axis_sticks_out_by_the_difference() -> None:
    f = fit_link(box_cloud(), [element(Box((0.21, 0.2, 0.1)))], TH).elements[0]
    assert f.protrusion_max == pytest.approx(0.045)  # (0.30 - 0.21) / 2
    assert f.gaps is not None and f.gaps["x-"] == pytest.approx(-0.045) and f.gaps["x+"] == pytest.approx(-0.045)
    # covered within 10 mm: |x| <= 0.115 m of the four long faces; the two end faces stick out
    long_faces, end_faces = 2 * 0.3 * 0.2 + 2 * 0.3 * 0.1, 2 * 0.2 * 0.1
    assert f.coverage == pytest.approx(long_faces * 0.23 / 0.3 / (long_faces + end_faces), abs=0.03)
    assert not f.covers(TH) and not f.fits_when_moved
    assert f.extent is not None and f.extent["x"][0] == pytest.approx(0.7)


def test_offset_box_would_fit_when_moved() -> None:
    f = fit_link(box_cloud(), [element(Box(BOX_SIZE), Pose((0.1, 0.0, 0.0)))], TH).elements[0]
    assert not f.covers(TH) and f.fits_when_moved
    assert f.shift == pytest.approx([-0.1, 0.0, 0.0])
    far = fit_link(box_cloud(), [element(Box(BOX_SIZE), Pose((1.0, 0.0, 0.0)))], TH).elements[0]
    assert far.disjoint(TH) and far.mesh_inside == 0.0 and far.in_hull == 0.0


def test_wheel_cylinder_on_the_right_axis_covers_within_tolerance() -> None:
    # the PR2's effective radius 0.0748 m is 4 mm inside the 0.079 m tyre: within 10 mm
    f = fit_link(wheel_cloud(), [element(Cylinder(0.074792, WHEEL_WIDTH), Z_ONTO_Y)], TH).elements[0]
    assert f.covers(TH) and f.axis_alternative is None
    assert f.protrusion_max == pytest.approx(0.0042, abs=1e-4)


def test_wheel_cylinder_on_the_wrong_axis_has_a_better_alternative() -> None:
    f = fit_link(wheel_cloud(), [element(Cylinder(WHEEL_RADIUS, WHEEL_WIDTH))], TH).elements[0]
    alt = f.axis_alternative
    assert not f.covers(TH) and f.coverage is not None and f.coverage < 0.5
    assert alt is not None and alt.axis_name == "y" and alt.coverage == 1.0
    assert abs(alt.axis @ [0.0, 1.0, 0.0]) == pytest.approx(1.0)
    assert f.suggested is not None and f.suggested.type == "cylinder"
    assert f.suggested.primitive == Cylinder(pytest.approx(WHEEL_RADIUS), pytest.approx(WHEEL_WIDTH))  # type: ignore[arg-type]


def test_suggested_cylinder_prefers_a_link_axis() -> None:
    s = suggest(Cylinder, wheel_cloud().vertices, wheel_cloud().samples, wheel_cloud().hull, None, 0.1, 0.01)
    assert s is not None and s.frame == "link"
    assert 'rpy="1.5708 0 0"' in s.urdf() and s.coverage == 1.0


def test_suggested_box_for_a_turned_box_is_oriented() -> None:
    turned = cloud(trimesh.creation.box(extents=BOX_SIZE), Pose((0.0, 0.0, 0.5), (0.0, 0.0, 0.4)))
    s = suggest(Box, turned.vertices, turned.samples, turned.hull, None, 0.1, 0.01)
    assert s is not None and s.frame == "oriented"
    assert sorted(s.primitive.size) == pytest.approx([0.1, 0.2, 0.3])  # type: ignore[union-attr]
    assert s.to_dict()["origin"]["rpy"] == pytest.approx([0.0, 0.0, 0.4], abs=1e-6)


def test_sphere_suggestion_encloses() -> None:
    v = box_cloud()
    s = suggest(Sphere, v.vertices, v.samples, v.hull, None, 0.1, 0.0)
    assert s is not None and s.primitive == Sphere(pytest.approx(np.linalg.norm(BOX_SIZE) / 2))  # type: ignore[arg-type]
    assert s.coverage == 1.0


def test_union_of_two_boxes_is_judged_together() -> None:
    halves = [
        element(Box((0.15, 0.2, 0.1)), Pose((-0.075, 0, 0)), 0),
        element(Box((0.15, 0.2, 0.1)), Pose((0.075, 0, 0)), 1),
    ]
    fit = fit_link(box_cloud(), halves, TH)
    assert fit.coverage == 1.0 and fit.protrusion_max == pytest.approx(0.0, abs=1e-12)
    assert all(f.covers(TH) for f in fit.elements)
    # each half answers for its own half of the mesh
    assert all(f.part_points > 0 for f in fit.elements)


def test_borrowed_elements_take_their_share() -> None:
    left = element(Box((0.15, 0.2, 0.1)), Pose((-0.075, 0, 0)))
    right = element(Box((0.15, 0.2, 0.1)), Pose((0.075, 0, 0)), 1)
    fit = fit_link(box_cloud(), [left], TH, borrowed=[right])
    assert fit.coverage == 1.0 and fit.elements[0].covers(TH)
    assert fit.borrowed_share == pytest.approx(0.5, abs=0.05)


def test_collision_mesh_comparison() -> None:
    visual = box_cloud()
    shell = trimesh.creation.box(extents=[0.32, 0.22, 0.12])
    solid = Solid.of(Surface.from_mesh(shell, np.eye(3), np.zeros(3)))
    f = fit_link(visual, [CollisionElement(0, np.eye(3), np.zeros(3), solid=solid)], TH).elements[0]
    assert f.covers(TH) and f.comparison is not None
    # outside a hull the distance is the farthest facet plane's: 10 mm at the corners (truly 17 mm)
    assert f.comparison.overshoot_max == pytest.approx(0.01, abs=1e-6)
    assert f.comparison.gaps["x+"] == pytest.approx(0.01)
    moved_away = Solid.of(Surface.from_mesh(shell, np.eye(3), np.array([0.0, 0.0, 0.08])))
    g = fit_link(visual, [CollisionElement(0, np.eye(3), np.zeros(3), solid=moved_away)], TH).elements[0]
    assert not g.covers(TH) and g.protrusion_max == pytest.approx(0.07, abs=1e-6)


def test_percentile_matches_numpy() -> None:
    values = np.random.default_rng(0).normal(size=1001)
    assert percentile(values, 95.0) == pytest.approx(np.percentile(values, 95))
    assert percentile(values[:2], 95.0) == pytest.approx(np.percentile(values[:2], 95))


def test_fmt_for_urdf() -> None:
    assert [fmt(0.45162), fmt(-0.0), fmt(2.0), fmt(-1e-7), fmt(1.5707963, 4)] == ["0.4516", "0", "2", "0", "1.5708"]


@pytest.mark.parametrize(
    ("ratio", "factor"),
    [(1000.0, 1000.0), (1100.0, 1000.0), (0.001, 0.001), (100.0, 100.0), (25.4, 25.4), (39.0, 1 / 0.0254)],
)
def test_match_factor(ratio: float, factor: float) -> None:
    found = match_factor(ratio, 0.25)
    assert found is not None and found[0] == pytest.approx(factor)


def test_match_factor_rejects_ordinary_ratios() -> None:
    assert [match_factor(r, 0.25) for r in (1.0, 3.0, 10.0, 60.0, 300.0)] == [None] * 5


def test_infer_unit_factor_needs_the_robot_to_agree() -> None:
    # a 300 m mesh on a link whose box is 0.3 m, on a robot of 0.25 m links: millimetres
    verdict = infer_unit_factor(300.0, 0.3, 0.25, 0.25)
    assert verdict is not None and verdict.factor == 1000.0 and verdict.scale_factor == 0.001
    # the 2009 PR2 tilting laser: 0.11 m against a 1 mm placeholder box, robot links ~1 cm
    assert infer_unit_factor(0.11, 0.001, 0.01, 0.25) is None
    # mesh-only references need the robot
    assert infer_unit_factor(300.0, 0.3, None, 0.25, link_reference_trusted=False) is None
    # robot alone: only the factor 1000 counts
    assert infer_unit_factor(25.0, None, 0.25, 0.25) is None
    only_robot = infer_unit_factor(250.0, None, 0.25, 0.25)
    assert only_robot is not None and only_robot.reference == "robot"


def test_plausible_factor_and_median() -> None:
    guess = plausible_factor(40.0, 0.3)
    assert guess is not None and guess[0] == 100.0
    assert median([3.0, 1.0, 2.0, 0.0, float("nan")]) == 2.0 and median([]) is None


def test_neighbours_and_invariance_across_a_revolute_joint() -> None:
    robot = Robot(
        "r",
        links=(Link("a"), Link("b")),
        joints=(Joint("j", "revolute", "a", "b", Pose((0.0, 0.0, 0.5)), axis=(0.0, 0.0, 1.0)),),
    )
    [from_a] = neighbours(robot, "a")
    [from_b] = neighbours(robot, "b")
    assert from_a.link == "b" and from_a.point == pytest.approx([0, 0, 0.5])
    assert from_b.link == "a" and from_b.translation == pytest.approx([0, 0, -0.5])
    on_axis = moved(element(Sphere(0.1), Pose((0.0, 0.0, 0.2))), from_a.rotation, from_a.translation)
    off_axis = moved(element(Sphere(0.1), Pose((0.1, 0.0, 0.2))), from_a.rotation, from_a.translation)
    along = moved(element(Cylinder(0.1, 0.3)), from_a.rotation, from_a.translation)
    across = moved(element(Cylinder(0.1, 0.3), Z_ONTO_Y), from_a.rotation, from_a.translation)
    assert on_axis.translation == pytest.approx([0, 0, 0.7])
    assert [invariant(e, from_a) for e in (on_axis, off_axis, along, across)] == [True, False, True, False]
    assert not invariant(element(Box((0.1, 0.1, 0.1))), from_a)


def test_a_mesh_too_large_must_outgrow_its_links_span() -> None:
    # a 0.184 m housing among 7 mm screws (median 7 mm: ratio 26, near 25.4), with a rail and
    # mirrors spanning 0.18 m: the housing is the link's size, not 25.4x too large
    assert infer_unit_factor(0.184, 0.007, None, 0.25, link_span=0.18) is None
    # the same housing exported in millimetres read as inches: 25.4x the span
    verdict = infer_unit_factor(0.184 * 25.4, 0.184, None, 0.25, link_span=0.18)
    assert verdict is not None and verdict.factor == pytest.approx(25.4)
    # twice the span is enough, whatever the factor (a 5 cm sensor on a 0.5 m box, in mm)
    assert infer_unit_factor(50.0, 0.05, 0.05, 0.25, link_span=0.5) is not None
    # too small: the span says nothing (a mesh 1000x too small is inside any span)
    small = infer_unit_factor(0.0003, 0.3, 0.3, 0.25, link_span=0.6)
    assert small is not None and small.factor == pytest.approx(0.001)
    # the robot-only path (factor 1000) also needs the mesh to outgrow the link's joints
    assert infer_unit_factor(250.0, None, 0.25, 0.25, link_span=200.0) is None


def test_a_mesh_too_small_must_stay_on_the_robot_once_scaled_up() -> None:
    # a sesamoid bone 2.6 mm across among 60 mm bones (ratio 0.043, near 1/25.4), drawn 169 mm
    # from its file's origin (a skeleton's shared frame) on a robot 1.1 m across: scaled up
    # 25.4x it would lie 4.3 m away: a small part, not one in another unit
    assert infer_unit_factor(0.0026, 0.06, 0.065, 0.25, offset=0.169, robot_extent=1.1) is None
    # the same part drawn about its own origin (a part exported alone): the unit may be wrong
    verdict = infer_unit_factor(0.0026, 0.06, 0.065, 0.25, offset=0.0013, robot_extent=1.1)
    assert verdict is not None and verdict.factor == pytest.approx(1 / 25.4)
    # a mesh 1000x too small shrank towards its origin too: scaled back, it lands on the robot
    assert infer_unit_factor(0.0003, 0.3, 0.3, 0.25, offset=0.0002, robot_extent=1.0) is not None
    # a mesh too large is judged by the span, not the offset
    assert infer_unit_factor(300.0, 0.3, 0.25, 0.25, offset=500.0, robot_extent=1.0) is not None


def test_capsule_along_an_axis_is_the_least_capsule_enclosing_the_points() -> None:
    from geomcheck.geometry.primitives import signed_distance, volume
    from geomcheck.geometry.suggest import capsule_along
    from geomcheck.model import Capsule

    # the surface points of a capsule of radius 2 cm and straight part 10 cm along x, centred at (0.1, 0, 0)
    rng = np.random.default_rng(7)
    t = rng.uniform(-0.07, 0.07, 4000)
    direction = rng.normal(size=(4000, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    on_axis = np.column_stack((np.clip(t, -0.05, 0.05), np.zeros(4000), np.zeros(4000)))
    points = on_axis + 0.02 * direction + np.array([0.1, 0.0, 0.0])
    along_x = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
    fitted = capsule_along(points, along_x, np.array([0.1, 0.0, 0.0]))
    assert isinstance(fitted, Capsule)
    assert fitted.radius == pytest.approx(0.02, abs=2e-4)
    assert fitted.straight_length == pytest.approx(0.10, abs=1e-3)
    # it encloses every point
    local = (points - np.array([0.1, 0.0, 0.0])) @ along_x
    assert signed_distance(fitted, local).max() <= 1e-9
    assert volume(fitted) == pytest.approx(np.pi * 0.02**2 * 0.1 + 4 / 3 * np.pi * 0.02**3, rel=0.02)
