"""urdfdom's own tests (ros/urdfdom, ``urdf_parser/test/``), one case per test, transcribed.

Each case names its test file and ``TEST(SUITE, name)``, and for a test that loads one of
``urdf_parser/test/assets/`` the asset; the URDF is the test's string or that asset, written
out again without its comments. The verdict is the test's: ``ASSERT_NE(nullptr, model)`` loads,
``EXPECT_EQ(nullptr, ...)`` refuses. Facts are the test's assertions that geomcheck's report
shows (names, counts, shapes, inertials, joints, limits, axes, origins, mimics); assertions on
what geomcheck does not model (dynamics, safety controllers, calibration, material colours,
acceleration limits) are left out. The ``URDF_VERSION_CLASS`` tests, which construct urdfdom's
version reader directly, are read as ``<robot version>`` of a one-link robot; the
``URDF_UNIT_TEST`` tests of ``urdf::Vector3`` as the ``xyz`` of a joint origin.
Sources and licences: NOTICE.md.
"""

# ruff: noqa: E501 (the descriptions are the reference tests' XML, one element per line as they wrote it)

from __future__ import annotations

from tests.load.conformance.harness import Case, Fact, fact

TESTS = "urdf_parser/test/"


def robot(body: str, version: str | None = "1.0", name: str = "r") -> str:
    written = "" if version is None else f' version="{version}"'
    return f'<?xml version="1.0"?>\n<robot name="{name}"{written}>\n{body}\n</robot>\n'


TWO_LINKS = '<link name="l1"/>\n<link name="l2"/>'


def joint(kind: str, inner: str = "", name: str = "j1", parent: str = "l1", child: str = "l2") -> str:
    return f'<joint name="{name}" type="{kind}">\n  <parent link="{parent}"/>\n  <child link="{child}"/>\n  {inner}\n</joint>'


def two(kind: str, inner: str = "", version: str | None = "1.0") -> str:
    """``l1`` and ``l2`` joined by ``j1`` of ``kind`` with ``inner`` elements."""
    return robot(f"{TWO_LINKS}\n{joint(kind, inner)}", version)


def visual(geometry: str, version: str | None = "1.0") -> str:
    return robot(f'<link name="base">\n  <visual><geometry>{geometry}</geometry></visual>\n</link>', version)


def case(
    file: str,
    test: str,
    verdict: str,
    text: str,
    *,
    asset: str | None = None,
    problem: str = "",
    facts: tuple[Fact, ...] = (),
) -> Case:
    return Case(TESTS + file, test, verdict, text, asset=asset, problem=problem, facts=facts)  # type: ignore[arg-type]


F = fact
MODEL, GEOMETRY, CAPSULE = (
    "urdf_schema_model_test.cpp",
    "urdf_schema_geometry_test.cpp",
    "urdf_schema_capsule_geometry_test.cpp",
)
AXIS, CALIBRATION, DYNAMICS = (
    "urdf_schema_joint_axis_test.cpp",
    "urdf_schema_joint_calibration_test.cpp",
    "urdf_schema_joint_dynamics_test.cpp",
)
LIMITS, MIMIC, SAFETY = (
    "urdf_schema_joint_limits_test.cpp",
    "urdf_schema_joint_mimic_test.cpp",
    "urdf_schema_joint_safety_test.cpp",
)
TYPES, INERTIAL, MATERIAL = (
    "urdf_schema_joint_types_test.cpp",
    "urdf_schema_link_inertial_test.cpp",
    "urdf_schema_material_test.cpp",
)
ORIGIN, TOPOLOGY, VISUAL = (
    "urdf_schema_origin_test.cpp",
    "urdf_schema_topology_test.cpp",
    "urdf_schema_visual_collision_test.cpp",
)
FULL, QUATERNION = "urdf_schema_full_robot_test.cpp", "urdf_schema_quaternion_test.cpp"
VERSION, UNIT = "urdf_version_test.cpp", "urdf_unit_test.cpp"

FULL_ROBOT = robot(
    """<material name="steel"><color rgba="0.5 0.5 0.5 1.0"/></material>
<material name="rubber"><color rgba="0.1 0.1 0.1 1.0"/></material>
<link name="base_link">
  <inertial>
    <origin xyz="0 0 0.05" rpy="0 0 0"/>
    <mass value="10.0"/>
    <inertia ixx="0.1" ixy="0.0" ixz="0.0" iyy="0.1" iyz="0.0" izz="0.05"/>
  </inertial>
  <visual name="base_vis">
    <origin xyz="0 0 0" rpy="0 0 0"/>
    <geometry><box size="0.4 0.3 0.1"/></geometry>
    <material name="steel"/>
  </visual>
  <collision name="base_col"><geometry><box size="0.4 0.3 0.1"/></geometry></collision>
</link>
<link name="shoulder_link">
  <inertial><mass value="2.5"/><inertia ixx="0.01" ixy="0.0" ixz="0.0" iyy="0.01" iyz="0.0" izz="0.005"/></inertial>
  <visual>
    <geometry><cylinder radius="0.05" length="0.2"/></geometry>
    <material name=""><color rgba="0.8 0.2 0.1 1.0"/></material>
  </visual>
  <collision><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision>
</link>
<joint name="shoulder_joint" type="revolute">
  <parent link="base_link"/>
  <child link="shoulder_link"/>
  <origin xyz="0.2 0 0.1" rpy="0 0 0"/>
  <axis xyz="0 1 0"/>
  <limit lower="-1.5707963" upper="1.5707963" effort="50.0" velocity="1.0"/>
  <dynamics damping="1.0" friction="0.1"/>
  <safety_controller soft_lower_limit="-1.4" soft_upper_limit="1.4" k_position="10.0" k_velocity="5.0"/>
  <calibration rising="0.0" falling="-0.1"/>
</joint>
<link name="elbow_link">
  <inertial><mass value="1.0"/><inertia ixx="0.005" ixy="0.0" ixz="0.0" iyy="0.005" iyz="0.0" izz="0.002"/></inertial>
  <visual><geometry><sphere radius="0.04"/></geometry></visual>
</link>
<joint name="elbow_joint" type="prismatic">
  <parent link="shoulder_link"/>
  <child link="elbow_link"/>
  <origin xyz="0 0 0.2"/>
  <axis xyz="0 0 1"/>
  <limit lower="-0.1" upper="0.1" effort="20.0" velocity="0.2"/>
  <dynamics damping="0.5" friction="0.05"/>
</joint>
<link name="wrist_link">
  <visual><geometry><mesh filename="package://robot/meshes/wrist.dae"/></geometry></visual>
  <collision><geometry><sphere radius="0.03"/></geometry></collision>
</link>
<joint name="wrist_joint" type="continuous">
  <parent link="elbow_link"/>
  <child link="wrist_link"/>
  <axis xyz="1 0 0"/>
  <dynamics damping="0.2" friction="0.0"/>
</joint>
<link name="tool_link">
  <visual><geometry><box size="0.01 0.01 0.05"/></geometry><material name="rubber"/></visual>
</link>
<joint name="tool_joint" type="fixed">
  <parent link="wrist_link"/>
  <child link="tool_link"/>
  <origin xyz="0 0 0.05" rpy="0 0 1.5707963"/>
</joint>
<link name="camera_link"><visual><geometry><box size="0.05 0.05 0.02"/></geometry></visual></link>
<joint name="camera_joint" type="floating">
  <parent link="base_link"/>
  <child link="camera_link"/>
  <origin xyz="-0.1 0 0.15"/>
</joint>
<link name="platform_link"><visual><geometry><box size="0.2 0.2 0.01"/></geometry></visual></link>
<joint name="platform_joint" type="planar">
  <parent link="base_link"/>
  <child link="platform_link"/>
  <mimic joint="shoulder_joint" multiplier="0.5" offset="0.0"/>
</joint>""",
    name="full_robot",
)

