"""Every GC1xx rule: a small description that triggers it (code, subject, line) and one that does not."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from geomcheck.checks.structure import check_robot
from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError
from geomcheck.load import load_description, make_bundle
from geomcheck.rules import all_rules
from geomcheck.thresholds import StructureThresholds

CLEAN = """<?xml version="1.0"?>
<robot name="arm">
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base_link">
    <inertial>
      <origin xyz="0 0 0"/>
      <mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
    <visual>
      <origin xyz="0 0 0.1" rpy="0 0 0"/><geometry><box size="0.2 0.2 0.2"/></geometry><material name="grey"/>
    </visual>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <link name="upper_arm">
    <visual><geometry><cylinder radius="0.05" length="0.4"/></geometry></visual>
  </link>
  <link name="forearm">
    <collision><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/>
    <child link="upper_arm"/>
    <origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper_arm"/>
    <child link="forearm"/>
    <origin xyz="0 0 0.4"/>
    <axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/>
    <mimic joint="shoulder" multiplier="1" offset="0"/>
  </joint>
  <gazebo reference="base_link"><material>Gazebo/Grey</material><mu1>0.5</mu1></gazebo>
  <transmission name="t"><type>transmission_interface/SimpleTransmission</type></transmission>
</robot>
"""

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
CLEAN_XACRO = f"""<?xml version="1.0"?>
<robot name="arm" {NS}>
  <xacro:property name="size" value="0.2"/>
  <link name="base_link">
    <visual><geometry><box size="${{size}} ${{size}} ${{size}}"/></geometry></visual>
  </link>
