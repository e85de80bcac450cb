"""URDF parsing into the model: values, defaults, locations, extensions, recoverable errors."""

from __future__ import annotations

import math

import pytest

from geomcheck.errors import InputError
from geomcheck.model import Box, Capsule, Cylinder, Mesh, Sphere

URDF = """<?xml version="1.0"?>
<robot name="demo" xmlns:drake="http://drake.mit.edu">
  <material name="blue"><color rgba="0 0 0.8 1"/></material>
  <link name="base">
    <inertial>
      <origin xyz="0.1 0 0.2" rpy="0 0 1.5707963"/>
      <mass value="2.5"/>
      <inertia ixx="0.1" ixy="0.01" ixz="0" iyy="0.2" iyz="0" izz="0.3"/>
    </inertial>
    <visual name="shell">
      <origin xyz="0 0 0.05"/>
      <geometry><mesh filename="package://demo/meshes/base.stl" scale="0.001 0.001 0.001"/></geometry>
      <material name="blue"/>
    </visual>
    <visual><geometry><sphere radius="0.02"/></geometry><material name="red"><color rgba="1 0 0 1"/></material></visual>
    <collision><geometry><box size="0.6 0.6 0.2"/></geometry><drake:proximity_properties/></collision>
    <collision><geometry><cylinder radius="0.1" length="0.3"/></geometry></collision>
  </link>
  <link name="wheel"/>
  <joint name="wheel_joint" type="continuous">
    <origin xyz="0 0.3 0" rpy="1.5707963 0 0"/>
    <parent link="base"/>
    <child link="wheel"/>
    <axis xyz="0 0 1"/>
    <limit effort="10" velocity="5"/>
    <dynamics damping="0.1" friction="0.01"/>
    <safety_controller k_velocity="10"/>
  </joint>
  <gazebo reference="wheel"><mu1>1.0</mu1><material>Gazebo/Black</material></gazebo>
  <transmission name="t"><joint name="wheel_joint"/></transmission>
  <sensor name="laser" type="ray"><parent link="base"/></sensor>
</robot>
"""


def line_of(text: str, needle: str) -> int:
    return text.count("\n", 0, text.index(needle)) + 1


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


def test_parsing_goes_on_after_bad_numbers(load) -> None:
    text = URDF.replace('<mass value="2.5"/>', '<mass value="heavy"/>').replace(
        '<box size="0.6 0.6 0.2"/>', '<box size="0.6 0.6"/>'
    )
    loaded = load(text)
    found = [(d.code, d.link, d.about, d.location.line) for d in loaded.diagnostics]
    assert found == [
        ("GC107", "base", "inertial.mass.value", line_of(text, "<mass")),
        ("GC107", "base", "collision[0].box.size", line_of(text, '<box size="0.6 0.6"/>')),
    ]
    assert loaded.diagnostics[1].message == (
        '<box size="0.6 0.6"> is not 3 numbers: expected 3, got 2; urdfdom logs an error and loads the link '
        "without this element"
    )
    assert loaded.diagnostics[1].data["accepted_by"] == "urdfdom"  # it drops the collision, the robot loads
    base = loaded.robot.link_map["base"]
    assert base.inertial is not None and base.inertial.mass == 0.0
    assert [s.geometry for s in base.collisions] == [Cylinder(0.1, 0.3)]  # the bad box is dropped
    assert [link.name for link in loaded.robot.links] == ["base", "wheel"]


def test_nan_and_inf_are_invalid(load) -> None:
    loaded = load(URDF.replace('<origin xyz="0 0.3 0"', '<origin xyz="0 nan 0"'))
    (d,) = loaded.diagnostics
    assert (d.code, d.joint, d.about) == ("GC107", "wheel_joint", "origin.xyz")


def test_misplaced_core_element_names_its_home(load) -> None:
    loaded = load(URDF.replace("<drake:proximity_properties/>", '<material name="blue"/>'))
    (d,) = loaded.diagnostics
    assert (d.code, d.severity.value) == ("GC105", "info")
    assert d.message == (
        "unknown element <material> inside <collision>; <material> belongs in <robot> or <visual> "
        "(a collision element has no appearance: every consumer ignores it)"
    )


def test_misplaced_origin_is_a_warning_unless_it_is_the_identity(load) -> None:
    shifted = load(URDF.replace('<link name="wheel"/>', '<link name="wheel"><origin xyz="0 0 0.1"/></link>'))
    (d,) = shifted.diagnostics
    assert (d.code, d.severity.value, d.link, d.about) == ("GC105", "warning", "wheel", "/origin")
    assert d.message == (
        "unknown element <origin> inside <link>; <origin> belongs in <collision> or <inertial> or <joint> or <visual>"
    )
    zero = '<link name="wheel"><origin rpy="0 0 0" xyz="0 0 0"/></link>'
    identity = load(URDF.replace('<link name="wheel"/>', zero))
    (d,) = identity.diagnostics
    assert (d.code, d.severity.value, d.link) == ("GC105", "info", "wheel")
    assert d.message.endswith("(an identity pose: it would change nothing where it belongs)")


