"""GC510 (geomcheck.checks.inertia.counterparts): left and right counterparts carry mirrored inertials."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh

from geomcheck.checks import CheckContext
from geomcheck.checks.inertia import run
from geomcheck.diagnostics import Diagnostic
from geomcheck.geometry.counterparts import named_pairs
from geomcheck.load import ExpandedDocument, LoadedDescription, MeshStore, make_bundle
from geomcheck.model import Box, Inertial, Joint, Limit, Link, Mesh, Pose, Robot, Shape
from geomcheck.options import CheckOptions

ROOT_FILE = "robot.urdf"
LEG = Box((0.05, 0.08, 0.3))
LIMIT = Limit(-1.0, 1.0, 1.0, 1.0)
TENSOR = (0.008, 0.0, 0.0, 0.008, 0.0, 0.001)


def leg(name: str, y: float, com_y: float, mass: float = 1.0, products: float = 0.0) -> Link:
    """A leg link whose box is drawn at ``y`` [m] in its frame, centre of mass at ``com_y``."""
    ixx, _, ixz, iyy, _, izz = TENSOR
    return Link(
        name,
        inertial=Inertial(mass, Pose((0.0, com_y, -0.15)), ixx, products, ixz, iyy, 0.0, izz),
        visuals=(Shape("visual", 0, LEG, Pose((0.0, y, -0.15))),),
    )


def legs(left: Link, right: Link) -> Robot:
    base = Link(
        "base",
        inertial=Inertial(5.0, Pose(), 0.1, 0.0, 0.0, 0.1, 0.0, 0.1),
        visuals=(Shape("visual", 0, Box((0.4, 0.3, 0.1))),),
    )
    joints = (
        Joint("left_hip", "revolute", "base", left.name, Pose((0.0, 0.1, -0.05)), axis=(0.0, 1.0, 0.0), limit=LIMIT),
        Joint("right_hip", "revolute", "base", right.name, Pose((0.0, -0.1, -0.05)), axis=(0.0, 1.0, 0.0), limit=LIMIT),
    )
    return Robot("r", links=(base, left, right), joints=joints)


def counterpart_findings(tmp_path: Path, robot: Robot) -> list[Diagnostic]:
    (tmp_path / ROOT_FILE).write_text("<robot name='r'/>\n")
    bundle = make_bundle(tmp_path / ROOT_FILE)
    document = ExpandedDocument(text="", root=ROOT_FILE, sources={}, is_xacro=False)
    loaded = LoadedDescription(bundle=bundle, robot=robot, document=document, diagnostics=())
    result = run(CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions()))
    return [d for d in result.diagnostics if d.code == "GC510"]


def test_mirrored_legs_with_mirrored_inertials_are_no_finding(tmp_path: Path) -> None:
    assert counterpart_findings(tmp_path, legs(leg("left_leg", 0.02, 0.02), leg("right_leg", -0.02, -0.02))) == []


def test_a_right_leg_carrying_the_lefts_centre_of_mass(tmp_path: Path) -> None:
    [d] = counterpart_findings(tmp_path, legs(leg("left_leg", 0.02, 0.02), leg("right_leg", -0.02, 0.02)))
    assert d.links == ("left_leg", "right_leg") and d.about == "inertia"
    assert d.data["com_distance_mm"] == pytest.approx(40.0) and d.data["com_allowed_mm"] == pytest.approx(30.0)
    assert "right_leg's centre of mass lies 40.0 mm from left_leg's" in d.message


def test_counterparts_of_different_masses(tmp_path: Path) -> None:
    [d] = counterpart_findings(tmp_path, legs(leg("left_leg", 0.02, 0.02), leg("right_leg", -0.02, -0.02, mass=1.5)))
    assert d.data["mass_difference"] == pytest.approx(1 / 3, abs=1e-4)
    assert "left_leg weighs 1 kg, right_leg 1.5 kg" in d.message


def test_products_of_inertia_copied_without_mirroring(tmp_path: Path) -> None:
    # a left and a right part (their own mesh files): mirroring flips the sign of ixy, a copy keeps it
    (tmp_path / "meshes").mkdir()
    for side in ("left", "right"):
        trimesh.creation.box(extents=LEG.size).export(tmp_path / "meshes" / f"{side}_leg.stl")

    def drawn(link: Link, side: str) -> Link:
        mesh = Shape("visual", 0, Mesh(f"meshes/{side}_leg.stl"), link.visuals[0].origin)
        return Link(link.name, inertial=link.inertial, visuals=(mesh,))

    left = drawn(leg("left_leg", 0.02, 0.02, products=0.004), "left")
    mirrored = drawn(leg("right_leg", -0.02, -0.02, products=-0.004), "right")
    assert counterpart_findings(tmp_path, legs(left, mirrored)) == []
    copied = drawn(leg("right_leg", -0.02, -0.02, products=0.004), "right")
    [d] = counterpart_findings(tmp_path, legs(left, copied))
    assert d.data["parts"] == "mirrored" and d.data["tensor_difference"] == pytest.approx(1.0)
    assert "(mirrored meshes: a left and a right part)" in d.message


def test_links_named_alike_but_not_mirrored_are_not_counterparts(tmp_path: Path) -> None:
    robot = legs(leg("left_leg", 0.02, 0.02), leg("right_leg", -0.02, 0.02))
    moved = Joint("right_hip", "revolute", "base", "right_leg", Pose((0.2, -0.1, -0.05)), axis=(0, 1, 0), limit=LIMIT)
    robot = Robot("r", links=robot.links, joints=(robot.joints[0], moved))
    assert counterpart_findings(tmp_path, robot) == []


@pytest.mark.parametrize(
    ("names", "pairs"),
    [
        (["l_shoulder", "r_shoulder", "torso"], [("l_shoulder", "r_shoulder")]),
        (["FL_thigh", "FR_thigh", "RL_thigh", "RR_thigh"], [("FL_thigh", "FR_thigh"), ("RL_thigh", "RR_thigh")]),
        (["panda_leftfinger", "panda_rightfinger"], [("panda_leftfinger", "panda_rightfinger")]),
        (["front_left_wheel", "front_right_wheel", "rear_left_wheel"], [("front_left_wheel", "front_right_wheel")]),
        (["link_l", "link_r2", "bl_caster", "br_caster"], [("bl_caster", "br_caster")]),
    ],
)
def test_names_that_differ_only_by_their_side(names: list[str], pairs: list[tuple[str, str]]) -> None:
    assert named_pairs(names) == pairs


@pytest.mark.parametrize("symmetric", [True, False])
def test_one_part_on_both_sides_is_its_own_mirror_image_when_symmetric(tmp_path: Path, symmetric: bool) -> None:
    # one mesh file drawn unmirrored on both sides, with mirrored centres of mass (y +-20 mm): a thigh
    # symmetric about its plane of motion fits mirrored values as well as identical ones; a part without
    # that symmetry does not: its right copy's centre of mass must be the left's
    (tmp_path / "meshes").mkdir()
    part = trimesh.creation.box(extents=LEG.size)
    if not symmetric:
        # brackets high on one side and low on the other: the same extents, but no mirror plane
        high, low = trimesh.creation.box(extents=(0.05, 0.06, 0.1)), trimesh.creation.box(extents=(0.05, 0.06, 0.1))
        high.apply_translation((0.0, 0.06, 0.08))
        low.apply_translation((0.0, -0.06, -0.08))
        part = trimesh.util.concatenate([part, high, low])
    part.export(tmp_path / "meshes" / "thigh.stl")

    def drawn(link: Link) -> Link:
        return Link(
            link.name,
            inertial=link.inertial,
            visuals=(Shape("visual", 0, Mesh("meshes/thigh.stl"), Pose((0.0, 0.0, -0.15))),),
        )

    found = counterpart_findings(tmp_path, legs(drawn(leg("left_leg", 0.0, 0.02)), drawn(leg("right_leg", 0.0, -0.02))))
    if symmetric:
        assert found == []
    else:
        [d] = found
        assert d.data["parts"] == "identical" and d.data["com_distance_mm"] == pytest.approx(40.0)