</robot>
"""

SHOULDER = '<joint name="shoulder" type="revolute">'
ELBOW = '<joint name="elbow" type="revolute">'
SHOULDER_LIMIT = '<limit lower="-1.5" upper="1.5" effort="10" velocity="1"/>'
SHOULDER_AXIS = '<axis xyz="0 1 0"/>\n    <limit lower="-1.5"'


@dataclass(frozen=True)
class Case:
    code: str
    bad: tuple[tuple[str, str], ...]  # replacements (old, new), first occurrence each
    subject: tuple[str, str] | None  # ("link" | "joint", name); None: the robot
    line_at: str  # text in the bad description whose line the finding points at
    message: str = ""  # a fragment of the message
    good: tuple[tuple[str, str], ...] = ()  # a near miss that must not trigger
    base: str = CLEAN
    name: str = "robot.urdf"
    occurrence: int = 1  # which occurrence of line_at


def add_before_first_joint(text: str) -> tuple[tuple[str, str], ...]:
    return ((SHOULDER, f"{text}\n  {SHOULDER}"),)


CASES = [
    Case("GC101", (("</collision>\n  </link>", "</collision>\n"),), None, "</robot>", "tag mismatch"),
    Case(
        "GC102",
        (("${size} ${size}", "${size} ${width}"),),
        None,
        "${width}",
        "name 'width' is not defined",
        good=(("${size} ${size}", "${size} ${size}"),),
        base=CLEAN_XACRO,
        name="arm.urdf.xacro",
    ),
    Case(
        "GC103",
        (('<xacro:property name="size"', '<property name="size"'),),
        None,
        "<property",
        "<property> x1",
        base=CLEAN_XACRO,
        name="arm.urdf.xacro",
    ),
    Case(
        "GC104",
        (('value="0.2"/>', 'value="0.2" unit="m"/>'),),
        None,
        "",
        "unknown attribute(s): unit",
        base=CLEAN_XACRO,
        name="arm.urdf.xacro",
    ),
    Case(
        "GC105",
        (('<origin xyz="0 0 0.2"/>', '<orgin xyz="0 0 0.2"/>'),),
        ("joint", "shoulder"),
        "<orgin",
        "unknown element <orgin> inside <joint>; did you mean 'origin'?",
    ),
    Case(
        "GC106",
        ((SHOULDER_AXIS, SHOULDER_AXIS.replace("xyz", "xzy")),),
        ("joint", "shoulder"),
        "xzy",
        "unknown attribute 'xzy' (did you mean 'xyz'?) on <axis>",
    ),
    Case(
        "GC107",
        (('<origin xyz="0 0 0.4"/>', '<origin xyz="0 0,4 0"/>'),),
        ("joint", "elbow"),
        "0 0,4 0",
        "'0,4' is not a finite number",
    ),
    Case("GC108", ((ELBOW, '<joint name="elbow">'),), ("joint", "elbow"), '<joint name="elbow"', "has no type"),
    Case(
        "GC109",
        (
            (
                '<visual><geometry><cylinder radius="0.05" length="0.4"/></geometry></visual>',
                '<visual><origin xyz="0 0 0"/></visual>',
            ),
        ),
        ("link", "upper_arm"),
        '<visual><origin xyz="0 0 0"/>',
        "<visual> has no <geometry>",
    ),
    Case(
        "GC110",
        add_before_first_joint('<link name="forearm"/>'),
        ("link", "forearm"),
        '<link name="forearm"',
        "link name 'forearm' is already used",
        occurrence=2,
    ),
    Case(
        "GC111",
        add_before_first_joint(
            '<link name="tool"/><joint name="elbow" type="fixed"><parent link="forearm"/><child link="tool"/></joint>'
        ),
        ("joint", "elbow"),
        '<joint name="elbow"',
        "joint name 'elbow' is already used by the joint at robot.urdf:21",
        occurrence=2,
    ),
    Case(
        "GC112",
        (('<parent link="upper_arm"/>', '<parent link="uper_arm"/>'),),
        ("joint", "elbow"),
        ELBOW,
        "parent link 'uper_arm' is not declared; did you mean 'upper_arm'?",
    ),
    Case(
        "GC113",
        add_before_first_joint(
            '<joint name="fix" type="fixed"><parent link="world"/><child link="base_link"/></joint>'
        ),
        ("joint", "fix"),
        '<joint name="fix"',
        "parent link 'world' is not declared",
        good=add_before_first_joint(
            '<link name="world"/><joint name="fix" type="fixed"><parent link="world"/><child link="base_link"/></joint>'
        ),
    ),
    Case(
        "GC114",
        ((CLEAN[CLEAN.index("  <material") : CLEAN.index("</robot>")], ""),),
        None,
        '<robot name="arm">',
        "the robot declares no links",
    ),
    Case(
        "GC115",
        add_before_first_joint('<link name="camera"/>'),
        ("link", "camera"),
        '<link name="camera"',
        "not connected to the tree rooted at 'base_link' (2 root links: base_link, camera)",
    ),
    Case(
        "GC116",
        add_before_first_joint(
            '<joint name="loop" type="fixed"><parent link="forearm"/><child link="base_link"/></joint>'
        ),
        ("joint", "loop"),
        '<joint name="loop"',
        "form a closed loop",
    ),
    Case(
        "GC117",
        add_before_first_joint(
            '<joint name="extra" type="fixed"><parent link="base_link"/><child link="forearm"/></joint>'
        ),
        ("link", "forearm"),
        '<joint name="elbow"',
        "link is the child of 2 joints: extra, elbow",
    ),
    Case(
        "GC118",
        ((ELBOW, '<joint name="elbow" type="revolut">'),),
        ("joint", "elbow"),
        '<joint name="elbow"',
        "did you mean 'revolute'?",
    ),
    Case(
        "GC119",
        ((SHOULDER_AXIS, SHOULDER_AXIS.replace("0 1 0", "0 0 0")),),
        ("joint", "shoulder"),
        SHOULDER,
        'zero-length axis (xyz="0 0 0")',
    ),
    Case(
        "GC120",
        ((SHOULDER_AXIS, SHOULDER_AXIS.replace("0 1 0", "0 2 0")),),
        ("joint", "shoulder"),
        SHOULDER,
        'axis xyz="0 2 0" has length 2, not 1',
        good=((SHOULDER_AXIS, SHOULDER_AXIS.replace("0 1 0", "0 0.7071 0.7071")),),
    ),
    Case("GC121", ((SHOULDER_LIMIT, ""),), ("joint", "shoulder"), SHOULDER, "revolute joint has no <limit>"),
    Case(
        "GC122",
        ((SHOULDER_LIMIT, SHOULDER_LIMIT.replace('lower="-1.5" upper="1.5"', 'lower="1.5" upper="-1.5"')),),
        ("joint", "shoulder"),
        SHOULDER,
        "lower limit 1.5 rad is above upper limit -1.5 rad",
    ),
    Case(
        "GC123",
        (('<mimic joint="shoulder"', '<mimic joint="shouldr"'),),
        ("joint", "elbow"),
        ELBOW,
        "<mimic joint='shouldr'> names no joint; did you mean 'shoulder'?",
    ),
    Case(
        "GC124",
        (('<material name="grey"/>', '<material name="gray"/>'),),
        ("link", "base_link"),
        '<material name="gray"/>',
        "material 'gray' is not defined with a color or texture; did you mean 'grey'?",
    ),
    Case(
        "GC125",
        ((SHOULDER_LIMIT, SHOULDER_LIMIT + '\n    <mimic joint="elbow"/>'),),
        ("joint", "shoulder"),
        SHOULDER,
        "mimic joints follow each other in a loop: shoulder -> elbow -> shoulder",
    ),
    Case(
        "GC126",
        (('<origin xyz="0 0 0.4"/>', '<origin xyz="0 0 4e5"/>'),),
        ("joint", "elbow"),
        "0 0 4e5",
        '<origin xyz="0 0 4e5">: 400000 m is beyond the limit of 100000 m',
        good=(('<origin xyz="0 0 0.4"/>', '<origin xyz="0 0 9e4"/>'),),
    ),
    Case(
        "GC127",
        (('<robot name="arm">', '<robot name="arm" version="1.0.0">'),),
        None,
        'version="1.0.0"',
        "<robot version=\"1.0.0\"> is not a version urdfdom reads (The version attribute should be in the form 'x.y')",
        good=(('<robot name="arm">', '<robot name="arm" version="1.1">'),),
    ),
    Case(
        "GC128",
        (
            (
                '<link name="base_link">',
                '<material name="grey"><color rgba="0.4 0.4 0.4 1"/></material>\n  <link name="base_link">',
            ),
        ),
        None,
        '<material name="grey"><color rgba="0.4',
        "material 'grey' is already defined at robot.urdf:3: urdfdom refuses the robot",
        good=(
            (
                '<link name="base_link">',
                '<material name="gray"><color rgba="0.4 0.4 0.4 1"/></material>\n  <link name="base_link">',
            ),
        ),
    ),
    Case(
        "GC129",
        (('<sphere radius="0.05"/>', '<capsule radius="0.05" length="0.1"/>'),),
        ("link", "forearm"),
        "<capsule",
        '<capsule> is URDF 1.1, this file is URDF 1.0 (write <robot version="1.1">): urdfdom logs an error and loads '
        "the robot without this <collision>",
        good=(
            ('<robot name="arm">', '<robot name="arm" version="1.1">'),
            ('<sphere radius="0.05"/>', '<capsule radius="0.05" length="0.1"/>'),
        ),
    ),
    Case(
        "GC130",
        (
            ('<limit lower="-2" upper="2"', '<limit lower="0" upper="2"'),
            ('<mimic joint="shoulder" multiplier="1"', '<mimic joint="shoulder" multiplier="-1"'),
        ),
        ("joint", "elbow"),
        ELBOW,
        "mimics shoulder (-1.5 to 1.5 rad) with multiplier -1: it must reach -1.5 to 1.5 rad, but its limits are 0 to "
        "2 rad: over 50% of shoulder's range it cannot follow",
        good=(('<mimic joint="shoulder" multiplier="1"', '<mimic joint="shoulder" multiplier="-1"'),),
    ),
    Case(
        "GC131",
        (('<?xml version="1.0"?>', '<?xml version="0.0"?>'),),
        None,
        "<?xml",
        'robot.urdf declares XML version "0.0", which XML does not have: ROS, Gazebo, MuJoCo and PyBullet read it',
        good=(('<?xml version="1.0"?>', '<?xml version="1.1"?>'),),
    ),
    Case(
        "GC132",
        (('<?xml version="1.0"?>', '<!-- exported --><?xml version="1.0"?>'),),
        None,
        "<!-- exported -->",
        "robot.urdf is XML only as TinyXML2 reads it: its <?xml ...?> declaration stands after blank lines or a "
        "comment",
        good=(('<?xml version="1.0"?>', '<?xml version="1.0"?><!-- exported -->'),),
    ),
]


def apply(text: str, replacements: tuple[tuple[str, str], ...]) -> str:
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


def line_of(text: str, needle: str, occurrence: int = 1) -> int:
    index = -1
    for _ in range(occurrence):
        index = text.index(needle, index + 1)
    return text.count("\n", 0, index) + 1


def findings(tmp_path: Path, text: str, name: str) -> list[Diagnostic]:
    """Every GC1xx finding of a description: load-time ones, structure checks, or the input error."""
    root = tmp_path / name
    root.write_text(text, encoding="utf-8")
    try:
        loaded = load_description(make_bundle(root, display_root=tmp_path))
    except InputError as err:
        assert err.diagnostic is not None
        return [err.diagnostic]
    return [d for d in (*loaded.diagnostics, *check_robot(loaded.robot)) if d.code.startswith("GC1")]


@pytest.mark.parametrize("case", CASES, ids=[c.code for c in CASES])
def test_rule_triggers_with_subject_and_line(tmp_path: Path, case: Case) -> None:
    bad = apply(case.base, case.bad)
    found = [d for d in findings(tmp_path, bad, case.name) if d.code == case.code]
    assert len(found) == 1, found
    d = found[0]
    kind, name = case.subject if case.subject else (None, None)
    assert (d.link, d.joint) == ((name, None) if kind == "link" else (None, name) if kind == "joint" else (None, None))
    assert d.location is not None and d.location.file == case.name
    expected_line = line_of(bad, case.line_at, case.occurrence) if case.line_at else None
    assert d.location.line == expected_line
    assert case.message in d.message
    assert d.help


@pytest.mark.parametrize("case", CASES, ids=[c.code for c in CASES])
def test_rule_does_not_trigger_on_the_near_miss(tmp_path: Path, case: Case) -> None:
    good = apply(case.base, case.good)
    assert [d for d in findings(tmp_path, good, case.name) if d.code == case.code] == []


def test_clean_descriptions_have_no_gc1_findings(tmp_path: Path) -> None:
    assert findings(tmp_path, CLEAN, "robot.urdf") == []
    assert findings(tmp_path, CLEAN_XACRO, "arm.urdf.xacro") == []


def test_every_gc1_rule_is_tested_and_documented() -> None:
    rules = [r for r in all_rules() if r.code.startswith("GC1")]
    assert sorted(c.code for c in CASES) == [r.code for r in rules]
    for rule in rules:
        assert rule.name == rule.name.lower() and " " not in rule.name
        assert rule.summary and rule.what and rule.why and rule.example and rule.fix


def test_cycle_makes_no_root_and_is_reported_once(tmp_path: Path) -> None:
    bad = apply(
        CLEAN,
        add_before_first_joint(
            '<joint name="loop" type="fixed"><parent link="forearm"/><child link="base_link"/></joint>'
        ),
    )
    codes = sorted(d.code for d in findings(tmp_path, bad, "robot.urdf"))
    assert codes == ["GC114", "GC116"]


def test_a_joint_written_backwards_is_one_gc117_with_the_swap(tmp_path: Path) -> None:
    # a camera attached by parent=camera child=forearm: forearm has two parent joints and the
    # camera, the root of a tree of its own, is named by the GC117 rather than by a GC115
    bad = apply(
        CLEAN,
        add_before_first_joint(
            '<link name="camera"/>'
            '<joint name="mount" type="fixed"><parent link="camera"/><child link="forearm"/></joint>'
        ),
    )
    found = findings(tmp_path, bad, "robot.urdf")
    assert [(d.code, d.link) for d in found] == [("GC117", "forearm")]
    assert found[0].message == (
        "link is the child of 2 joints: mount, elbow; joint mount joins the tree of 'camera', which no joint "
        "attaches: swapped (parent 'forearm', child 'camera') it makes one tree; urdfdom loads it, but KDL "
        "(robot_state_publisher) refuses the robot"
    )
    assert (found[0].data["joints"], found[0].data["reversed"]) == (["mount", "elbow"], ["mount"])
    assert found[0].data["accepted_by"] == "urdfdom"
    # a second parent within the one tree joins nothing: no swap is offered
    within = apply(
        CLEAN,
        add_before_first_joint(
            '<joint name="extra" type="fixed"><parent link="base_link"/><child link="forearm"/></joint>'
        ),
    )
    (d,) = findings(tmp_path, within, "robot.urdf")
    assert (d.code, d.data["reversed"]) == ("GC117", [])
    assert d.message.startswith("link is the child of 2 joints: extra, elbow; urdfdom loads it")


def test_joint_without_parent_or_child(tmp_path: Path) -> None:
    bad = apply(
        CLEAN,
        add_before_first_joint(
            '<joint name="gripper" type="prismatic"><limit lower="0" upper="0.09" effort="1" velocity="1"/></joint>'
        ),
    )
    found = [(d.code, d.joint, d.about, d.message) for d in findings(tmp_path, bad, "robot.urdf")]
    assert found == [("GC112", "gripper", "parent+child", "joint has no <parent link=...> and no <child link=...>")]
    no_child = apply(
        CLEAN,
        add_before_first_joint('<joint name="gripper" type="fixed"><parent link="forearm"/></joint>'),
    )
    found = [(d.code, d.joint, d.about, d.message) for d in findings(tmp_path, no_child, "robot.urdf")]
    assert found == [("GC112", "gripper", "child", "joint has no <child link=...>")]


def test_a_macro_line_missing_links_for_both_sides_is_one_finding(tmp_path: Path) -> None:
    text = f"""<?xml version="1.0"?>
