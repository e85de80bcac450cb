"""GC302's over-coverage (geomcheck.checks.fit_oversize): a side standing off its part, the wrong
kind of shape, and the elements of a union that are not judged."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from geomcheck.diagnostics import Severity
from geomcheck.model import Box, Capsule, Cylinder, Link, Mesh, Pose, Shape, SourceLocation, Sphere
from tests.checks.fit.test_fit import (
    BOX_SIZE,
    ROOT_FILE,
    WHEEL_MESH,
    WHEEL_RADIUS,
    WHEEL_WIDTH,
    Z_ONTO_Y,
    bundle_dir,
    check,
    collision,
    link,
    only,
    robot_of,
)

__all__ = ["bundle_dir"]  # the fixture, used by name


def test_a_box_standing_off_one_side_of_its_part(bundle_dir: Path) -> None:
    # the 0.3 x 0.2 x 0.1 m part in a box 0.2 m longer on its +x side
    grown = collision(Box((BOX_SIZE[0] + 0.2, BOX_SIZE[1], BOX_SIZE[2])), Pose((0.1, 0.0, 0.0)))
    d = only(check(bundle_dir, robot_of(link("body", grown))), "GC302")
    assert d.severity is Severity.WARNING
    assert d.data["standoff_side"] == "x+" and d.data["standoff_mm"] == 200.0
    assert d.data["standoff_allowed_mm"] == 30.0  # a tenth of the part's 0.3 m across that side
    assert d.message.startswith("collision[0] box reaches 0.2 m past its part of the mesh at its +x face")
    assert "1.7 times the volume of a box fitted to the part" in d.message


def test_a_box_longer_but_not_much_larger_is_no_finding(bundle_dir: Path) -> None:
    # 60 mm more on one side, 1.2 times the volume: a loose end, not an oversized box
    grown = collision(Box((BOX_SIZE[0] + 0.06, BOX_SIZE[1], BOX_SIZE[2])), Pose((0.03, 0.0, 0.0)))
    assert "GC302" not in [d.code for d in check(bundle_dir, robot_of(link("body", grown))).diagnostics]


def test_a_box_a_little_larger_than_its_part_is_no_finding(bundle_dir: Path) -> None:
    # 8 mm on every side: within the part's tolerance
    padded = collision(Box(tuple(s + 0.016 for s in BOX_SIZE)))
    result = check(bundle_dir, robot_of(link("body", padded)))
    assert [d.code for d in result.diagnostics] == []


def test_a_sphere_of_the_wheels_radius_is_the_wrong_kind(bundle_dir: Path) -> None:
    sphere = collision(Sphere(WHEEL_RADIUS))
    d = only(check(bundle_dir, robot_of(link("wheel", sphere, mesh=WHEEL_MESH))), "GC302")
    expected = (4.0 / 3.0 * WHEEL_RADIUS) / WHEEL_WIDTH  # sphere over the fitted cylinder
    assert d.data["better_kind"]["type"] == "cylinder"
    assert d.data["kind_ratio"] == round(expected, 3) or abs(d.data["kind_ratio"] - expected) < 0.05 * expected
    assert "the part is not sphere-shaped" in d.message
    # the sphere fitted to the wheel reaches its rim's corners: the part is no more sphere-shaped than that
    reach = float(np.hypot(WHEEL_RADIUS, WHEEL_WIDTH / 2))
    own = (4.0 / 3.0 * reach**3) / (WHEEL_RADIUS**2 * WHEEL_WIDTH)
    assert abs(d.data["own_kind_ratio"] - own) < 0.02 * own
    assert f"(a sphere fitted to the mesh would have {d.data['own_kind_ratio']:.1f} times)" in d.message


def test_a_capsule_on_a_blocky_rod_is_of_the_right_kind(bundle_dir: Path) -> None:
    """A capsule around a square rod encloses it in 1.5 to 1.7 times the rod's box whatever its
    fit: a capsule 2.3 times the box is larger than its fit, not the wrong kind of shape."""
    import trimesh

    rod = (0.03, 0.03, 0.12)
    trimesh.creation.box(extents=rod).export(bundle_dir / "meshes" / "rod.stl")
    half_diagonal = float(np.hypot(rod[0], rod[1])) / 2
    # the fitted capsule, at the least: the rod's corners on its cylinder, its caps past the ends
    fitted = np.pi * half_diagonal**2 * rod[2] + 4.0 / 3.0 * np.pi * half_diagonal**3
    assert 1.5 < fitted / np.prod(rod) < 2.0
    capsule = collision(Capsule(0.026, 0.19))  # the enclosing cylinder's radius and length
    element = np.pi * 0.026**2 * (0.19 - 2 * 0.026) + 4.0 / 3.0 * np.pi * 0.026**3
    assert element / np.prod(rod) > 2.0  # the element is more than twice the box: once the wrong kind
    result = check(bundle_dir, robot_of(link("rod", capsule, mesh=Mesh("meshes/rod.stl"))))
    assert not any("-shaped" in d.message for d in result.diagnostics)
    assert "GC302" not in [d.code for d in result.diagnostics]


def test_a_wheel_cylinder_twice_the_tyre_width_stands_off(bundle_dir: Path) -> None:
    wide = collision(Cylinder(WHEEL_RADIUS, 2 * WHEEL_WIDTH), Z_ONTO_Y)
    d = only(check(bundle_dir, robot_of(link("wheel", wide, mesh=WHEEL_MESH))), "GC302")
    assert d.data["standoff_side"] in ("z-", "z+") and d.data["standoff_mm"] == round(WHEEL_WIDTH / 2 * 1000, 1)


def test_an_inner_face_of_a_union_is_not_judged(bundle_dir: Path) -> None:
    # two boxes end to end over the part, the first reaching 50 mm into the second: its +x face is
    # inside the union, not its surface
    half = BOX_SIZE[0] / 2
    first = collision(Box((half + 0.05, BOX_SIZE[1], BOX_SIZE[2])), Pose((-half / 2 + 0.025, 0.0, 0.0)))
    second = collision(Box((half, BOX_SIZE[1], BOX_SIZE[2])), Pose((half / 2, 0.0, 0.0)), index=1)
    result = check(bundle_dir, robot_of(link("body", first, second)))
    assert [d.code for d in result.diagnostics] == []


def test_an_element_standing_for_what_the_visual_does_not_draw_is_not_judged(bundle_dir: Path) -> None:
    # a cable's box past the part's end: it answers for a sliver of the mesh, not for that mesh
    body = collision(Box(BOX_SIZE))
    cable = collision(Box((0.1, 0.03, 0.03)), Pose((BOX_SIZE[0] / 2 + 0.05, 0.0, 0.0)), index=1)
    result = check(bundle_dir, robot_of(link("body", body, cable)))
    assert "GC302" not in [d.code for d in result.diagnostics]


def test_a_visual_primitive_is_judged_as_a_mesh_is(bundle_dir: Path) -> None:
    # a 22 mm camera drawn as a sphere inside a 50 mm collision sphere
    camera = Link(
        "camera",
        visuals=(Shape("visual", 0, Sphere(0.011)),),
        collisions=(collision(Sphere(0.025)),),
        location=SourceLocation(ROOT_FILE, 3),
    )
    d = only(check(bundle_dir, robot_of(camera)), "GC302")
    assert d.data["standoff_side"] == "radial" and d.data["standoff_mm"] == 14.0
    assert np.isclose(d.data["volume_ratio"], (25 / 11) ** 3, rtol=0.01)


def test_padding_within_the_near_miss_margin_is_no_finding(bundle_dir: Path) -> None:
    """Minitaur's motor cylinders reach 4 mm past each face of a 13 mm decorative disc: more than
    a tenth of the disc, but padding within the 5 mm the sweeps call a near miss. 8 mm is not."""
    import trimesh

    disc = trimesh.creation.cylinder(radius=0.043, height=0.013, sections=64)
    disc.export(bundle_dir / "meshes" / "disc.stl")
    mesh = Mesh("meshes/disc.stl")

    def proud(by: float) -> list[str]:
        element = collision(Cylinder(0.0425, 0.013 + 2 * by))
        return [d.code for d in check(bundle_dir, robot_of(link("motor", element, mesh=mesh))).diagnostics]

    assert "GC302" not in proud(0.004)
    d = only(check(bundle_dir, robot_of(link("motor", collision(Cylinder(0.0425, 0.029)), mesh=mesh))), "GC302")
    assert (d.data["standoff_mm"], d.data["standoff_allowed_mm"]) == (8.0, 5.0)


def test_a_lone_element_left_a_sliver_by_its_neighbours_box_is_not_judged_by_its_slack(bundle_dir: Path) -> None:
    """A motor stator fixed inside its bracket's box: the box holds all of the stator's mesh but
    a 1 cm slice, which is all the stator's own (well-fitted) box answers for. Against that
    slice's hull any element is huge; it is not the stator's box that is oversized."""
    from geomcheck.model import Joint, Robot

    bracket = Link("bracket", collisions=(collision(Box((0.4, 0.4, 0.4)), Pose((-0.06, 0.0, 0.0))),))
    stator = link("stator", collision(Box(tuple(s + 0.02 for s in BOX_SIZE))))
    robot = Robot("r", links=(bracket, stator), joints=(Joint("j", "fixed", "bracket", "stator", Pose()),))
    result = check(bundle_dir, robot)
    assert [d.code for d in result.diagnostics if d.link == "stator"] == []
    # alone, the same box around the same mesh is no finding either: it is 1.4 times the mesh's hull
    assert [d.code for d in check(bundle_dir, robot_of(stator)).diagnostics] == []


def test_an_element_is_judged_against_the_mesh_it_holds_not_the_slab_a_neighbour_leaves(bundle_dir: Path) -> None:
    """A battery whose collision box repeats its visual box, inside the torso's box but for its
    bottom 1 cm: the torso's box owns the points both hold, and the slab left is a third of the
    battery's surface, so the battery's box answers for it and is judged; against the slab's hull
    (0.3 x 0.2 x 0.01 m) the box would be ten times too large. It holds the whole battery: 1.0."""
    from geomcheck.model import Joint, Robot

    torso = Link("torso", collisions=(collision(Box((0.4, 0.4, 0.4)), Pose((0.0, 0.0, 0.16))),))
    battery = link("battery", collision(Box(BOX_SIZE)))
    robot = Robot("r", links=(torso, battery), joints=(Joint("j", "fixed", "torso", "battery", Pose()),))
    result = check(bundle_dir, robot)
    assert [d.code for d in result.diagnostics if d.link == "battery"] == []
    fit = next(e for e in result.sections["links"] if e["link"] == "battery")["collisions"][0]["fit"]
    assert fit["part_points"] > 0.25 * 2000  # a third of the points: its part is judged
    assert fit["slack"] == pytest.approx(1.0, abs=0.02)
    assert fit["hull_volume"] == pytest.approx(0.3 * 0.2 * 0.1, rel=0.02)