MULTIPLE_GEOMETRIES = robot(
    """<link name="base">
  <visual name="v1"><geometry><sphere radius="0.1"/></geometry></visual>
  <visual name="v2"><geometry><box size="1 1 1"/></geometry></visual>
  <visual name="v3"><geometry><cylinder radius="0.2" length="0.5"/></geometry></visual>
  <collision name="c1"><geometry><sphere radius="0.1"/></geometry></collision>
  <collision name="c2"><geometry><box size="1 1 1"/></geometry></collision>
</link>""",
    name="multi_geometry_robot",
)

# two joints from l1 to l2, as the quaternion tests write them (urdfdom accepts a link with two parents)
PAIR = """<joint name="j1" type="fixed">
  <parent link="l1"/>
  <child link="l2"/>
  <origin xyz="0 0 0" {rotation}/>
</joint>
<joint name="j2" type="fixed">
  <parent link="l1"/>
  <child link="l2"/>
</joint>
<link name="l1"/>
<link name="l2"/>"""

DOUBLES_LINKS = """<link name="l1">
  <visual><geometry><sphere radius="1.349"/></geometry>{material1}</visual>
  <inertial>
    <mass value="8.4396"/>
    <inertia ixx="0.087" ixy="0.14" ixz="0.912" iyy="0.763" iyz="0.0012" izz="0.908"/>
  </inertial>
</link>
<link name="l2">
  <visual><geometry><cylinder radius="3.349" length="7.5490"/></geometry>{material2}</visual>
</link>"""
DOUBLES_JOINTS = """<joint name="j1" type="fixed"><parent link="l1"/><child link="l2"/></joint>
<joint name="j2" type="fixed"><parent link="l1"/><child link="l2"/></joint>"""
DOUBLES_FACTS = (
    F("count links", 2),
    F("count joints", 2),
    F("shape l1 visual 0 type", "sphere"),
    F("shape l1 visual 0 radius", 1.349),
    F("shape l2 visual 0 type", "cylinder"),
    F("shape l2 visual 0 radius", 3.349),
    F("shape l2 visual 0 length", 7.549),
    F("inertial l1 mass", 8.4396),
    F("inertial l1 ixx", 0.087),
    F("inertial l1 ixy", 0.14),
    F("inertial l1 ixz", 0.912),
    F("inertial l1 iyy", 0.763),
    F("inertial l1 iyz", 0.0012),
    F("inertial l1 izz", 0.908),
)

IDENTITY = (0.0, 0.0, 0.0, 1.0)
HALVES = (0.5, 0.5, 0.5, 0.5)


def version_class(test: str, version: str, words: str) -> Case:
    """A ``URDF_VERSION_CLASS`` test: urdfdom's version reader refuses ``version`` with ``words``."""
    return case(
        VERSION,
        f"URDF_VERSION_CLASS.{test}",
        "refuse",
        robot('<link name="l1"/>', version=version, name="test"),
        problem=f"GC127.*{words}",
    )


def vector3(test: str, xyz: str, verdict: str, facts: tuple[Fact, ...] = ()) -> Case:
    """A ``URDF_UNIT_TEST`` test of ``urdf::Vector3``, read as the ``xyz`` of a joint origin."""
    problem = "GC107.*xyz" if verdict == "refuse" else ""
    return case(
        UNIT, f"URDF_UNIT_TEST.{test}", verdict, two("fixed", f'<origin xyz="{xyz}"/>'), problem=problem, facts=facts
    )


