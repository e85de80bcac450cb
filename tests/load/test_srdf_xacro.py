"""A MoveIt SRDF written as xacro (NAME.srdf.xacro) is expanded like the description before it is read."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from geomcheck.errors import SandboxViolation
from geomcheck.load import load_description, make_bundle
from geomcheck.load.srdf import read_srdf

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'

URDF = """<robot name="arm">
  <link name="arm_base"/><link name="arm_link1"/>
  <joint name="arm_joint1" type="revolute"><parent link="arm_base"/><child link="arm_link1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""

MACRO = f"""<?xml version="1.0"?>
<robot {NS}>
  <xacro:macro name="arm_srdf" params="prefix">
    <disable_collisions link1="${{prefix}}base" link2="${{prefix}}link1" reason="Adjacent"/>
  </xacro:macro>
</robot>
"""

SRDF_XACRO = f"""<?xml version="1.0"?>
<robot name="arm" {NS}>
  <xacro:arg name="prefix" default="" />
  <xacro:include filename="$(find arm_moveit_config)/srdf/macro.srdf.xacro"/>
  <group_state name="home" group="arm">
    <joint name="$(arg prefix)joint1" value="0.5"/>
  </group_state>
  <xacro:arm_srdf prefix="$(arg prefix)"/>
</robot>
"""


@pytest.fixture
def moveit(write: Callable[[str, str], Path]) -> Path:
    """A description package and a MoveIt config package whose SRDF is xacro; the SRDF's path."""
    write("arm_description/package.xml", "<package><name>arm_description</name></package>")
    write("arm_description/urdf/arm.urdf", URDF)
    write("arm_moveit_config/package.xml", "<package><name>arm_moveit_config</name></package>")
    write("arm_moveit_config/srdf/macro.srdf.xacro", MACRO)
    return write("arm_moveit_config/srdf/arm.srdf.xacro", SRDF_XACRO)


def test_srdf_xacro_is_expanded_with_the_description_args(tmp_path: Path, moveit: Path) -> None:
    bundle = make_bundle(tmp_path / "arm_description/urdf/arm.urdf", display_root=tmp_path)
    srdf = read_srdf(moveit, "arm.srdf.xacro", bundle=bundle, args={"prefix": "arm_"})
    assert [(d.link1, d.link2, d.reason) for d in srdf.disabled] == [("arm_base", "arm_link1", "Adjacent")]
    # each entry is located where it was written: the macro's line in the included file
    assert (srdf.disabled[0].location.file, srdf.disabled[0].location.line) == (
        "arm_moveit_config/srdf/macro.srdf.xacro",
        4,
    )
    (state,) = srdf.group_states
    assert state.values == {"arm_joint1": (0.5,)}
    assert (state.location.file, state.location.line) == ("arm_moveit_config/srdf/arm.srdf.xacro", 5)
    robot = load_description(bundle).robot
    named = {name for d in srdf.disabled for name in (d.link1, d.link2)}
    assert named <= set(robot.link_map) and set(state.values) <= set(robot.joint_map)


def test_xacro_is_recognised_by_content_not_only_by_name(write: Callable[[str, str], Path]) -> None:
    text = f'<robot name="r" {NS}>\n  <xacro:property name="p" value="a_"/>\n'
    text += '  <disable_collisions link1="${p}x" link2="${p}y" reason="Never"/>\n</robot>\n'
    srdf = read_srdf(write("config/r.srdf", text))
    assert [(d.link1, d.link2, d.location.line) for d in srdf.disabled] == [("a_x", "a_y", 3)]


def test_plain_srdf_is_read_as_written(write: Callable[[str, str], Path]) -> None:
    text = '<robot name="r">\n  <disable_collisions link1="$(arg p)x" link2="y" reason="Never"/>\n</robot>\n'
    srdf = read_srdf(write("config/r.srdf", text), "r.srdf")
    assert [(d.link1, d.location.file, d.location.line) for d in srdf.disabled] == [("$(arg p)x", "r.srdf", 2)]


def test_srdf_xacro_keeps_the_description_sandbox(
    tmp_path: Path, moveit: Path, write: Callable[[str, str], Path]
) -> None:
    outside = write("elsewhere/secret.xacro", MACRO)
    text = SRDF_XACRO.replace("$(find arm_moveit_config)/srdf/macro.srdf.xacro", str(outside))
    srdf_path = write("upload/arm_moveit_config/srdf/arm.srdf.xacro", text)
    write("upload/arm.urdf", URDF)
    bundle = make_bundle(tmp_path / "upload/arm.urdf", display_root=tmp_path / "upload", confined=True)
    with pytest.raises(SandboxViolation, match="access outside the uploaded bundle refused"):
        read_srdf(srdf_path, bundle=bundle)


def test_corpus_srdf_xacro_names_only_links_and_joints_of_the_robot(corpus: Path) -> None:
    # kinova_gen3 ships its MoveIt SRDF only as .srdf.xacro (names written $(arg prefix)joint_1)
    root = corpus / "kinova_gen3"
    bundle = make_bundle(
        root / "kortex_description/robots/gen3_robotiq_2f_85.xacro",
        packages={"kortex_description": root / "kortex_description"},
        display_root=root,
    )
    robot = load_description(bundle).robot
    path = root / "kortex_move_it_config/gen3_robotiq_2f_85_move_it_config/config/7dof/gen3_robotiq_2f_85.srdf.xacro"
    srdf = read_srdf(path, bundle=bundle)
    named = {name for d in srdf.disabled for name in (d.link1, d.link2)}
    assert len(srdf.disabled) == 128
    assert named <= set(robot.link_map)
    joints = {name for state in srdf.group_states for name in state.values}
    assert "joint_1" in joints and joints <= set(robot.joint_map)