def test_extension_markup_is_one_info_finding_per_kind_for_the_robot(load) -> None:
    surface = "<surface><friction><ode><mu>1</mu></ode></friction></surface>"
    text = URDF.replace("<drake:proximity_properties/>", surface).replace(
        '<cylinder radius="0.1" length="0.3"/></geometry>', f'<cylinder radius="0.1" length="0.3"/></geometry>{surface}'
    )
    text = text.replace(
        '<link name="wheel"/>',
        f'<link name="wheel"><collision><geometry><sphere radius="0.1"/></geometry>{surface}</collision></link>',
    )
    text = text.replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 1" rpy="0 0 0"/><joint_properties damping="0"/>')
    found = sorted((d.code, d.severity.value, d.link or d.joint, d.data.get("also")) for d in load(text).diagnostics)
    assert found == [
        ("GC105", "info", "base", ["base", "wheel"]),
        ("GC105", "info", "wheel_joint", None),
        ("GC106", "info", "wheel_joint", None),
    ]
    messages = sorted(d.message for d in load(text).diagnostics)
    assert messages[0] == (
        "unknown attribute 'rpy' on <axis> (URDF defines: xyz): extension markup no URDF consumer reads"
    )
    assert messages[2] == (
        "unknown element <surface> inside <collision>: extension markup no URDF consumer reads there "
        "(also in base, wheel)"
    )


def test_a_misspelt_name_stays_a_warning(load) -> None:
    (d,) = load(URDF.replace("<drake:proximity_properties/>", '<orign xyz="0 0 1"/>')).diagnostics
    assert (d.code, d.severity.value, d.data["suggestion"]) == ("GC105", "warning", "origin")
    (d,) = load(URDF.replace('<axis xyz="0 0 1"/>', '<axis xzy="0 0 1"/>')).diagnostics
    assert (d.code, d.severity.value, d.data["suggestions"]) == ("GC106", "warning", {"xzy": "xyz"})


def test_top_level_typo_is_reported_but_extensions_are_not(load) -> None:
    loaded = load(URDF.replace('<link name="wheel"/>', '<lnk name="wheel"/><link name="wheel"/>'))
    (d,) = loaded.diagnostics
    assert (d.code, d.link, d.joint) == ("GC105", None, None)
    assert d.message == "unknown top-level element <lnk>; did you mean 'link'?"


def test_unknown_attributes_are_grouped_per_element(load) -> None:
    loaded = load(
        URDF.replace('<dynamics damping="0.1" friction="0.01"/>', '<dynamics dampin="0.1" Q="3" friction="0"/>')
    )
    (d,) = loaded.diagnostics
    assert d.code == "GC106" and d.joint == "wheel_joint"
    assert d.message == (
        "unknown attributes 'dampin' (did you mean 'damping'?), 'Q' on <dynamics> (URDF defines: damping, friction)"
    )
    assert d.data["suggestions"] == {"dampin": "damping"}


def test_attributes_a_known_tool_reads_are_extensions_not_typos(load) -> None:
    # Franka's friction model on <dynamics> (franka_description), PyBullet's concave and mask on <collision>
    franka = '<dynamics D="1" K="7000" damping="0.003" friction="0.0" mu_coulomb="0" mu_viscous="16"/>'
    text = URDF.replace('<dynamics damping="0.1" friction="0.01"/>', franka)
    text = text.replace("<collision><geometry><cylinder", '<collision concave="yes" mask="3"><geometry><cylinder')
    assert load(text).diagnostics == ()
    # a misspelt extension attribute is still a typo, offered the tool's name
    (d,) = load(text.replace('mu_viscous="16"', 'mu_viscos="16"')).diagnostics
    assert (d.code, d.joint, d.data["attributes"]) == ("GC106", "wheel_joint", ["mu_viscos"])
    assert d.data["suggestions"] == {"mu_viscos": "mu_viscous"}
    assert "'mu_viscos' (did you mean 'mu_viscous'?) on <dynamics>" in d.message
    # only where the tool writes them: K on <limit> is a typo
    (d,) = load(text.replace('<limit effort="10"', '<limit K="1" effort="10"')).diagnostics
    assert (d.code, d.data["attributes"]) == ("GC106", ["K"])


def test_missing_required_attributes(load) -> None:
    loaded = load(URDF.replace('<limit effort="10" velocity="5"/>', '<limit effort="10"/>'))
    (d,) = loaded.diagnostics
    assert (d.code, d.joint, d.message) == ("GC108", "wheel_joint", "<limit> has no velocity attribute")


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


def test_isaac_gym_dont_collapse_is_an_extension(load) -> None:
    text = URDF.replace(
        '<joint name="wheel_joint" type="continuous">',
        '<joint name="wheel_joint" type="continuous" dont_collapse="true">',
    )
    assert load(text).diagnostics == ()


def test_a_grouped_finding_does_not_depend_on_the_order_of_the_links(load) -> None:
    surface = "<surface/>"
    first = f'<link name="a"><collision><geometry><sphere radius="0.1"/></geometry>{surface}</collision></link>'
    second = f'<link name="b"><collision><geometry><sphere radius="0.2"/></geometry>{surface}</collision></link>'
    texts = [f'<robot name="r">\n  {x}\n  {y}\n</robot>\n' for x, y in ((first, second), (second, first))]
    found = [[(d.link, d.message, d.data["also"]) for d in load(text).diagnostics] for text in texts]
    assert (
        found[0]
        == found[1]
        == [
            (
                "a",
                "unknown element <surface> inside <collision>: extension markup no URDF consumer reads there"
                " (also in b)",
                ["b"],
            )
        ]
    )


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
