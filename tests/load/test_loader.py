"""The one entry point of loading: a root file's declaration read as its format's own tools read it."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.load import load_description, make_bundle

DECLARED = '<?xml version="0.0" ?>\n'
ROBOTS = {
    "robot.urdf": '<robot name="r">\n  <link name="a"/>\n</robot>\n',
    "robot.urdf.xacro": (
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:property name="n" value="a"/>\n  <link name="${n}"/>\n</robot>\n'
    ),
    "robot.xml": (
        '<mujoco model="r">\n  <worldbody>\n    <body name="a"><geom size="0.1"/></body>\n  </worldbody>\n</mujoco>\n'
    ),
    "robot.sdf": '<sdf version="1.7">\n  <model name="r">\n    <link name="a"/>\n  </model>\n</sdf>\n',
}


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_a_root_declaring_xml_version_0_0_loads_with_gc131(tmp_path: Path, name: str) -> None:
    """Old exporters wrote version="0.0" (26 files of PyBullet's data): ROS, Gazebo and MuJoCo
    read them, so geomcheck loads the robot and says that libxml2-based readers do not."""
    root = tmp_path / name
    root.write_text(DECLARED + ROBOTS[name], encoding="utf-8")
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    assert "a" in {link.name for link in loaded.robot.links}
    said = [d for d in loaded.diagnostics if d.code == "GC131"]
    assert [(d.severity.value, d.location.file, d.location.line, d.data["version"]) for d in said] == [
        ("warning", name, 1, "0.0")
    ]
    assert said[0].message.startswith(f'{name} declares XML version "0.0", which XML does not have: ')


def test_a_root_declaring_xml_1_0_gets_no_gc131(tmp_path: Path) -> None:
    root = tmp_path / "robot.urdf"
    root.write_text('<?xml version="1.0" ?>\n' + ROBOTS["robot.urdf"], encoding="utf-8")
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    assert [d.code for d in loaded.diagnostics if d.code.startswith("GC13")] == []