<robot name="r" {NS}>
  <xacro:macro name="gripper" params="side">
    <joint name="${{side}}_gripper_joint" type="prismatic">
      <limit effort="100" velocity="0.2" lower="0" upper="0.09"/>
    </joint>
  </xacro:macro>
  <link name="base"/>
  <xacro:gripper side="l"/><xacro:gripper side="r"/>
</robot>
"""
    found = [d for d in findings(tmp_path, text, "r.urdf.xacro") if d.code == "GC112"]
    assert [(d.joint, d.about, d.data["also"]) for d in found] == [
        ("l_gripper_joint", "parent+child", ["r_gripper_joint"])
    ]
    assert found[0].message.endswith("(also in r_gripper_joint)")
    assert found[0].location is not None and found[0].location.line == 4


def test_undeclared_world_parent_is_a_warning_naming_who_refuses_it(tmp_path: Path) -> None:
    world = '<joint name="fix" type="fixed"><parent link="world"/><child link="base_link"/></joint>'
    (d,) = findings(tmp_path, apply(CLEAN, add_before_first_joint(world)), "robot.urdf")
    assert (d.code, d.severity.value, d.joint, d.data["link"]) == ("GC113", "warning", "fix", "world")
    assert d.message == (
        "parent link 'world' is not declared: urdfdom (robot_state_publisher, MoveIt, Gazebo's URDF import) refuses "
        "the robot; the boxturtle parser (ROS until 2010) added the link, and geomcheck takes it, as the fixed world "
        "frame"
    )


def test_limit_without_bounds_is_a_warning(tmp_path: Path) -> None:
    bad = apply(CLEAN, ((SHOULDER_LIMIT, '<limit effort="10" velocity="1"/>'),))
    (d,) = [d for d in findings(tmp_path, bad, "robot.urdf") if d.code == "GC121"]
    assert d.severity.value == "warning"
    assert "urdfdom reads its range as [0, 0]" in d.message and "MuJoCo and PyBullet leave it unlimited" in d.message


def test_axis_tolerance_comes_from_thresholds(tmp_path: Path) -> None:
    bad = apply(CLEAN, ((SHOULDER_AXIS, SHOULDER_AXIS.replace("0 1 0", "0 1.01 0")),))
    root = tmp_path / "robot.urdf"
    root.write_text(bad)
    robot = load_description(make_bundle(root, display_root=tmp_path)).robot
    assert [d.code for d in check_robot(robot)] == ["GC120"]
    assert check_robot(robot, StructureThresholds(axis_norm_tolerance=0.02)) == []


def test_typo_in_a_macro_is_reported_once_naming_the_other_subjects(tmp_path: Path) -> None:
    text = f"""<?xml version="1.0"?>
