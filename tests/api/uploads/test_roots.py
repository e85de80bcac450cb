"""The root a person means, by what the files do: the file that makes the robot and pulls
the others in; never a library of macros; the package's own files (launch files, a README, a
model.config, an SRDF) naming it; and no guess when several robots are equally likely."""

from __future__ import annotations

from pathlib import Path

import pytest

from api.errors import UploadError
from api.uploads.layout import choose_root
from api.uploads.roots import choose, evident_root, root_candidates

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def write(folder: Path, rel: str, text: str) -> None:
    path = folder / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


def include(*files: str) -> str:
    return "".join(f'<xacro:include filename="$(find pkg)/urdf/{f}"/>' for f in files)


MACRO = "<robot " + NS + '><xacro:macro name="{name}" params="p"><link name="${{p}}"/></xacro:macro></robot>'


@pytest.fixture
def package(tmp_path: Path) -> Path:
    """A PR2-like package: the whole robot and a caster test file, both in robots/, the
    test file first in the alphabet; macro libraries in urdf/."""
    write(tmp_path, "urdf/common.xacro", f'<robot {NS}><xacro:property name="r" value="1"/></robot>')
    write(tmp_path, "urdf/base.urdf.xacro", f"<robot {NS}>{include('common.xacro')}</robot>")
    for part in ("torso", "arm", "head"):
        write(tmp_path, f"urdf/{part}.urdf.xacro", MACRO.format(name=part))
    caster = f'<robot name="caster" {NS}>{include("base.urdf.xacro")}<xacro:base p="b"/></robot>'
    write(tmp_path, "robots/caster.urdf.xacro", caster)
    whole = include("base.urdf.xacro", "torso.urdf.xacro", "arm.urdf.xacro", "head.urdf.xacro")
    write(tmp_path, "robots/robot.urdf.xacro", f'<robot name="robot" {NS}>{whole}<xacro:torso p="t"/></robot>')
    return tmp_path


def test_the_whole_robot_ranks_before_its_sub_assembly(package: Path) -> None:
    found = root_candidates(package)
    assert [(c.path, c.included, c.pulls_in, c.instantiates, c.dominated) for c in found[:2]] == [
        ("robots/robot.urdf.xacro", False, 5, True, False),
        ("robots/caster.urdf.xacro", False, 2, True, True),
    ]
    assert all(c.included and not c.instantiates for c in found[2:])  # macro and property libraries
    chosen = choose(found)
    assert chosen is not None and chosen.path == "robots/robot.urdf.xacro" and not chosen.given
    assert chosen.reason == "the whole robot: it includes what robots/caster.urdf.xacro includes and more (5 files)"
    assert chosen.alternatives[0] == "robots/caster.urdf.xacro"
    assert evident_root(found) == found[0]


def test_the_service_takes_the_root_it_explains(package: Path) -> None:
    assert choose_root(package, None, 200).path == "robots/robot.urdf.xacro"
    given = choose_root(package, "robots/caster.urdf.xacro", 200)
    assert (given.path, given.given, given.reason) == ("robots/caster.urdf.xacro", True, "named by the request")


def test_a_file_that_only_defines_macros_is_never_the_root(tmp_path: Path) -> None:
    """kinova_gen3's gripper macro file was chosen and answered "the robot declares no links":
    a library is never the root, whatever its name or place, even alone beside a wrapper."""
    write(tmp_path, "grippers/robotiq/urdf/robotiq_macro.xacro", MACRO.format(name="gripper"))
    write(tmp_path, "arms/gen3/urdf/gen3_macro.xacro", MACRO.format(name="arm"))
    robot = '<robot name="gen3" {ns}><xacro:include filename="$(find pkg)/robots/kortex.xacro"/><xacro:load/></robot>'
    write(tmp_path, "robots/gen3.xacro", robot.format(ns=NS))
    loader = (
        f"<robot {NS}><xacro:macro name='load'>"
        '<xacro:include filename="$(find pkg)/arms/${arm}/urdf/${arm}_macro.xacro"/></xacro:macro></robot>'
    )
    write(tmp_path, "robots/kortex.xacro", loader)
    found = root_candidates(tmp_path)
    assert found[0].path == "robots/gen3.xacro"
    assert [c.path for c in found if c.instantiates] == ["robots/gen3.xacro"]
    chosen = choose_root(tmp_path, None, 200)
    assert chosen.path == "robots/gen3.xacro"
    assert chosen.reason == "the only file that makes a robot at its top level; the others define macros or materials"


