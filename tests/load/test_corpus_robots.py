"""Every robot of robots.toml loads, link for link and joint for joint as the real xacro
package expands it and yourdfpy parses it; a robot current xacro cannot expand is one in
pre-2013 xacro syntax, and geomcheck says so (GC103)."""

from __future__ import annotations

import contextlib
import io

import pytest
import xacro
import yourdfpy

from geomcheck.load import load_description, make_bundle
from tests.corpustools import ros_packages, script

pytestmark = pytest.mark.corpus
CORPUS = script("corpus_robots").corpus_from_env()
# xacro and yourdfpy read URDF only: MJCF and SDFormat robots are compared with MuJoCo and
# libsdformat's semantics in tests/load/test_mjcf.py and test_sdf.py
ROBOTS = [r for r in script("corpus_robots").checked_robots(CORPUS) if r.format == "urdf"] if CORPUS else []


def reference_names(robot: object) -> tuple[set[str], set[str]]:
    """Link and joint names of ``robot`` expanded by xacro and parsed by yourdfpy."""
    with ros_packages(robot.packages), contextlib.redirect_stderr(io.StringIO()):  # type: ignore[attr-defined]
        text = xacro.process_file(str(robot.root), mappings=dict(robot.args)).toxml()  # type: ignore[attr-defined]
    urdf = yourdfpy.URDF.load(io.StringIO(text), build_scene_graph=False, load_meshes=False)
    return {link.name for link in urdf.robot.links}, {joint.name for joint in urdf.robot.joints}


@pytest.mark.parametrize("robot", ROBOTS, ids=[r.name for r in ROBOTS])
def test_robot_loads_as_xacro_and_yourdfpy_read_it(robot: object) -> None:
    bundle = make_bundle(robot.root, robot.packages, display_root=robot.corpus)  # type: ignore[attr-defined]
    loaded = load_description(bundle, robot.args)  # type: ignore[attr-defined]
    links = {link.name for link in loaded.robot.links}
    joints = {joint.name for joint in loaded.robot.joints}
    assert links, robot
    try:
        expected = reference_names(robot)
    except xacro.XacroException as error:
        # current xacro no longer expands unprefixed macros: the robot needs the xacro of its time
        assert "unknown macro name" in str(error)
        assert any(d.code == "GC103" for d in loaded.diagnostics)
        return
    assert (links, joints) == expected