CASES: tuple[Case, ...] = (
    # urdf_schema_model_test.cpp
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.no_version_attr_defaults_to_v1_0",
        "load",
        robot('<link name="base"/>', None, "no_version"),
        facts=(F("name", "no_version"), F("count links", 1)),
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.single_link_robot_is_valid",
        "load",
        robot('<link name="only_link"/>', name="single"),
        facts=(F("count links", 1), F("root", "only_link")),
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.invalid_xml_fails",
        "refuse",
        '<robot name="bad" version="1.0"\n',
        asset="bad_invalid_xml.urdf",
        problem="GC101|well-formed|xml",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.no_robot_element_fails",
        "refuse",
        '<?xml version="1.0"?>\n<not_a_robot name="r"><link name="l"/></not_a_robot>\n',
        asset="bad_no_robot_element.urdf",
        problem="not <robot>",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.robot_without_name_fails",
        "refuse",
        '<?xml version="1.0"?>\n<robot version="1.0"><link name="l"/></robot>\n',
        asset="bad_robot_no_name.urdf",
        problem="GC108.*<robot> has no name",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.no_links_fails",
        "refuse",
        robot("", name="empty"),
        asset="bad_no_links.urdf",
        problem="GC114.*no links",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.unsupported_version_too_high_fails",
        "refuse",
        robot('<link name="l"/>', "2.0"),
        asset="bad_version_too_high.urdf",
        problem="GC127",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.unsupported_version_too_low_fails",
        "refuse",
        robot('<link name="l"/>', "0.9"),
        asset="bad_version_too_low.urdf",
        problem="GC127",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.malformed_version_string_fails",
        "refuse",
        robot('<link name="l"/>', "one.zero"),
        asset="bad_malformed_version.urdf",
        problem="GC127.*not an integer",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.duplicate_link_name_fails",
        "refuse",
        robot('<link name="base"/>\n<link name="base"/>', name="dup"),
        asset="bad_duplicate_link_name.urdf",
        problem="GC110.*base",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.duplicate_joint_name_fails",
        "refuse",
        robot(
            '<link name="l1"/>\n<link name="l2"/>\n<link name="l3"/>\n'
            + joint("fixed")
            + "\n"
            + joint("fixed", child="l3"),
            name="dup",
        ),
        asset="bad_duplicate_joint_name.urdf",
        problem="GC111.*j1",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.joint_referencing_unknown_parent_link_fails",
        "refuse",
        robot('<link name="child"/>\n' + joint("fixed", parent="nonexistent", child="child")),
        asset="bad_joint_unknown_parent.urdf",
        problem="GC112.*nonexistent",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.joint_referencing_unknown_child_link_fails",
        "refuse",
        robot('<link name="base"/>\n' + joint("fixed", parent="base", child="nonexistent")),
        asset="bad_joint_unknown_child.urdf",
        problem="GC112.*nonexistent",
    ),
    case(
        MODEL,
        "URDF_SCHEMA_MODEL.two_root_links_fails",
        "refuse",
        robot('<link name="root1"/>\n<link name="root2"/>'),
        asset="bad_two_root_links.urdf",
        problem="GC115",
    ),
    # urdf_schema_geometry_test.cpp
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.box_geometry_positive_values",
        "load",
        visual('<box size="1.0 2.0 3.0"/>'),
        facts=(F("shape base visual 0 type", "box"), F("shape base visual 0 size", (1.0, 2.0, 3.0))),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.box_geometry_zero_dimension_allowed_v1_0",
        "load",
        visual('<box size="1.0 0.0 3.0"/>'),
        facts=(F("visuals base", 1),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.box_geometry_no_size_attr_fails",
        "load",
        visual("<box/>"),
        asset="bad_box_no_size.urdf",
        facts=(F("visuals base", 0),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.sphere_geometry_positive_value",
        "load",
        visual('<sphere radius="0.75"/>'),
        facts=(F("shape base visual 0 type", "sphere"), F("shape base visual 0 radius", 0.75)),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.sphere_geometry_large_radius_allowed_v1_0",
        "load",
        visual('<sphere radius="1e6"/>'),
        facts=(F("shape base visual 0 radius", 1e6),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.sphere_geometry_negative_radius_allowed_v1_0",
        "load",
        visual('<sphere radius="-0.5"/>'),
        facts=(F("shape base visual 0 radius", -0.5),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.sphere_geometry_no_radius_attr_fails",
        "load",
        visual("<sphere/>"),
        asset="bad_sphere_no_radius.urdf",
        facts=(F("visuals base", 0),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.cylinder_geometry_positive_values",
        "load",
        visual('<cylinder radius="0.4" length="1.2"/>'),
        facts=(F("shape base visual 0 radius", 0.4), F("shape base visual 0 length", 1.2)),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.cylinder_geometry_negative_radius_allowed_v1_0",
        "load",
        visual('<cylinder radius="-0.4" length="1.2"/>'),
        facts=(F("shape base visual 0 radius", -0.4), F("shape base visual 0 length", 1.2)),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.cylinder_geometry_negative_length_allowed_v1_0",
        "load",
        visual('<cylinder radius="0.4" length="-1.2"/>'),
        facts=(F("shape base visual 0 radius", 0.4), F("shape base visual 0 length", -1.2)),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.cylinder_geometry_no_length_attr_fails",
        "load",
        visual('<cylinder radius="0.4"/>'),
        asset="bad_cylinder_no_length.urdf",
        facts=(F("visuals base", 0),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.cylinder_geometry_no_radius_attr_fails",
        "load",
        visual('<cylinder length="1.2"/>'),
        asset="bad_cylinder_no_radius.urdf",
        facts=(F("visuals base", 0),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.mesh_geometry_with_filename",
        "load",
        visual('<mesh filename="package://my_pkg/meshes/base.dae"/>'),
        facts=(F("shape base visual 0 filename", "package://my_pkg/meshes/base.dae"),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.mesh_geometry_default_scale_is_one",
        "load",
        visual('<mesh filename="my_mesh.stl"/>'),
        facts=(F("shape base visual 0 scale", (1.0, 1.0, 1.0)),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.mesh_geometry_with_explicit_scale",
        "load",
        visual('<mesh filename="my_mesh.stl" scale="0.001 0.001 0.001"/>'),
        facts=(F("shape base visual 0 scale", (0.001, 0.001, 0.001)),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.mesh_geometry_no_filename_fails",
        "load",
        visual("<mesh/>"),
        asset="bad_mesh_no_filename.urdf",
        facts=(F("visuals base", 0),),
    ),
    case(
        GEOMETRY,
        "URDF_SCHEMA_GEOMETRY.unknown_geometry_type_fails",
        "load",
        visual('<torus radius="1.0"/>'),
        asset="bad_unknown_geometry_type.urdf",
        facts=(F("visuals base", 0),),
    ),
    # urdf_schema_capsule_geometry_test.cpp
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_version_1_1",
        "load",
        robot(
            """<link name="link1">
  <visual><geometry><capsule radius="0.05" length="0.5"/></geometry></visual>
  <collision><geometry><capsule radius="0.1" length="1.0"/></geometry></collision>
</link>""",
            "1.1",
            "capsule_test",
        ),
        facts=(
            F("name", "capsule_test"),
            F("count links", 1),
            F("visuals link1", 1),
            F("shape link1 visual 0 type", "capsule"),
            F("shape link1 visual 0 radius", 0.05),
            F("shape link1 visual 0 length", 0.5),
            F("collisions link1", 1),
            F("shape link1 collision 0 type", "capsule"),
            F("shape link1 collision 0 radius", 0.1),
            F("shape link1 collision 0 length", 1.0),
        ),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_ignored_version_1_0",
        "load",
        robot(
            '<link name="link1"><visual><geometry><capsule radius="0.05" length="0.5"/></geometry></visual></link>',
            "1.0",
            "capsule_ignored_test",
        ),
        facts=(F("name", "capsule_ignored_test"), F("visuals link1", 0)),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_zero_values",
        "load",
        robot(
            '<link name="link1"><visual><geometry><capsule radius="0.0" length="0.0"/></geometry></visual></link>',
            "1.1",
        ),
        facts=(F("shape link1 visual 0 radius", 0.0), F("shape link1 visual 0 length", 0.0)),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_negative_radius_fails",
        "load",
        robot(
            '<link name="link1"><visual><geometry><capsule radius="-0.05" length="0.5"/></geometry></visual></link>',
            "1.1",
        ),
        facts=(F("visuals link1", 0),),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_negative_length_fails",
        "load",
        robot(
            '<link name="link1"><visual><geometry><capsule radius="0.05" length="-0.5"/></geometry></visual></link>',
            "1.1",
        ),
        facts=(F("visuals link1", 0),),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_missing_radius_fails",
        "load",
        robot('<link name="link1"><visual><geometry><capsule length="0.5"/></geometry></visual></link>', "1.1"),
        facts=(F("visuals link1", 0),),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_missing_length_fails",
        "load",
        robot('<link name="link1"><visual><geometry><capsule radius="0.05"/></geometry></visual></link>', "1.1"),
        facts=(F("visuals link1", 0),),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_capsule_geometry_inf_value_fails",
        "load",
        robot(
            '<link name="link1"><visual><geometry><capsule radius="inf" length="0.5"/></geometry></visual></link>',
            "1.1",
        ),
        facts=(F("visuals link1", 0),),
    ),
    case(
        CAPSULE,
        "URDF_UNIT_TEST.parse_multiple_capsules_in_same_link",
        "load",
        robot(
            """<link name="link1">
  <visual><geometry><capsule radius="0.05" length="0.5"/></geometry></visual>
  <visual><geometry><capsule radius="0.1" length="1.0"/></geometry></visual>
  <collision><geometry><capsule radius="0.15" length="1.5"/></geometry></collision>
  <collision><geometry><capsule radius="0.2" length="2.0"/></geometry></collision>
</link>""",
            "1.1",
            "multi_capsule_test",
        ),
        facts=(
            F("visuals link1", 2),
            F("shape link1 visual 0 radius", 0.05),
            F("shape link1 visual 0 length", 0.5),
            F("shape link1 visual 1 radius", 0.1),
            F("shape link1 visual 1 length", 1.0),
            F("collisions link1", 2),
            F("shape link1 collision 0 radius", 0.15),
            F("shape link1 collision 0 length", 1.5),
            F("shape link1 collision 1 type", "capsule"),
            F("shape link1 collision 1 radius", 0.2),
            F("shape link1 collision 1 length", 2.0),
        ),
    ),
    # urdf_schema_joint_axis_test.cpp
    case(
        AXIS,
        "URDF_SCHEMA_JOINT_AXIS.joint_axis_default_is_1_0_0",
        "load",
        two("revolute", '<limit lower="-1" upper="1" effort="10" velocity="1"/>'),
        facts=(F("joint j1 axis", (1.0, 0.0, 0.0)),),
    ),
    case(
        AXIS,
        "URDF_SCHEMA_JOINT_AXIS.joint_axis_custom_value",
        "load",
        two("revolute", '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/>'),
        facts=(F("joint j1 axis", (0.0, 1.0, 0.0)),),
    ),
    case(
        AXIS,
        "URDF_SCHEMA_JOINT_AXIS.joint_axis_negative_components",
        "load",
        two("continuous", '<axis xyz="0 0 -1"/>'),
        facts=(F("joint j1 axis", (0.0, 0.0, -1.0)),),
    ),
    case(
        AXIS,
        "URDF_SCHEMA_JOINT_AXIS.joint_axis_zero_vector_allowed_v1_0",
        "load",
        two("continuous", '<axis xyz="0 0 0"/>'),
        facts=(F("joint j1 axis", (0.0, 0.0, 0.0)),),
    ),
    case(
        AXIS,
        "URDF_SCHEMA_JOINT_AXIS.joint_axis_non_unit_length_allowed_v1_0",
        "load",
        two("revolute", '<axis xyz="2 0 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/>'),
        facts=(F("joint j1 axis", (2.0, 0.0, 0.0)),),
    ),
    case(
        AXIS,
        "URDF_SCHEMA_JOINT_AXIS.joint_axis_non_principal_unit_vector_allowed",
        "load",
        two(
            "revolute",
            '<axis xyz="0.57735026919 0.57735026919 0.57735026919"/><limit lower="-1" upper="1" effort="10" velocity="1"/>',
        ),
        facts=(F("joint j1 axis", (0.57735026919, 0.57735026919, 0.57735026919)),),
    ),
    case(
        AXIS,
        "URDF_SCHEMA_JOINT_AXIS.joint_axis_diagonal_unit_vector_xy_plane",
        "load",
        two("continuous", '<axis xyz="0.70710678118 0.70710678118 0"/>'),
        facts=(F("joint j1 axis", (0.70710678118, 0.70710678118, 0.0)),),
    ),
    # urdf_schema_joint_calibration_test.cpp
    case(
        CALIBRATION,
        "URDF_SCHEMA_JOINT_CALIBRATION.calibration_rising_only",
        "load",
        two("fixed", '<calibration rising="1.234"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        CALIBRATION,
        "URDF_SCHEMA_JOINT_CALIBRATION.calibration_falling_only",
        "load",
        two("fixed", '<calibration falling="-0.567"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        CALIBRATION,
        "URDF_SCHEMA_JOINT_CALIBRATION.calibration_both_rising_and_falling",
        "load",
        two("fixed", '<calibration rising="0.5" falling="-0.5"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        CALIBRATION,
        "URDF_SCHEMA_JOINT_CALIBRATION.calibration_no_attributes_produces_null_pointers",
        "load",
        two("fixed", "<calibration/>"),
        facts=(F("joint j1 type", "fixed"),),
    ),
    # urdf_schema_joint_dynamics_test.cpp
    case(
        DYNAMICS,
        "URDF_SCHEMA_JOINT_DYNAMICS.dynamics_only_damping",
        "load",
        two("fixed", '<dynamics damping="5.5"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        DYNAMICS,
        "URDF_SCHEMA_JOINT_DYNAMICS.dynamics_only_friction",
        "load",
        two("fixed", '<dynamics friction="2.25"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        DYNAMICS,
        "URDF_SCHEMA_JOINT_DYNAMICS.dynamics_neither_damping_nor_friction_fails",
        "refuse",
        two("fixed", "<dynamics/>"),
        asset="bad_dynamics_empty.urdf",
        problem="GC108.*dynamics",
    ),
    case(
        DYNAMICS,
        "URDF_SCHEMA_JOINT_DYNAMICS.dynamics_negative_damping_allowed_v1_0",
        "load",
        two("fixed", '<dynamics damping="-1.0" friction="0.0"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        DYNAMICS,
        "URDF_SCHEMA_JOINT_DYNAMICS.dynamics_negative_friction_allowed_v1_0",
        "load",
        two("fixed", '<dynamics damping="0.0" friction="-0.5"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        DYNAMICS,
        "URDF_SCHEMA_JOINT_DYNAMICS.dynamics_zero_values_allowed_v1_0",
        "load",
        two("fixed", '<dynamics damping="0.0" friction="0.0"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    # urdf_schema_joint_limits_test.cpp
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_negative_effort_allowed_v1_0",
        "load",
        two("fixed", '<limit effort="-5.0" velocity="1.0"/>'),
        facts=(F("joint j1 limit.effort", -5.0),),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_negative_velocity_allowed_v1_0",
        "load",
        two("fixed", '<limit effort="10.0" velocity="-3.0"/>'),
        facts=(F("joint j1 limit.velocity", -3.0),),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_zero_effort_and_velocity_allowed_v1_0",
        "load",
        two("fixed", '<limit effort="0.0" velocity="0.0"/>'),
        facts=(F("joint j1 limit.effort", 0.0), F("joint j1 limit.velocity", 0.0)),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_missing_effort_fails_v1_0",
        "refuse",
        two("fixed", '<limit velocity="1.0"/>'),
        asset="bad_limit_no_effort.urdf",
        problem="GC108.*effort",
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_missing_velocity_fails_v1_0",
        "refuse",
        two("fixed", '<limit effort="1.0"/>'),
        asset="bad_limit_no_velocity.urdf",
        problem="GC108.*velocity",
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_large_positive_values_v1_0",
        "load",
        two("revolute", '<limit lower="-3.14159" upper="3.14159" effort="9999.9" velocity="100.0"/>'),
        facts=(
            F("joint j1 limit.lower", -3.14159),
            F("joint j1 limit.upper", 3.14159),
            F("joint j1 limit.effort", 9999.9),
            F("joint j1 limit.velocity", 100.0),
        ),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_acceleration_deceleration_jerk_default_to_inf_v1_0",
        "load",
        two("fixed", '<limit effort="10.0" velocity="1.0"/>'),
        facts=(F("joint j1 limit.effort", 10.0), F("joint j1 limit.velocity", 1.0)),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_invalid_effort_string_fails_v1_0",
        "refuse",
        two("fixed", '<limit effort="not_a_number" velocity="1.0"/>'),
        asset="bad_limit_effort_not_number.urdf",
        problem="GC107.*effort",
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.limits_invalid_velocity_string_fails_v1_0",
        "refuse",
        two("fixed", '<limit effort="10.0" velocity="fast"/>'),
        asset="bad_limit_velocity_not_number.urdf",
        problem="GC107.*velocity",
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.revolute_joint_limits_lower_greater_than_upper_allowed_v1_0",
        "load",
        two("revolute", '<limit lower="1.57" upper="-1.57" effort="10.0" velocity="1.0"/>'),
        facts=(F("joint j1 limit.lower", 1.57), F("joint j1 limit.upper", -1.57)),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.prismatic_joint_limits_lower_greater_than_upper_allowed_v1_0",
        "load",
        two("prismatic", '<limit lower="0.5" upper="-0.5" effort="50.0" velocity="0.5"/>'),
        facts=(F("joint j1 limit.lower", 0.5), F("joint j1 limit.upper", -0.5)),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.revolute_joint_negative_effort_allowed_v1_0",
        "load",
        two("revolute", '<limit lower="-1.57" upper="1.57" effort="-10.0" velocity="1.0"/>'),
        facts=(F("joint j1 limit.effort", -10.0),),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.revolute_joint_negative_velocity_allowed_v1_0",
        "load",
        two("revolute", '<limit lower="-1.57" upper="1.57" effort="10.0" velocity="-2.0"/>'),
        facts=(F("joint j1 limit.velocity", -2.0),),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.prismatic_joint_negative_effort_and_velocity_allowed_v1_0",
        "load",
        two("prismatic", '<limit lower="-0.5" upper="0.5" effort="-50.0" velocity="-0.5"/>'),
        facts=(F("joint j1 limit.effort", -50.0), F("joint j1 limit.velocity", -0.5)),
    ),
    case(
        LIMITS,
        "URDF_SCHEMA_JOINT_LIMITS.revolute_joint_zero_effort_and_velocity_allowed_v1_0",
        "load",
        two("revolute", '<limit lower="-1.0" upper="1.0" effort="0.0" velocity="0.0"/>'),
        facts=(F("joint j1 limit.effort", 0.0), F("joint j1 limit.velocity", 0.0)),
    ),
    # urdf_schema_joint_mimic_test.cpp
    case(
        MIMIC,
        "URDF_SCHEMA_JOINT_MIMIC.mimic_joint_name_only_uses_defaults",
        "load",
        robot(
            '<link name="l1"/>\n<link name="l2"/>\n<link name="l3"/>\n'
            + joint("fixed")
            + "\n"
            + joint("fixed", '<mimic joint="j1"/>', name="j2", child="l3")
        ),
        facts=(F("joint j2 mimic.joint", "j1"), F("joint j2 mimic.multiplier", 1.0), F("joint j2 mimic.offset", 0.0)),
    ),
    case(
        MIMIC,
        "URDF_SCHEMA_JOINT_MIMIC.mimic_with_negative_multiplier_allowed_v1_0",
        "load",
        robot(
            '<link name="l1"/>\n<link name="l2"/>\n<link name="l3"/>\n'
            + joint("fixed")
            + "\n"
            + joint("fixed", '<mimic joint="j1" multiplier="-2.0" offset="0.1"/>', name="j2", child="l3")
        ),
        facts=(F("joint j2 mimic.multiplier", -2.0), F("joint j2 mimic.offset", 0.1)),
    ),
    case(
        MIMIC,
        "URDF_SCHEMA_JOINT_MIMIC.mimic_without_joint_name_fails",
        "refuse",
        two("fixed", '<mimic multiplier="1.0"/>'),
        asset="bad_mimic_no_joint_name.urdf",
        problem="GC108.*mimic",
    ),
    # urdf_schema_joint_safety_test.cpp
    case(
        SAFETY,
        "URDF_SCHEMA_JOINT_SAFETY.safety_k_velocity_only_other_defaults_to_zero",
        "load",
        two("fixed", '<safety_controller k_velocity="8.5"/>'),
        facts=(F("joint j1 type", "fixed"),),
    ),
    case(
        SAFETY,
        "URDF_SCHEMA_JOINT_SAFETY.safety_without_k_velocity_fails",
        "refuse",
        two("fixed", '<safety_controller k_position="1.0" soft_lower_limit="-1.0"/>'),
        asset="bad_safety_no_k_velocity.urdf",
        problem="GC108.*k_velocity",
    ),
    case(
        SAFETY,
        "URDF_SCHEMA_JOINT_SAFETY.safety_negative_soft_limits_allowed_v1_0",
        "load",
        two(
            "fixed",
            '<safety_controller soft_lower_limit="-5.0" soft_upper_limit="-1.0" k_position="0.1" k_velocity="3.0"/>',
        ),
        facts=(F("joint j1 type", "fixed"),),
    ),
    # urdf_schema_joint_types_test.cpp
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.revolute_joint_with_limits",
        "load",
        two("revolute", '<limit lower="-1.57" upper="1.57" effort="100.0" velocity="2.0"/>').replace(
            'name="r"', 'name="revolute_robot"'
        ),
        asset="revolute_joint.urdf",
        facts=(
            F("joint j1 type", "revolute"),
            F("joint j1 limit.lower", -1.57),
            F("joint j1 limit.upper", 1.57),
            F("joint j1 limit.effort", 100.0),
            F("joint j1 limit.velocity", 2.0),
        ),
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.revolute_joint_without_limits_fails",
        "refuse",
        two("revolute"),
        asset="bad_revolute_no_limits.urdf",
        problem="GC121",
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.prismatic_joint_with_limits",
        "load",
        two("prismatic", '<axis xyz="0 0 1"/><limit lower="-0.5" upper="0.5" effort="50.0" velocity="0.5"/>'),
        facts=(F("joint j1 type", "prismatic"),),
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.prismatic_joint_without_limits_fails",
        "refuse",
        two("prismatic"),
        asset="bad_prismatic_no_limits.urdf",
        problem="GC121",
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.continuous_joint_no_limits_required",
        "load",
        two("continuous"),
        facts=(F("joint j1 type", "continuous"), F("joint j1 limit", None)),
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.fixed_joint_no_limits_required",
        "load",
        two("fixed"),
        facts=(F("joint j1 type", "fixed"), F("joint j1 limit", None)),
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.floating_joint_no_limits_required",
        "load",
        two("floating"),
        facts=(F("joint j1 type", "floating"),),
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.planar_joint_no_limits_required",
        "load",
        two("planar"),
        facts=(F("joint j1 type", "planar"),),
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.unknown_joint_type_fails",
        "refuse",
        two("spring"),
        asset="bad_unknown_joint_type.urdf",
        problem="GC118.*spring",
    ),
    case(
        TYPES,
        "URDF_SCHEMA_JOINT_TYPES.joint_without_type_attr_fails",
        "refuse",
        robot(TWO_LINKS + '\n<joint name="j1">\n  <parent link="l1"/>\n  <child link="l2"/>\n</joint>'),
        asset="bad_joint_no_type.urdf",
        problem="GC108.*type",
    ),
    # urdf_schema_link_inertial_test.cpp
    case(
        INERTIAL,
        "URDF_SCHEMA_LINK_INERTIAL.inertial_positive_values",
        "load",
        robot(
            '<link name="base"><inertial><mass value="5.25"/>'
            '<inertia ixx="0.2" ixy="0.01" ixz="0.001" iyy="0.3" iyz="0.002" izz="0.4"/></inertial></link>',
            name="inertial_robot",
        ),
        asset="inertial_link.urdf",
        facts=(
            F("inertial base mass", 5.25),
            F("inertial base ixx", 0.2),
            F("inertial base ixy", 0.01),
            F("inertial base ixz", 0.001),
            F("inertial base iyy", 0.3),
            F("inertial base iyz", 0.002),
            F("inertial base izz", 0.4),
        ),
    ),
    case(
        INERTIAL,
        "URDF_SCHEMA_LINK_INERTIAL.inertial_negative_mass_allowed_v1_0",
        "load",
        robot(
            '<link name="base"><inertial><mass value="-3.0"/>'
            '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>'
        ),
        facts=(F("inertial base mass", -3.0),),
    ),
    case(
        INERTIAL,
        "URDF_SCHEMA_LINK_INERTIAL.inertial_zero_mass_allowed_v1_0",
        "load",
        robot(
            '<link name="base"><inertial><mass value="0.0"/>'
            '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>'
        ),
        facts=(F("inertial base mass", 0.0),),
    ),
    case(
        INERTIAL,
        "URDF_SCHEMA_LINK_INERTIAL.inertial_negative_inertia_tensor_allowed_v1_0",
        "load",
        robot(
            '<link name="base"><inertial><mass value="1.0"/>'
            '<inertia ixx="0.5" ixy="-0.1" ixz="-0.2" iyy="0.6" iyz="-0.3" izz="0.7"/></inertial></link>'
        ),
        facts=(F("inertial base ixy", -0.1), F("inertial base ixz", -0.2), F("inertial base iyz", -0.3)),
    ),
    case(
        INERTIAL,
        "URDF_SCHEMA_LINK_INERTIAL.inertial_with_origin",
        "load",
        robot(
            '<link name="base"><inertial><origin xyz="0.1 -0.2 0.3" rpy="0 0 1.5707963"/><mass value="2.0"/>'
            '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>'
        ),
        facts=(F("inertial base origin.xyz", (0.1, -0.2, 0.3)),),
    ),
    # urdf_schema_material_test.cpp
    case(
        MATERIAL,
        "URDF_SCHEMA_MATERIAL.global_material_with_color",
        "load",
        robot(
            '<material name="blue"><color rgba="0.0 0.0 1.0 1.0"/></material>\n'
            '<link name="base"><visual><geometry><sphere radius="0.1"/></geometry><material name="blue"/></visual></link>',
            name="material_robot",
        ),
        asset="global_material.urdf",
        facts=(F("visuals base", 1),),
    ),
    case(
        MATERIAL,
        "URDF_SCHEMA_MATERIAL.global_material_with_texture",
        "load",
        robot(
            '<material name="checker"><texture filename="package://my_pkg/textures/checker.png"/></material>\n'
            '<link name="base"><visual><geometry><sphere radius="0.1"/></geometry><material name="checker"/></visual></link>'
        ),
        facts=(F("visuals base", 1),),
    ),
    case(
        MATERIAL,
        "URDF_SCHEMA_MATERIAL.duplicate_global_material_fails",
        "refuse",
        robot(
            '<material name="red"><color rgba="1 0 0 1"/></material>\n<material name="red"><color rgba="0.8 0 0 1"/></material>\n'
            '<link name="base"/>'
        ),
        asset="bad_duplicate_material.urdf",
        problem="GC128.*red",
    ),
    case(
        MATERIAL,
        "URDF_SCHEMA_MATERIAL.inline_material_definition_in_visual",
        "load",
        robot(
            '<link name="base"><visual><geometry><sphere radius="0.1"/></geometry>'
            '<material name="green_ish"><color rgba="0.1 0.9 0.1 0.5"/></material></visual></link>'
        ),
        facts=(F("visuals base", 1),),
    ),
    case(
        MATERIAL,
        "URDF_SCHEMA_MATERIAL.visual_color_rgba_boundary_values",
        "load",
        robot(
            '<link name="base"><visual><geometry><sphere radius="0.1"/></geometry>'
            '<material name=""><color rgba="0.0 1.0 0.0 1.0"/></material></visual></link>'
        ),
        facts=(F("visuals base", 1),),
    ),
    # urdf_schema_origin_test.cpp
    case(
        ORIGIN,
        "URDF_SCHEMA_ORIGIN.origin_no_attributes_is_identity",
        "load",
        two("fixed", "<origin/>"),
        facts=(F("joint j1 origin.xyz", (0.0, 0.0, 0.0)), F("joint j1 origin.quat", IDENTITY)),
    ),
    case(
        ORIGIN,
        "URDF_SCHEMA_ORIGIN.origin_xyz_only",
        "load",
        two("fixed", '<origin xyz="0.5 -1.5 2.25"/>'),
        facts=(F("joint j1 origin.xyz", (0.5, -1.5, 2.25)),),
    ),
    case(
        ORIGIN,
        "URDF_SCHEMA_ORIGIN.origin_rpy_only",
        "load",
        two("fixed", '<origin rpy="1.5707963 0 0"/>'),
        facts=(F("joint j1 origin.quat", (0.7071068, 0.0, 0.0, 0.7071068)),),
    ),
    case(
        ORIGIN,
        "URDF_SCHEMA_ORIGIN.origin_negative_xyz_values",
        "load",
        two("fixed", '<origin xyz="-10.0 -20.5 -0.001"/>'),
        facts=(F("joint j1 origin.xyz", (-10.0, -20.5, -0.001)),),
    ),
    case(
        ORIGIN,
        "URDF_SCHEMA_ORIGIN.quat_xyzw_ignored_in_v1_0",
        "load",
        two("fixed", '<origin quat_xyzw="0.5 0.5 0.5 0.5"/>'),
        facts=(F("joint j1 origin.quat", IDENTITY),),
    ),
    # urdf_schema_topology_test.cpp
    case(
        TOPOLOGY,
        "URDF_SCHEMA_TOPOLOGY.three_link_chain_topology",
        "load",
        robot(
            '<link name="base"/>\n<link name="mid"/>\n<link name="tip"/>\n'
            + joint("fixed", parent="base", child="mid")
            + "\n"
            + joint("fixed", name="j2", parent="mid", child="tip"),
            name="three_link_chain",
        ),
        asset="three_link_chain.urdf",
        facts=(
            F("count links", 3),
            F("count joints", 2),
            F("root", "base"),
            F("children base", 1),
            F("joint j1 child", "mid"),
            F("children mid", 1),
            F("joint j2 child", "tip"),
            F("children tip", 0),
        ),
    ),
    case(
        TOPOLOGY,
        "URDF_SCHEMA_TOPOLOGY.branching_topology",
        "load",
        robot(
            '<link name="torso"/>\n<link name="left_arm"/>\n<link name="right_arm"/>\n<link name="head"/>\n'
            + joint("fixed", name="j_left", parent="torso", child="left_arm")
            + "\n"
            + joint("fixed", name="j_right", parent="torso", child="right_arm")
            + "\n"
            + joint("fixed", name="j_head", parent="torso", child="head"),
            name="branching_robot",
        ),
        asset="branching_robot.urdf",
        facts=(F("count links", 4), F("count joints", 3), F("root", "torso"), F("children torso", 3)),
    ),
    case(
        TOPOLOGY,
        "URDF_SCHEMA_TOPOLOGY.parent_link_tree_is_correct",
        "load",
        robot('<link name="base"/>\n<link name="child"/>\n' + joint("fixed", parent="base", child="child")),
        facts=(F("joint j1 parent", "base"), F("joint j1 child", "child")),
    ),
    # urdf_schema_visual_collision_test.cpp
    case(
        VISUAL,
        "URDF_SCHEMA_VISUAL_COLLISION.visual_with_name_attr",
        "load",
        robot('<link name="base"><visual name="my_visual"><geometry><sphere radius="0.1"/></geometry></visual></link>'),
        facts=(F("visuals base", 1), F("shape base visual 0 name", "my_visual")),
    ),
    case(
        VISUAL,
        "URDF_SCHEMA_VISUAL_COLLISION.collision_with_name_attr",
        "load",
        robot(
            '<link name="base"><collision name="my_col"><geometry><sphere radius="0.1"/></geometry></collision></link>'
        ),
        facts=(F("collisions base", 1), F("shape base collision 0 name", "my_col")),
    ),
    case(
        VISUAL,
        "URDF_SCHEMA_VISUAL_COLLISION.visual_with_origin",
        "load",
        robot(
            '<link name="base"><visual><origin xyz="1.0 -2.0 3.0" rpy="0.1 0.2 0.3"/>'
            '<geometry><sphere radius="0.1"/></geometry></visual></link>'
        ),
        facts=(F("shape base visual 0 origin.xyz", (1.0, -2.0, 3.0)),),
    ),
    case(
        VISUAL,
        "URDF_SCHEMA_VISUAL_COLLISION.collision_with_origin",
        "load",
        robot(
            '<link name="base"><collision><origin xyz="-0.5 0.0 0.25" rpy="0 0 0"/>'
            '<geometry><box size="1 1 1"/></geometry></collision></link>'
        ),
        facts=(F("shape base collision 0 origin.xyz", (-0.5, 0.0, 0.25)),),
    ),
    case(
        VISUAL,
        "URDF_SCHEMA_VISUAL_COLLISION.multiple_visuals_v1_0",
        "load",
        MULTIPLE_GEOMETRIES,
        asset="multiple_geometries.urdf",
        facts=(
            F("visuals base", 3),
            F("shape base visual 0 type", "sphere"),
            F("shape base visual 1 type", "box"),
            F("shape base visual 2 type", "cylinder"),
        ),
    ),
    case(
        VISUAL,
        "URDF_SCHEMA_VISUAL_COLLISION.multiple_collisions_v1_0",
        "load",
        MULTIPLE_GEOMETRIES,
        asset="multiple_geometries.urdf",
        facts=(F("collisions base", 2),),
    ),
    case(
        VISUAL,
        "URDF_SCHEMA_VISUAL_COLLISION.visual_and_collision_in_same_link",
        "load",
        robot(
            '<link name="base"><visual><geometry><sphere radius="0.5"/></geometry></visual>'
            '<collision><geometry><box size="1 1 1"/></geometry></collision></link>'
        ),
        facts=(
            F("visuals base", 1),
            F("collisions base", 1),
            F("shape base visual 0 type", "sphere"),
            F("shape base collision 0 type", "box"),
        ),
    ),
    # urdf_schema_full_robot_test.cpp
    case(
        FULL,
        "URDF_SCHEMA_FULL_ROBOT.full_v1_0_robot_all_features",
        "load",
        FULL_ROBOT,
        asset="full_robot_v1_0.urdf",
        facts=(
            F("name", "full_robot"),
            F("count links", 7),
            F("count joints", 6),
            F("root", "base_link"),
            F("inertial base_link mass", 10.0),
            F("inertial base_link ixx", 0.1),
            F("visuals base_link", 1),
            F("collisions base_link", 1),
            F("shape base_link visual 0 type", "box"),
            F("joint shoulder_joint type", "revolute"),
            F("joint shoulder_joint limit.lower", -1.5707963),
            F("joint shoulder_joint limit.upper", 1.5707963),
            F("joint shoulder_joint limit.effort", 50.0),
            F("joint shoulder_joint limit.velocity", 1.0),
            F("joint elbow_joint type", "prismatic"),
            F("joint wrist_joint type", "continuous"),
            F("joint wrist_joint limit", None),
            F("shape wrist_link visual 0 type", "mesh"),
            F("shape wrist_link visual 0 filename", "package://robot/meshes/wrist.dae"),
            F("joint tool_joint type", "fixed"),
            F("joint camera_joint type", "floating"),
            F("joint platform_joint type", "planar"),
            F("joint platform_joint mimic.joint", "shoulder_joint"),
            F("joint platform_joint mimic.multiplier", 0.5),
            F("joint platform_joint mimic.offset", 0.0),
        ),
    ),
    # urdf_schema_quaternion_test.cpp
    case(
        QUATERNION,
        "URDF_UNIT_TEST.parse_rot_rpy_version_1_0",
        "load",
        robot(PAIR.format(rotation='rpy="1.5707963 0 1.5707963"'), "1.0", "rot_rpy"),
        facts=(F("count links", 2), F("count joints", 2), F("name", "rot_rpy"), F("joint j1 origin.quat", HALVES)),
    ),
    case(
        QUATERNION,
        "URDF_UNIT_TEST.parse_rot_quat_ignored_version_1_0",
        "load",
        robot(PAIR.format(rotation='quat_xyzw="0.5 0.5 0.5 0.5"'), "1.0", "rot_quat_ignored"),
        facts=(F("count links", 2), F("count joints", 2), F("joint j1 origin.quat", IDENTITY)),
    ),
    case(
        QUATERNION,
        "URDF_UNIT_TEST.parse_rot_quat_version_1_1",
        "load",
        robot(PAIR.format(rotation='quat_xyzw="0.5 0.5 0.5 0.5"'), "1.1", "rot_quat"),
        facts=(F("count links", 2), F("count joints", 2), F("joint j1 origin.quat", HALVES)),
    ),
    case(
        QUATERNION,
        "URDF_UNIT_TEST.parse_rot_both_quat_ignored_version_1_0",
        "load",
        robot(PAIR.format(rotation='rpy="0 0 0" quat_xyzw="0.5 0.5 0.5 0.5"'), "1.0", "rot_both_quat_ignored"),
        facts=(F("count links", 2), F("count joints", 2), F("joint j1 origin.quat", IDENTITY)),
    ),
    case(
        QUATERNION,
        "URDF_UNIT_TEST.parse_rot_both_error_version_1_1",
        "refuse",
        robot(PAIR.format(rotation='rpy="0 0 0" quat_xyzw="0.5 0.5 0.5 0.5"'), "1.1", "rot_both_error"),
        problem="GC107.*rpy and quat_xyzw",
    ),
    # urdf_version_test.cpp
    case(VERSION, "URDF_VERSION.test_version_wrong_type", "refuse", robot("", "foo", "test"), problem="GC127"),
    case(VERSION, "URDF_VERSION.test_version_unsupported_version", "refuse", robot("", "2", "test"), problem="GC127"),
    case(
        VERSION,
        "URDF_VERSION.test_version_not_specified",
        "load",
        robot('<link name="l1"/>', None, "test"),
        facts=(F("count links", 1),),
    ),
    case(
        VERSION, "URDF_VERSION.test_version_one_int", "refuse", robot('<link name="l1"/>', "1", "test"), problem="GC127"
    ),
    case(
        VERSION,
        "URDF_VERSION.test_version_one_float",
        "load",
        robot('<link name="l1"/>', "1.0", "test"),
        facts=(F("count links", 1),),
    ),
    case(
        VERSION,
        "URDF_VERSION_CLASS.test_null_ptr",
        "load",
        robot('<link name="l1"/>', None, "test"),
        facts=(F("count links", 1),),
    ),
    case(
        VERSION,
        "URDF_VERSION_CLASS.test_correct_string",
        "load",
        robot('<link name="l1"/>', "1.0", "test"),
        facts=(F("count links", 1),),
    ),
    version_class("test_too_many_dots", "1.0.0", "form 'x.y'"),
    version_class("test_not_enough_numbers", "1.", "form 'x.y'"),
    version_class("test_no_major_number", ".1", "blank"),
    version_class("test_negative_major_number", "-1.0", "must be positive"),
    version_class("test_negative_minor_number", "1.-1", "must be positive"),
    version_class("test_no_numbers", "abc", "form 'x.y'"),
    version_class("test_dots_no_numbers", "a.c", "not an integer"),
    version_class("test_dots_one_number", "1.c", "not an integer"),
    version_class("test_trailing_junk", "1.0~pre6", "Extra characters"),
    # urdf_unit_test.cpp
    vector3("test_vector3_simple", "1.0 2.0 3.0", "load", (F("joint j1 origin.xyz", (1.0, 2.0, 3.0)),)),
    vector3("test_vector3_bad_string", "1.0 foo 3.0", "refuse"),
    vector3("test_vector3_invalid_number", "1.0 2.10.110 3.0", "refuse"),
    vector3("test_vector3_not_enough_numbers", "1.0 2.0", "refuse"),
    vector3("test_vector3_too_many_numbers", "1.0 2.0 3.0 4.0", "refuse"),
    case(
        UNIT,
        "URDF_UNIT_TEST.parse_joint_doubles",
        "load",
        robot(
            """<joint name="j1" type="fixed">
  <parent link="l1"/>
  <child link="l2"/>
  <origin xyz="0 0 0" rpy="0 0 0"/>
  <dynamics damping="87.098" friction="3.1290"/>
  <limit lower="12.34" upper="22.999" effort="99.0" velocity="23.0"/>
  <safety_controller soft_lower_limit="8.765" soft_upper_limit="9.003" k_position="7.0034" k_velocity="9.998"/>
  <calibration rising="8.654" falling="0.0445"/>
  <mimic joint="j2" multiplier="9.87" offset="0.098"/>
</joint>
<joint name="j2" type="fixed"><parent link="l1"/><child link="l2"/></joint>
<link name="l1"/>
<link name="l2"/>""",
            None,
            "test",
        ),
        facts=(
            F("count links", 2),
            F("count joints", 2),
            F("name", "test"),
            F("joint j1 limit.lower", 12.34),
            F("joint j1 limit.upper", 22.999),
            F("joint j1 limit.effort", 99.0),
            F("joint j1 limit.velocity", 23.0),
            F("joint j1 mimic.multiplier", 9.87),
            F("joint j1 mimic.offset", 0.098),
        ),
    ),
    case(
        UNIT,
        "URDF_UNIT_TEST.parse_link_doubles",
        "load",
        robot(DOUBLES_JOINTS + "\n" + DOUBLES_LINKS.format(material1="", material2=""), None, "test"),
        facts=DOUBLES_FACTS,
    ),
    case(
        UNIT,
        "URDF_UNIT_TEST.parse_color_doubles",
        "load",
        robot(
            DOUBLES_JOINTS
            + "\n"
            + DOUBLES_LINKS.format(
                material1='<material name=""><color rgba="1.0 0.65 0.0 0.01"/></material>',
                material2='<material name="red ish"><color rgba="1 0.0001 0.0 1"/></material>',
            ),
            None,
            "test",
        ),
        facts=DOUBLES_FACTS,
    ),
    case(
        UNIT,
        "URDF_UNIT_TEST.material_no_name",
        "refuse",
        robot('<material/>\n<link name="l1"/>', None, "test"),
        problem="GC108.*material",
    ),
    case(
        UNIT,
        "URDF_UNIT_TEST.link_no_name",
        "refuse",
        robot("<link/>", None, "test"),
        problem="GC108.*<link> has no name",
    ),
)
