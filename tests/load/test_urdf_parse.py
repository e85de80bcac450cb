"""URDF parsing into the model: values, defaults, locations, versions, materials, refused files."""

from __future__ import annotations

import math

import pytest

from geomcheck.errors import InputError
from geomcheck.model import Box, Capsule, Cylinder, Mesh, Sphere
from tests.load.urdf_sample import URDF, line_of


def test_plain_urdf_model(load) -> None:
    loaded = load(URDF)
    robot = loaded.robot
    assert loaded.diagnostics == ()
    assert not loaded.document.is_xacro and loaded.document.text == URDF
    assert robot.name == "demo"
    assert [link.name for link in robot.links] == ["base", "wheel"]
    base = robot.link_map["base"]
    assert base.inertial is not None
    assert base.inertial.mass == 2.5
    assert base.inertial.origin.xyz == (0.1, 0.0, 0.2)
    assert base.inertial.tensor()[0, 1] == 0.01
    assert [s.label for s in base.visuals] == ["visual[0]", "visual[1]"]
    assert base.visuals[0].name == "shell"
    assert base.visuals[0].geometry == Mesh("package://demo/meshes/base.stl", (0.001, 0.001, 0.001))
    assert base.visuals[0].origin.xyz == (0.0, 0.0, 0.05)
    assert base.visuals[1].geometry == Sphere(0.02)
    assert base.collisions[0].geometry == Box((0.6, 0.6, 0.2))
    assert base.collisions[1].geometry == Cylinder(0.1, 0.3)
    joint = robot.joint_map["wheel_joint"]
    assert (joint.type, joint.parent, joint.child, joint.axis) == ("continuous", "base", "wheel", (0.0, 0.0, 1.0))
    assert joint.limit is not None and (joint.limit.lower, joint.limit.effort) == (None, 10.0)
    assert joint.origin.rpy == (1.5707963, 0.0, 0.0)
    assert dict(robot.materials) == {"blue": (0.0, 0.0, 0.8, 1.0), "red": (1.0, 0.0, 0.0, 1.0)}


def test_plain_urdf_locations_are_the_file_lines(load) -> None:
    robot = load(URDF, "demo.urdf").robot
    wheel = robot.link_map["wheel"]
    assert wheel.location is not None
    assert (wheel.location.file, wheel.location.line, wheel.location.expanded_line) == (
        "demo.urdf",
        line_of(URDF, '<link name="wheel"'),
        line_of(URDF, '<link name="wheel"'),
    )
    collision = robot.link_map["base"].collisions[1]
    assert collision.location is not None and collision.location.line == line_of(URDF, "<collision><geometry><cyl")


def test_defaults(load) -> None:
    text = '<robot name="r"><link name="a"><visual><geometry><mesh filename="a.stl"/></geometry></visual></link>'
    text += '<link name="b"/><joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
    text += '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    robot = load(text).robot
    assert robot.links[0].visuals[0].geometry == Mesh("a.stl", (1.0, 1.0, 1.0))
    assert robot.links[0].visuals[0].origin.xyz == (0.0, 0.0, 0.0)
    joint = robot.joints[0]
    assert joint.axis == (1.0, 0.0, 0.0)
    assert joint.origin.rpy == (0.0, 0.0, 0.0)
    assert joint.mimic is None


def test_top_level_typo_is_reported_but_extensions_are_not(load) -> None:
    loaded = load(URDF.replace('<link name="wheel"/>', '<lnk name="wheel"/><link name="wheel"/>'))
    (d,) = loaded.diagnostics
    assert (d.code, d.link, d.joint) == ("GC105", None, None)
    assert d.message == "unknown top-level element <lnk>; did you mean 'link'?"


def test_not_a_robot(load) -> None:
    # a root element no format claims (<sdf> is SDFormat's now) is named by the URDF loader
    with pytest.raises(InputError, match="root element is <gazebo>, not <robot>"):
        load('<gazebo version="1.0"><model name="m"/></gazebo>', "m.urdf")


def test_undefined_material_in_a_macro_is_reported_once(load) -> None:
    text = URDF.replace('<material name="blue"/>', '<material name="Wheel_l"/>')
    (d,) = load(text).diagnostics
    assert (d.code, d.link, d.about) == ("GC124", "base", "visual[0].material")
    # urdfdom keeps the name-only material (its default colour) and loads the robot: cosmetic only
    assert d.severity.value == "info"


@pytest.mark.parametrize(
    ("version", "reason"),
    [
        ("2.0", "urdfdom reads versions 1.0, 1.1, 1.2"),
        ("1", "The version attribute should be in the form 'x.y'"),
        (".1", "One of the fields of the version attribute is blank"),
        ("1.x", "Version attribute is not an integer"),
        ("1.0~pre6", "Extra characters after the version number"),
        ("1.-1", "Version number must be positive"),
    ],
)
def test_a_version_urdfdom_does_not_read_is_refused_in_its_words(load, version: str, reason: str) -> None:
    loaded = load(URDF.replace('<robot name="demo"', f'<robot name="demo" version="{version}"'))
    (d,) = [d for d in loaded.diagnostics if d.code == "GC127"]
    assert d.severity.value == "error" and d.data["version"] == version and reason in d.message


def test_urdf_1_1_reads_capsules_and_quaternions_as_urdfdom_does(load) -> None:
    capsule = '<capsule radius="0.05" length="0.2"/>'
    text = URDF.replace('<sphere radius="0.02"/>', capsule).replace(
        '<origin xyz="0 0.3 0" rpy="1.5707963 0 0"/>', '<origin xyz="0 0.3 0" quat_xyzw="0.7071068 0 0 0.7071068"/>'
    )
    newer = load(text.replace('<robot name="demo"', '<robot name="demo" version="1.1"'))
    shape = newer.robot.link_map["base"].visuals[1].geometry
    assert shape == Capsule(0.05, pytest.approx(0.3)) and shape.straight_length == pytest.approx(0.2)
    assert newer.robot.joint_map["wheel_joint"].origin.rpy == pytest.approx((math.pi / 2, 0.0, 0.0), abs=1e-6)
    assert [d.code for d in newer.diagnostics] == []
    older = load(text)  # a 1.0 file: urdfdom drops the capsule and ignores the quaternion
    assert len(older.robot.link_map["base"].visuals) == 1
    assert older.robot.joint_map["wheel_joint"].origin.rpy == (0.0, 0.0, 0.0)
    assert [(d.code, d.severity.value, d.data.get("accepted_by")) for d in older.diagnostics] == [
        ("GC129", "error", "urdfdom"),
        ("GC106", "warning", None),
    ]


def test_a_material_defined_twice_and_joint_elements_urdfdom_refuses(load) -> None:
    text = URDF.replace(
        '<link name="base">', '<material name="blue"><color rgba="0 0 1 1"/></material>\n  <link name="base">'
    ).replace('<dynamics damping="0.1" friction="0.01"/>', "<dynamics/>")
    text = text.replace('<safety_controller k_velocity="10"/>', '<safety_controller k_position="1"/>')
    loaded = load(text)
    assert [(d.code, d.about) for d in loaded.diagnostics] == [
        ("GC128", "material blue occurrence 2"),
        ("GC108", "dynamics.damping"),
        ("GC108", "safety_controller.k_velocity"),
    ]
    assert loaded.diagnostics[0].data == {"material": "blue", "first": "robot.urdf:3"}