def test_variants_equally_likely_are_not_guessed(tmp_path: Path) -> None:
    """create_1 and create_2, each with its launch file: the request must say which."""
    write(tmp_path, "urdf/base.urdf.xacro", MACRO.format(name="base"))
    for n in (1, 2):
        write(tmp_path, f"urdf/create_{n}.urdf.xacro", f'<robot name="c{n}" {NS}>{include("base.urdf.xacro")}'
              '<xacro:base p="b"/></robot>')  # fmt: skip
        write(tmp_path, f"launch/create_{n}.launch", f"<launch>$(find pkg)/urdf/create_{n}.urdf.xacro</launch>")
    assert choose(root_candidates(tmp_path)) is None
    with pytest.raises(UploadError, match=r"2 files could each be the robot.*urdf/create_1.urdf.xacro, urdf/create_2"):
        choose_root(tmp_path, None, 200)


def test_what_the_package_says_decides_between_robots(tmp_path: Path) -> None:
    """A README naming one file, an SRDF written for one robot, a model.config's newest
    version: each makes one of otherwise equal robots the root."""
    write(tmp_path, "a/urdf/main.urdf", '<robot name="main"><link name="x"/></robot>')
    write(tmp_path, "a/urdf/other.urdf", '<robot name="other"><link name="x"/></robot>')
    write(tmp_path, "a/README.md", "Load `main.urdf`.")
    chosen = choose_root(tmp_path / "a", None, 200)
    assert (chosen.path, chosen.reason) == (
        "urdf/main.urdf",
        "named by 1 other file of the upload (launch files, documentation, configuration)",
    )
    write(tmp_path, "b/urdf/arm.urdf", '<robot name="arm"><link name="x"/></robot>')
    write(tmp_path, "b/urdf/cart.urdf", '<robot name="cart"><link name="x"/></robot>')
    write(tmp_path, "b/config/moveit.srdf", '<robot name="cart"><group name="g"/></robot>')
    assert choose_root(tmp_path / "b", None, 200).path == "urdf/cart.urdf"
    for version in ("1_3", "1_4"):
        write(tmp_path, f"c/model-{version}.sdf", '<sdf version="1.4"><model name="m"><link name="l"/></model></sdf>')
    write(tmp_path, "c/model.sdf", '<sdf version="1.6"><model name="m"><link name="l"/></model></sdf>')
    config = '<model><sdf version="1.3">model-1_3.sdf</sdf><sdf version="1.6">model.sdf</sdf></model>'
    write(tmp_path, "c/model.config", config)
    assert choose_root(tmp_path / "c", None, 200).path == "model.sdf"


def test_the_source_wins_over_its_generated_urdf(tmp_path: Path) -> None:
    write(tmp_path, "urdf/arm_macro.xacro", MACRO.format(name="arm"))
    write(tmp_path, "urdf/arm.xacro", f'<robot name="kr6" {NS}>{include("arm_macro.xacro")}<xacro:arm p="a"/></robot>')
    write(tmp_path, "urdf/arm.urdf", '<robot name="kr6"><link name="a"/></robot>')
    chosen = choose_root(tmp_path, None, 200)
    assert chosen.path == "urdf/arm.xacro"
    assert chosen.reason == "the source of urdf/arm.urdf, which holds the same robot (kr6) as plain URDF"


def test_includes_chosen_by_arguments_make_parts_and_size_tells_a_robot_from_a_dock(tmp_path: Path) -> None:
    """LoCoBot includes ``arms/$(arg arm_model).urdf.xacro``: every arm file is a part of it;
    beside it a docking station pulls in a tenth of the files."""
    parts = [f"part{i}.xacro" for i in range(6)]
    for part in parts:
        write(tmp_path, f"urdf/{part}", MACRO.format(name=part[:-6]))
    for arm in ("px100", "wx250s"):
        write(tmp_path, f"urdf/arms/mobile_{arm}.urdf.xacro", f'<robot name="{arm}"><link name="l"/></robot>')
    locobot = include(*parts) + '<xacro:include filename="$(find pkg)/urdf/arms/$(arg arm_model).urdf.xacro"/>'
    write(tmp_path, "urdf/locobot.urdf.xacro", f'<robot name="locobot" {NS}>{locobot}<xacro:part0 p="b"/></robot>')
    write(tmp_path, "urdf/dock/dock_macro.xacro", MACRO.format(name="dock"))
    dock = f'<robot name="dock" {NS}><xacro:include filename="dock_macro.xacro"/><xacro:dock p="d"/></robot>'
    write(tmp_path, "urdf/dock/dock.urdf.xacro", dock)
    found = {c.path: c for c in root_candidates(tmp_path)}
    assert found["urdf/arms/mobile_px100.urdf.xacro"].included
    chosen = choose_root(tmp_path, None, 200)
    assert chosen.path == "urdf/locobot.urdf.xacro"
    assert chosen.reason.startswith("the largest robot: it pulls in 8 files, at least 2 times as many as any other")


