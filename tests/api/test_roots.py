"""The root a person means: the description that pulls the others in, in a robots/ folder;
the service takes it when ``root`` is omitted and it is evident."""

from __future__ import annotations

from pathlib import Path

import pytest

from api.errors import UploadError
from api.layout import choose_root
from api.roots import evident_root, root_candidates

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def write(folder: Path, rel: str, text: str) -> None:
    path = folder / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


def include(*files: str) -> str:
    return "".join(f'<xacro:include filename="$(find pkg)/urdf/{f}"/>' for f in files)


@pytest.fixture
def package(tmp_path: Path) -> Path:
    """A PR2-like package: the whole robot and a caster test file, both in robots/, the
    test file first in the alphabet; parts in urdf/."""
    write(tmp_path, "urdf/common.xacro", f"<robot {NS}/>")
    write(tmp_path, "urdf/base.urdf.xacro", f"<robot {NS}>{include('common.xacro')}</robot>")
    for part in ("torso", "arm", "head"):
        write(tmp_path, f"urdf/{part}.urdf.xacro", f"<robot {NS}>{include('common.xacro')}</robot>")
    write(tmp_path, "robots/caster.urdf.xacro", f'<robot name="caster" {NS}>{include("base.urdf.xacro")}</robot>')
    whole = include("base.urdf.xacro", "torso.urdf.xacro", "arm.urdf.xacro", "head.urdf.xacro")
    write(tmp_path, "robots/robot.urdf.xacro", f'<robot name="robot" {NS}>{whole}</robot>')
    return tmp_path


def test_the_file_that_pulls_in_the_most_ranks_first(package: Path) -> None:
    found = root_candidates(package)
    assert [(c.path, c.included, c.pulls_in) for c in found[:2]] == [
        ("robots/robot.urdf.xacro", False, 5),
        ("robots/caster.urdf.xacro", False, 2),
    ]
    assert all(c.included for c in found[2:])
    assert evident_root(found) == found[0]


def test_the_service_takes_the_evident_root(package: Path) -> None:
    assert choose_root(package, None, 200) == "robots/robot.urdf.xacro"
    assert choose_root(package, "robots/caster.urdf.xacro", 200) == "robots/caster.urdf.xacro"


def test_two_alike_roots_are_not_evident(tmp_path: Path) -> None:
    write(tmp_path, "robots/a.urdf", '<robot name="a"><link name="x"/></robot>')
    write(tmp_path, "robots/b.urdf", '<robot name="b"><link name="x"/></robot>')
    assert evident_root(root_candidates(tmp_path)) is None
    with pytest.raises(UploadError, match=r"likely root first: robots/a.urdf, robots/b.urdf"):
        choose_root(tmp_path, None, 200)


def test_a_robots_folder_wins_among_equals(tmp_path: Path) -> None:
    write(tmp_path, "test/a.urdf", '<robot name="a"/>')
    write(tmp_path, "robots/z.urdf", '<robot name="z"/>')
    assert [c.path for c in root_candidates(tmp_path)] == ["robots/z.urdf", "test/a.urdf"]


def test_sdformat_and_mjcf_files_are_roots_and_other_xml_is_not(tmp_path: Path) -> None:
    """A Gazebo model path (a model including another by ``model://``) and a MuJoCo scene
    including its robot: the including file is the root; package.xml and a launch file are
    not descriptions."""
    write(tmp_path, "create/model.sdf", '<?xml version="1.0"?><sdf version="1.6"><model name="create"/></sdf>')
    turtle = '<sdf version="1.6"><model name="turtle"><include><uri>model://create</uri></include></model></sdf>'
    write(tmp_path, "turtle/model.sdf", f"<!-- licence -->\n{turtle}")
    write(tmp_path, "mj/arm.xml", '<mujoco model="arm"><worldbody/></mujoco>')
    write(tmp_path, "mj/scene.xml", '<mujoco model="arm scene"><include file="arm.xml"/></mujoco>')
    write(tmp_path, "package.xml", "<package><name>turtle</name></package>")
    write(tmp_path, "launch/view.launch.xml", "<launch><node/></launch>")
    ranked = root_candidates(tmp_path)
    assert [(c.path, c.robot, c.included, c.pulls_in) for c in ranked] == [
        ("mj/scene.xml", "arm scene", False, 1),
        ("turtle/model.sdf", "turtle", False, 1),
        ("create/model.sdf", "create", True, 0),
        ("mj/arm.xml", "arm", True, 0),
    ]
    assert evident_root(ranked) is None  # two robots side by side: the user names one
    assert choose_root(tmp_path / "turtle", None, 255) == "model.sdf"
