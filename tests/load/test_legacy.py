"""Legacy xacro syntax (bare tags, no xmlns:xacro): rewritten in memory, one GC103 per file."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.errors import InputError

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'

# The 2009 PR2 style: no namespace, bare property/macro/insert_block/include.
LEGACY_PARTS = """<?xml version="1.0"?>
<robot>
  <property name="wheel_radius" value="0.079"/>
  <property name="wheel_diameter" value="${2 * wheel_radius}"/>
  <macro name="wheel" params="suffix *origin">
    <link name="${suffix}_wheel">
      <collision><geometry><cylinder radius="${wheel_radius}" length="0.034"/></geometry></collision>
    </link>
    <joint name="${suffix}_wheel_joint" type="continuous">
      <insert_block name="origin"/>
      <parent link="base_link"/>
      <child link="${suffix}_wheel"/>
    </joint>
  </macro>
</robot>
"""

LEGACY_ROOT = """<?xml version="1.0"?>
<robot name="base">
  <include filename="parts.xacro"/>
  <link name="base_link">
    <visual><geometry><box size="${wheel_diameter} 0.6 0.2"/></geometry></visual>
  </link>
  <if value="true">
    <xacro:wheel suffix="left"><origin xyz="0 0.3 0"/></xacro:wheel>
  </if>
  <unless value="true"><link name="never"/></unless>
  <wheel suffix="right"><origin xyz="0 -0.3 0"/></wheel>
  <gazebo><include><uri>model://sun</uri></include></gazebo>
