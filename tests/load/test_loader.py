"""The one entry point of loading: a root file's declaration read as its format's own tools read it."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.errors import InputError
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


def test_a_urdf_xml_only_as_tinyxml2_reads_it_loads_with_gc132(tmp_path: Path) -> None:
    """PyBullet's biped: blank lines before the declaration; its humanoid: a NUL byte after
    </robot>. TinyXML2 (urdfdom, Gazebo, PyBullet) reads both, libxml2 and expat refuse them."""
    root = tmp_path / "robot.urdf"
    root.write_bytes(b"\n\n\n" + b'<?xml version="1.0"?>\n' + ROBOTS["robot.urdf"].encode() + b"\x00\x00")
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    assert [link.name for link in loaded.robot.links] == ["a"]
    (said,) = [d for d in loaded.diagnostics if d.code == "GC132"]
    assert (said.severity.value, said.location.line, said.data) == (
        "warning",
        1,
        {"file": "robot.urdf", "issues": ["trailing-nul", "late-declaration"]},
    )
    assert said.message.startswith(
        "robot.urdf is XML only as TinyXML2 reads it: NUL bytes follow its last element and its <?xml ...?> "
        "declaration stands after blank lines or a comment"
    )
    assert said.help == (
        "Delete the NUL bytes at the end of the file and put the <?xml ...?> declaration on the first line, or "
        "delete it: every reader then reads it."
    )
    # the robot's own lines stay where they were: link a on line 6
    assert loaded.robot.link_map["a"].location.line == 6


def test_a_nul_byte_amid_the_document_stays_malformed(tmp_path: Path) -> None:
    root = tmp_path / "robot.urdf"
    root.write_bytes(b'<robot name="r">\n  <link name="a"/>\x00\n  <link name="b"/>\n</robot>\n')
    with pytest.raises(InputError, match="GC101"):
        load_description(make_bundle(root, display_root=tmp_path))


def test_an_sdf_read_as_gazebo_reads_it_gets_no_gc132(tmp_path: Path) -> None:
    """Gazebo, an SDFormat file's one reader, reads a declaration after a licence comment."""
    root = tmp_path / "model.sdf"
    root.write_text('<!-- licence -->\n<?xml version="1.0"?>\n' + ROBOTS["robot.sdf"], encoding="utf-8")
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    assert [link.name for link in loaded.robot.links] == ["a"]
    assert [d.code for d in loaded.diagnostics if d.code.startswith("GC13")] == []


WORLD = '<sdf version="1.7">\n  <world name="default">\n{inside}  </world>\n</sdf>\n'
MODEL = '    <model name="{name}">\n      <link name="{name}_base"/>\n    </model>\n'


def test_a_world_around_one_robot_is_that_robot(tmp_path: Path) -> None:
    """PyBullet's kuka_with_gripper2.sdf: a <world> holding one model and nothing else."""
    root = tmp_path / "world.sdf"
    root.write_text(WORLD.format(inside=MODEL.format(name="arm")), encoding="utf-8")
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    assert (loaded.robot.name, [link.name for link in loaded.robot.links]) == ("arm", ["arm_base"])


@pytest.mark.parametrize(
    "inside",
    [
        MODEL.format(name="arm") + MODEL.format(name="table"),
        MODEL.format(name="arm") + "    <include><uri>model://ground_plane</uri></include>\n",
    ],
    ids=["two models", "a model and an include"],
)
def test_a_world_of_several_models_is_refused(tmp_path: Path, inside: str) -> None:
    root = tmp_path / "world.sdf"
    root.write_text(WORLD.format(inside=inside), encoding="utf-8")
    with pytest.raises(InputError, match=r"the <sdf> holds a <world>; geomcheck checks one robot"):
        load_description(make_bundle(root, display_root=tmp_path))