def test_a_wrapper_choosing_a_variant_is_the_root_and_a_scene_around_a_robot_is_not(tmp_path: Path) -> None:
    """dingo.urdf.xacro includes dingo-d or dingo-o and makes nothing itself: it is the root
    (it picks the variant). A MuJoCo scene includes its one robot and adds a floor and lights:
    the robot is the root, the floor no part of it."""
    variant = '<robot name="dingo" {ns}><link name="base"/></robot>'
    write(tmp_path, "d/urdf/dingo-d.urdf.xacro", variant.format(ns=NS))
    write(tmp_path, "d/urdf/dingo-o.urdf.xacro", variant.format(ns=NS))
    wrapper = (
        f'<robot name="dingo" {NS}><xacro:if value="$(optenv DINGO_OMNI 0)">{include("dingo-o.urdf.xacro")}'
        f'</xacro:if><xacro:unless value="$(optenv DINGO_OMNI 0)">{include("dingo-d.urdf.xacro")}'
        "</xacro:unless></robot>"
    )
    write(tmp_path, "d/urdf/dingo.urdf.xacro", wrapper)
    assert choose_root(tmp_path / "d", None, 200).path == "urdf/dingo.urdf.xacro"
    write(tmp_path, "m/arm.xml", '<mujoco model="arm"><worldbody><body name="b"/></worldbody></mujoco>')
    floor = '<worldbody><geom name="floor" type="plane" size="1 1 0.1"/><light pos="0 0 2"/></worldbody>'
    write(tmp_path, "m/scene.xml", f'<mujoco model="arm scene"><include file="arm.xml"/>{floor}</mujoco>')
    chosen = choose_root(tmp_path / "m", None, 200)
    assert (chosen.path, chosen.alternatives) == ("arm.xml", ("scene.xml",))
    assert chosen.reason == "the robot itself: scene.xml only includes it, and adds no link or body of its own"


def test_legacy_xacro_calls_make_a_robot(tmp_path: Path) -> None:
    """The 2009 PR2 declares the xacro prefix with a Gazebo URI and calls its macros bare."""
    legacy = (
        '<robot name="pr2" xmlns:xacro="http://playerstage.sourceforge.net/gazebo/xmlschema/#interface">'
        '<include filename="$(find pr2)/urdf/base.urdf.xacro"/><pr2_base name="base"/></robot>'
    )
    write(tmp_path, "robots/pr2.urdf.xacro", legacy)
    base = '<robot><macro name="pr2_base" params="name"><link name="${name}_link"/></macro></robot>'
    write(tmp_path, "urdf/base.urdf.xacro", base)
    write(tmp_path, "urdf/materials.urdf.xacro", '<robot><material name="Blue"/></robot>')
    found = root_candidates(tmp_path)
    assert [(c.path, c.instantiates) for c in found] == [
        ("robots/pr2.urdf.xacro", True),
        ("urdf/materials.urdf.xacro", False),
        ("urdf/base.urdf.xacro", False),
    ]


def test_sdformat_and_mjcf_files_are_roots_and_other_xml_is_not(tmp_path: Path) -> None:
    """A Gazebo model path (a model including another by ``model://``) and a MuJoCo scene
    including its robot; package.xml, a launch file and an SRDF are not descriptions."""
    write(tmp_path, "create/model.sdf", '<?xml version="1.0"?><sdf version="1.6"><model name="create"/></sdf>')
    turtle = '<sdf version="1.6"><model name="turtle"><include><uri>model://create</uri></include></model></sdf>'
    write(tmp_path, "turtle/model.sdf", f"<!-- licence -->\n{turtle}")
    write(tmp_path, "mj/arm.xml", '<mujoco model="arm"><worldbody><body name="b"/></worldbody></mujoco>')
    write(tmp_path, "mj/scene.xml", '<mujoco model="arm scene"><include file="arm.xml"/></mujoco>')
    write(tmp_path, "package.xml", "<package><name>turtle</name></package>")
    write(tmp_path, "launch/view.launch.xml", "<launch><node/></launch>")
    write(tmp_path, "config/turtle.srdf", '<robot name="turtle"><group name="g"/></robot>')
    ranked = root_candidates(tmp_path)
    assert [(c.path, c.robot, c.included, c.pulls_in) for c in ranked] == [
        ("turtle/model.sdf", "turtle", False, 1),  # its SRDF names it
        ("mj/arm.xml", "arm", False, 0),
        ("mj/scene.xml", "arm scene", False, 1),  # makes no robot of its own
        ("create/model.sdf", "create", True, 0),
    ]
    assert choose_root(tmp_path / "turtle", None, 255).path == "model.sdf"