</robot>
"""


def legacy_findings(loaded) -> dict[str, object]:
    return {d.location.file: d for d in loaded.diagnostics if d.code == "GC103"}


def test_legacy_description_loads_like_its_modern_form(load) -> None:
    loaded = load(LEGACY_ROOT, "base.urdf.xacro", files={"parts.xacro": LEGACY_PARTS})
    robot = loaded.robot
    assert [link.name for link in robot.links] == ["base_link", "left_wheel", "right_wheel"]
    assert robot.link_map["base_link"].visuals[0].geometry.size == pytest.approx((0.158, 0.6, 0.2))  # type: ignore[union-attr]
    assert robot.link_map["left_wheel"].collisions[0].geometry.radius == pytest.approx(0.079)  # type: ignore[union-attr]
    assert robot.joint_map["right_wheel_joint"].origin.xyz == pytest.approx((0, -0.3, 0))
    wheel = robot.link_map["right_wheel"]
    assert wheel.location is not None and (wheel.location.file, wheel.location.line) == ("parts.xacro", 6)
    # the Gazebo <include><uri> is not a xacro include and stays in the document
    assert "<uri>model://sun</uri>" in loaded.document.text


def test_one_gc103_per_file_naming_tags_counts_and_fix(load) -> None:
    loaded = load(LEGACY_ROOT, "base.urdf.xacro", files={"parts.xacro": LEGACY_PARTS})
    found = legacy_findings(loaded)
    assert sorted(found) == ["base.urdf.xacro", "parts.xacro"]
    parts = found["parts.xacro"]
    assert parts.name == "legacy-xacro-syntax" and parts.severity.value == "warning"
    assert parts.message == (
        "legacy xacro syntax in parts.xacro: <property> x2, <insert_block> x1, <macro> x1; no xmlns:xacro declaration"
    )
    assert parts.location.line == 3
    assert 'xmlns:xacro="http://www.ros.org/wiki/xacro"' in parts.help
    assert "prefix <insert_block>, <macro>, <property> with xacro:" in parts.help
    root = found["base.urdf.xacro"]
    assert root.message == (
        "legacy xacro syntax in base.urdf.xacro: <if> x1, <include> x1, <unless> x1, bare macro calls x1; "
        "xacro: prefix used without an xmlns:xacro declaration"
    )
    assert root.location.line == 3
    assert root.data["tags"] == {"if": 1, "include": 1, "macro call": 1, "unless": 1}
    # <xacro:wheel> without the declaration: xacro's namespace-aware parser refuses the file
    assert root.severity.value == "error"


def test_a_file_included_twice_is_reported_once(load) -> None:
    root = LEGACY_ROOT.replace(
        '<include filename="parts.xacro"/>', '<include filename="parts.xacro"/>\n  <include filename="parts.xacro"/>'
    )
    loaded = load(root, "base.urdf.xacro", files={"parts.xacro": LEGACY_PARTS})
    assert legacy_findings(loaded)["parts.xacro"].data["tags"] == {"insert_block": 1, "macro": 1, "property": 2}


def test_modern_file_has_no_gc103(load) -> None:
    modern = LEGACY_PARTS.replace("<robot>", f"<robot {NS}>")
    for tag in ("property", "macro", "insert_block"):
        modern = modern.replace(f"<{tag} ", f"<xacro:{tag} ").replace(f"</{tag}>", f"</xacro:{tag}>")
    root = (
        f'<?xml version="1.0"?>\n<robot name="base" {NS}>\n  <xacro:include filename="parts.xacro"/>\n'
        '  <link name="base_link"/>\n  <xacro:wheel suffix="l"><origin xyz="0 0.3 0"/></xacro:wheel>\n</robot>\n'
    )
    loaded = load(root, "base.urdf.xacro", files={"parts.xacro": modern})
    assert [d.code for d in loaded.diagnostics] == []
    assert [link.name for link in loaded.robot.links] == ["base_link", "l_wheel"]


def test_wrong_xacro_namespace_uri_is_named(load) -> None:
    text = (
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://playerstage.sourceforge.net/gazebo/xmlschema/#interface">\n'
        '  <xacro:property name="w" value="1"/>\n  <link name="l${w}"/>\n</robot>\n'
    )
    loaded = load(text, "r.urdf.xacro")
    (finding,) = legacy_findings(loaded).values()
    assert "xmlns:xacro is bound to 'http://playerstage.sourceforge.net/gazebo/xmlschema/#interface'" in finding.message
    assert loaded.robot.links[0].name == "l1"
    # xacro matches xacro:property by the prefix of the tag name, not the URI: dead markup
    assert finding.severity.value == "info"
    assert "the file expands as it is" in finding.help


def test_wrong_namespace_uri_with_bare_tags_is_a_warning(load) -> None:
    text = (
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://example.com/other">\n'
        '  <property name="w" value="1"/>\n  <link name="l${w}"/>\n</robot>\n'
    )
    (finding,) = legacy_findings(load(text, "r.urdf.xacro")).values()
    assert (finding.severity.value, finding.data["tags"]) == ("warning", {"property": 1})


def test_plain_urdf_declaring_a_wrong_namespace_is_not_legacy(load) -> None:
    text = '<robot name="r" xmlns:xacro="http://example.com/other">\n  <link name="a"/>\n</robot>\n'
    loaded = load(text, "r.urdf")
    assert [d.code for d in loaded.diagnostics] == []


def test_undeclared_xacro_prefix_is_declared_in_memory(load) -> None:
    text = (
        '<?xml version="1.0"?>\n<robot name="r">\n'
        '  <xacro:property name="w" value="2"/>\n  <link name="l${w}"/>\n</robot>\n'
    )
    loaded = load(text, "r.urdf.xacro")
    assert loaded.robot.links[0].name == "l2"
    (finding,) = legacy_findings(loaded).values()
    assert "xacro: prefix used without an xmlns:xacro declaration" in finding.message
    assert finding.severity.value == "error"
    assert loaded.document.sources["r.urdf.xacro"] == text  # the user's text, not the patched one


def test_undeclared_other_prefix_is_still_malformed(load) -> None:
    with pytest.raises(InputError, match="GC101 malformed-xml: Namespace prefix gz"):
        load('<robot name="r">\n  <gz:plugin/>\n</robot>\n', "r.urdf.xacro")


def test_users_files_are_not_touched(load, tmp_path: Path) -> None:
    load(LEGACY_ROOT, "base.urdf.xacro", files={"parts.xacro": LEGACY_PARTS})
    assert (tmp_path / "parts.xacro").read_text() == LEGACY_PARTS
    assert (tmp_path / "base.urdf.xacro").read_text() == LEGACY_ROOT


def test_legacy_arg_and_call(load) -> None:
    text = (
        '<?xml version="1.0"?>\n<robot name="r">\n  <arg name="side" default="left"/>\n'
        '  <macro name="m" params="n"><link name="${n}_$(arg side)"/></macro>\n'
        '  <call macro="m" n="a"/>\n</robot>\n'
    )
    loaded = load(text, "r.xacro", args={"side": "right"})
    assert [link.name for link in loaded.robot.links] == ["a_right"]
    (finding,) = legacy_findings(loaded).values()
    assert finding.data["tags"] == {"arg": 1, "call": 1, "macro": 1}


SENSOR_LIBRARY = f"""<?xml version="1.0"?>
<robot {NS}>
  <xacro:macro name="camera" params="parent *origin">
    <joint name="camera_joint" type="fixed">
      <insert_block name="origin"/>
      <parent link="${{parent}}"/><child link="camera_link"/>
    </joint>
    <link name="camera_link"/>
  </xacro:macro>
</robot>
"""


@pytest.mark.parametrize("called", [False, True])
def test_bare_tags_only_in_macros_the_robot_never_calls_are_info(load, called: bool) -> None:
    call = '<xacro:camera parent="base"><origin xyz="0 0 1"/></xacro:camera>' if called else ""
    root = f'<robot name="r" {NS}>\n  <xacro:include filename="sensors.xacro"/>\n  <link name="base"/>\n  {call}\n'
    root += "</robot>\n"
    loaded = load(root, "r.urdf.xacro", files={"sensors.xacro": SENSOR_LIBRARY})
    (finding,) = legacy_findings(loaded).values()
    assert (finding.location.file, finding.location.line) == ("sensors.xacro", 5)
    if called:
        assert finding.severity.value == "warning"
        assert finding.message == "legacy xacro syntax in sensors.xacro: <insert_block> x1"
        assert loaded.robot.joint_map["camera_joint"].origin.xyz == (0.0, 0.0, 1.0)
    else:
        assert finding.severity.value == "info"
        assert finding.message == (
            "legacy xacro syntax in sensors.xacro: <insert_block> x1 (only in macros this robot does not call: camera)"
        )