<robot name="r" {NS}>
  <xacro:macro name="leg" params="n">
    <link name="${{n}}"><visual><orgin xyz="0 0 0"/><geometry><sphere radius="0.1"/></geometry></visual></link>
  </xacro:macro>
  <link name="base"/>
  <xacro:leg n="a"/><xacro:leg n="b"/><xacro:leg n="c"/>
</robot>
"""
    found = [d for d in findings(tmp_path, text, "r.urdf.xacro") if d.code == "GC105"]
    assert len(found) == 1
    assert found[0].link == "a" and found[0].location is not None and found[0].location.line == 4
    assert found[0].message.endswith("(also in b, c)")


FIXED_WITH_SENTINELS = '<joint name="mount" type="fixed"><parent link="forearm"/><child link="tool"/>'
SENTINEL_LIMIT = '<limit lower="-1e16" upper="1e16" effort="0" velocity="0"/>'


def with_tool(joint: str) -> tuple[tuple[str, str], ...]:
    return ((SHOULDER, f'<link name="tool"/>\n  {joint}\n  {SHOULDER}'),)


@pytest.mark.parametrize("kind", ["fixed", "continuous", "floating", "planar"])
def test_bounds_of_joints_no_consumer_bounds_are_not_judged(tmp_path: Path, kind: str) -> None:
    joint = (
        f'<joint name="mount" type="{kind}"><parent link="forearm"/><child link="tool"/>'
        f'<axis xyz="0 0 1"/><limit lower="-1e16" upper="1e300" effort="0" velocity="0"/></joint>'
    )
    assert findings(tmp_path, apply(CLEAN, with_tool(joint)), "robot.urdf") == []


def test_unparseable_bounds_stay_errors_on_any_joint_type(tmp_path: Path) -> None:
    # urdfdom parses every <limit> and refuses the robot on a number it cannot read
    joint = f'{FIXED_WITH_SENTINELS}<limit lower="-1e400" upper="0" effort="0" velocity="0"/></joint>'
    (d,) = findings(tmp_path, apply(CLEAN, with_tool(joint)), "robot.urdf")
    assert (d.code, d.severity.value, d.joint, d.about) == ("GC107", "error", "mount", "limit.lower")


@pytest.mark.parametrize("kind", ["revolute", "prismatic"])
def test_sdformat_no_limit_sentinel_is_info_and_an_open_bound(tmp_path: Path, kind: str) -> None:
    joint = (
        f'<joint name="slide" type="{kind}"><parent link="forearm"/><child link="tool"/>'
        f'<axis xyz="0 0 1"/>{SENTINEL_LIMIT}</joint>'
    )
    text = apply(CLEAN, with_tool(joint))
    found = findings(tmp_path, text, "robot.urdf")
    assert [(d.code, d.severity.value, d.joint, d.about, d.data["value"]) for d in found] == [
        ("GC126", "info", "slide", "limit.lower", -1e16),
        ("GC126", "info", "slide", "limit.upper", 1e16),
    ]
    assert 'SDFormat\'s "no limit" value, read by Gazebo as unlimited' in found[0].message
    root = tmp_path / "robot.urdf"
    limit = load_description(make_bundle(root, display_root=tmp_path)).robot.joint_map["slide"].limit
    assert limit is not None and (limit.lower, limit.upper, limit.unlimited) == (None, None, True)


def test_one_open_bound_never_inverts_the_range(tmp_path: Path) -> None:
    bad = apply(CLEAN, ((SHOULDER_LIMIT, '<limit lower="-1e16" upper="-0.5" effort="10" velocity="1"/>'),))
    assert [(d.code, d.severity.value) for d in findings(tmp_path, bad, "robot.urdf")] == [("GC126", "info")]


@pytest.mark.parametrize("kind", ["revolute", "prismatic"])
def test_a_large_outward_bound_is_no_limit_written_large(tmp_path: Path, kind: str) -> None:
    """999999 (a mobile base's virtual joints) is "no limit" as its author wrote it: info, an
    open side, and no claim that the joint has no bounds (urdfdom reads them as written)."""
    joint = (
        f'<joint name="slide" type="{kind}"><parent link="forearm"/><child link="tool"/><axis xyz="0 0 1"/>'
        '<limit lower="-999999" upper="999999" effort="10" velocity="1"/></joint>'
    )
    root = tmp_path / "robot.urdf"
    found = findings(tmp_path, apply(CLEAN, with_tool(joint)), "robot.urdf")
    unit = "m" if kind == "prismatic" else "rad"
    assert [(d.code, d.severity.value, d.joint, d.about, d.data["value"]) for d in found] == [
        ("GC126", "info", "slide", "limit.lower", -999999),
        ("GC126", "info", "slide", "limit.upper", 999999),
    ]
    assert found[1].message == (
        f'<limit upper="999999">: 999999 {unit}, a large value written for "no limit" (no {kind} joint travels '
        f"that far); urdfdom, MoveIt and pinocchio take it as written (geomcheck takes the {kind} joint as "
        "unbounded on that side)"
    )
    limit = load_description(make_bundle(root, display_root=tmp_path)).robot.joint_map["slide"].limit
    assert limit is not None and (limit.lower, limit.upper, limit.unlimited) == (None, None, True)


def test_a_large_bound_pointing_inward_is_still_an_error(tmp_path: Path) -> None:
    bad = apply(CLEAN, ((SHOULDER_LIMIT, '<limit lower="3e6" upper="4e6" effort="10" velocity="1"/>'),))
    found = findings(tmp_path, bad, "robot.urdf")
    assert [(d.code, d.severity.value, d.joint, d.about) for d in found] == [
        ("GC126", "error", "shoulder", "limit.lower"),
        ("GC126", "info", "shoulder", "limit.upper"),
    ]
    assert found[0].message == (
        '<limit lower="3e6">: 3e+06 rad is beyond the limit of 100000 rad; urdfdom loads it as written, geomcheck '
        "does not use it"
    )
    assert found[0].data["accepted_by"] == "urdfdom"


def test_distinct_joints_on_one_line_of_a_plain_file_stay_distinct(tmp_path: Path) -> None:
    joints = "".join(f'<joint name="j{i}" type="fixed"/>' for i in range(3))  # minified: one line
    found = [d for d in findings(tmp_path, apply(CLEAN, add_before_first_joint(joints)), "robot.urdf")]
    assert [(d.code, d.joint, "also" in d.data) for d in found] == [
        ("GC112", "j0", False),
        ("GC112", "j1", False),
        ("GC112", "j2", False),
    ]


@pytest.mark.parametrize("tag", ["inertial", "visual", "collision"])
def test_a_link_element_written_after_its_link_closed(tmp_path: Path, tag: str) -> None:
    element = {
        "inertial": '<inertial><mass value="2"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>',
        "visual": '<visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>',
        "collision": '<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>',
    }[tag]
    bad = apply(CLEAN, (('<link name="upper_arm">', f'{element}\n  <link name="upper_arm">'),))
    [d] = [d for d in findings(tmp_path, bad, "robot.urdf") if d.code == "GC105"]
    assert (d.link, d.severity.value, d.location.line) == ("base_link", "warning", line_of(bad, element))
    assert d.message == (
        f"<{tag}> is a child of <robot>, after link base_link closed: urdfdom reads it only inside a <link> and "
        "drops it here, so link base_link goes without it"
    )


@pytest.mark.parametrize(
    ("elbow_upper", "reported"),
    [
        ("0.2869", False),  # 0.0031 rad short: 1.07% of the range, the rounding of a limit written to 4 decimals
        ("0.2800", True),  # 0.01 rad short: more than half a degree, a linkage that stops short
    ],
)
def test_a_mimic_joint_short_of_its_leader_by_rounding_is_no_finding(
    tmp_path: Path, elbow_upper: str, reported: bool
) -> None:
    # the shoulder's range, 0 to 0.29 rad, passed on with multiplier 1: the elbow must reach 0.29
    text = apply(
        CLEAN,
        (
            ('<limit lower="-1.5" upper="1.5"', '<limit lower="0" upper="0.29"'),
            ('<limit lower="-2" upper="2"', f'<limit lower="0" upper="{elbow_upper}"'),
        ),
    )
    found = [d for d in findings(tmp_path, text, "robot.urdf") if d.code == "GC130"]
    assert [(d.joint, d.severity.value) for d in found] == ([("elbow", "warning")] if reported else [])
