"""SDFormat loading: frame semantics (relative_to, default frames, expressed_in, placement),
nested and included models, joints, refusals and self-collision."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.errors import InputError
from geomcheck.load import load_description, make_bundle
from geomcheck.load.formats import detect, formats
from geomcheck.load.meshes import LoadedMesh, MeshStore
from geomcheck.load.xmlsafe import parse_bytes
from geomcheck.model import Capsule, Cylinder, Mesh, Sphere
from tests.load.sdftools import ARM, TOL, assert_pose, load, rx, rz, world, write


def test_sdf_is_recognised_by_its_root_element() -> None:
    assert [f.name for f in formats()][:3] == ["urdf", "mjcf", "sdf"]
    assert detect(parse_bytes(b"<sdf version='1.6'/>", "m.xml"), "m.xml").name == "sdf"
    assert detect(parse_bytes(b"<robot name='r'/>", "m.sdf"), "m.sdf").name == "urdf"
    assert detect(None, "model.sdf").name == "sdf"  # unparsed: by suffix


def test_links_joints_and_names_of_nested_models(tmp_path: Path) -> None:
    loaded = load(tmp_path, ARM)
    robot = loaded.robot
    assert loaded.format == "sdf" and robot.name == "arm"
    assert [link.name for link in robot.links] == ["base", "upper", "hand::palm", "hand::finger", "upper::shoulder"]
    assert [link.synthetic for link in robot.links] == [False, False, False, False, True]
    assert [(j.name, j.type, j.parent, j.child) for j in robot.joints] == [
        ("shoulder", "revolute", "base", "upper::shoulder"),
        ("upper_anchor", "fixed", "upper::shoulder", "upper"),
        ("wrist", "fixed", "upper", "hand::palm"),
        ("hand::slide", "prismatic", "hand::palm", "hand::finger"),
    ]
    assert robot.link_map["upper"].location is not None and robot.link_map["upper"].location.line == 16


def test_poses_follow_relative_to_frames_degrees_and_nested_models(tmp_path: Path) -> None:
    robot = load(tmp_path, ARM).robot
    frames = world(robot)
    # the root link is the origin (the model's own pose places it in a world geomcheck has no use for)
    assert_pose(frames["base"], (0, 0, 0), np.eye(3))
    # upper: 0.2 above the frame 'mount', itself 0.1 above base and turned 90 degrees about z
    assert_pose(frames["upper"], (0, 0, 0.3), rz(math.pi / 2))
    # the nested model 'hand' is 0.4 above upper; its link finger 0.05 along the model's x (world y)
    assert_pose(frames["hand::palm"], (0, 0, 0.7), rz(math.pi / 2))
    assert_pose(frames["hand::finger"], (0, 0.05, 0.7), rz(math.pi / 2))
    # the joint frame: 0.1 below its child link, where the intermediate link is
    assert_pose(frames["upper::shoulder"], (0, 0, 0.2), rz(math.pi / 2))

    upper = robot.link_map["upper"]
    (cylinder,) = upper.collisions
    assert cylinder.geometry == Cylinder(0.03, 0.4) and cylinder.name == "upper_cyl"
    # written relative to the model frame: world pose (0, 0, 0.5) unturned whatever the link's pose
    assert_pose(frames["upper"] @ cylinder.origin.matrix(), (0, 0, 0.5), np.eye(3))
    (capsule,) = upper.visuals  # the plane is no robot part
    # a capsule, named as such, measured as the cylinder that encloses it
    assert capsule.geometry == Capsule(0.02, pytest.approx(0.34)) and capsule.geometry.straight_length == pytest.approx(
        0.3
    )
    assert_pose(frames["upper"] @ capsule.origin.matrix(), (0, 0, 0.3), rz(math.pi / 2) @ rx(math.pi / 2))
    assert robot.link_map["hand::palm"].collisions[0].geometry == Sphere(0.05)
    assert robot.link_map["hand::finger"].collisions[0].geometry == Cylinder(0.01, pytest.approx(0.06), ellipsoid=True)


def test_joint_axes_limits_and_motion_about_the_joint_frame(tmp_path: Path) -> None:
    robot = load(tmp_path, ARM).robot
    shoulder = robot.joint_map["shoulder"]
    # (0, 2, 0) in the model frame, normalised, into the joint frame turned 90 degrees about z
    np.testing.assert_allclose(shoulder.axis, (1, 0, 0), atol=TOL)
    assert shoulder.limit is not None
    assert (shoulder.limit.lower, shoulder.limit.upper, shoulder.limit.effort, shoulder.limit.velocity) == (
        -1,
        1,
        5,
        None,
    )
    slide = robot.joint_map["hand::slide"]
    assert slide.axis == pytest.approx((1, 0, 0)) and slide.limit is not None and slide.limit.unlimited
    # turning the shoulder swings upper about the world y axis through the joint frame at z = 0.2
    angle = 0.3
    frames = world(robot, {"shoulder": angle, "hand::slide": 0.02})
    assert_pose(
        frames["upper"], (0.1 * math.sin(angle), 0, 0.2 + 0.1 * math.cos(angle)), rot_y(angle) @ rz(math.pi / 2)
    )
    # the finger slides along its own x axis (world y at zero)
    moved = frames["hand::finger"][:3, 3] - frames["hand::palm"][:3, 3]
    np.testing.assert_allclose(moved, frames["hand::palm"][:3, :3] @ np.array([0.07, 0.0, 0.0]), atol=TOL)


def rot_y(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def test_inertial_in_the_link_frame_and_absent_inertials(tmp_path: Path) -> None:
    robot = load(tmp_path, ARM).robot
    inertial = robot.link_map["base"].inertial
    assert inertial is not None
    assert inertial.mass == 2.0 and inertial.origin.xyz == pytest.approx((0, 0, 0.05))
    assert (inertial.ixx, inertial.iyy, inertial.izz, inertial.ixy, inertial.ixz, inertial.iyz) == (
        0.1,
        0.2,
        0.3,
        0.01,
        0,
        0,
    )
    assert robot.link_map["upper"].inertial is None  # libsdformat's 1 kg default is no author's value


LEGACY = """<sdf version="{version}">
  <model name="legacy">
    <link name="base"/>
    <link name="wheel"><pose>0 0.2 0 0 0 1.5707963267948966</pose></link>
    <joint name="spin" type="revolute">
      <parent>base</parent><child>wheel</child>
      <axis><xyz>1 0 0</xyz>{flag}</axis>
    </joint>
  </model>
</sdf>"""


@pytest.mark.parametrize(
    ("version", "flag", "axis"),
    [
        ("1.6", "", (1, 0, 0)),  # the joint frame, the wheel's
        ("1.6", "<use_parent_model_frame>true</use_parent_model_frame>", (0, -1, 0)),  # the model frame
        ("1.5", "<use_parent_model_frame>0</use_parent_model_frame>", (1, 0, 0)),
        ("1.4", "", (0, -1, 0)),  # 1.4 always meant the model frame
    ],
)
def test_legacy_axis_frames(tmp_path: Path, version: str, flag: str, axis: tuple[float, ...]) -> None:
    robot = load(tmp_path, LEGACY.format(version=version, flag=flag)).robot
    (spin,) = robot.joints
    np.testing.assert_allclose(spin.axis, axis, atol=TOL)
    assert spin.limit is not None and spin.limit.unlimited and spin.limit.lower is None  # no <limit>: open


def test_joint_to_the_world_and_two_axis_and_ball_joints(tmp_path: Path) -> None:
    text = """<sdf version="1.8"><model name="m">
      <pose>0 0 1 0 0 0</pose>
      <link name="a"/>
      <link name="b"><pose>0.3 0 0 0 0 0</pose></link>
      <link name="c"><pose>0.6 0 0 0 0 0</pose></link>
      <joint name="anchor" type="fixed"><parent>world</parent><child>a</child></joint>
      <joint name="u" type="universal"><parent>a</parent><child>b</child>
        <axis><xyz>0 0 1</xyz><limit><lower>-0.5</lower><upper>0.5</upper></limit></axis>
        <axis2><xyz>0 1 0</xyz></axis2></joint>
      <joint name="ball" type="ball"><parent>b</parent><child>c</child></joint>
    </model></sdf>"""
    robot = load(tmp_path, text).robot
    # the world and the frames of the universal joint's two axes are the loader's, not the file's
    assert [(link.name, link.authored) for link in robot.links] == [
        ("world", False),
        ("a", True),
        ("b", True),
        ("c", True),
        ("b::u", False),
        ("b::u::axis2", False),
    ]
    assert [(j.name, j.type, j.parent, j.child, j.axis, j.synthetic, j.author) for j in robot.joints] == [
        ("anchor", "fixed", "world", "a", (1.0, 0.0, 0.0), False, None),
        ("u", "revolute", "a", "b::u", (0.0, 0.0, 1.0), False, None),
        ("u::axis2", "revolute", "b::u", "b::u::axis2", (0.0, 1.0, 0.0), True, "u"),
        ("b_anchor", "fixed", "b::u::axis2", "b", (1.0, 0.0, 0.0), True, "u"),
        ("ball", "ball", "b", "c", (1.0, 0.0, 0.0), False, None),  # held at its reference, as written
    ]
    assert robot.joint_map["u"].written_type == "universal"
    assert [j.name for j in robot.authored_joints] == ["anchor", "u", "ball"]
    frames = world(robot, {"u": 0.5})
    assert_pose(frames["a"], (0, 0, 1), np.eye(3))  # the model's pose places it in the world
    assert_pose(frames["c"], (0.3 + 0.3 * math.cos(0.5), 0.3 * math.sin(0.5), 1), rz(0.5))


def test_quaternion_pose_and_placement_frame(tmp_path: Path) -> None:
    half = math.sqrt(0.5)
    text = f"""<sdf version="1.9"><model name="m">
      <link name="base"/>
      <frame name="flange" attached_to="base"><pose>0 0 0.5 0 0 0</pose></frame>
      <model name="tool" placement_frame="tip">
        <pose rotation_format="quat_xyzw">0 0 1 0 0 {half} {half}</pose>
        <link name="body"/>
        <frame name="tip" attached_to="body"><pose>0 0 0.2 0 0 0</pose></frame>
      </model>
      <joint name="j" type="fixed"><parent>flange</parent><child>tool::tip</child></joint>
      <joint name="s" type="screw"><parent>base</parent><child>tool</child></joint>
    </model></sdf>"""
    robot = load(tmp_path, text).robot
    # a joint may name frames (SDFormat 1.8): the links they are attached to are its ends
    assert [(j.name, j.type, j.parent, j.child) for j in robot.joints] == [
        ("j", "fixed", "base", "tool::body"),
        ("s", "screw", "base", "tool::body"),  # SDFormat's type, held at its reference
    ]
    frames = world(robot)
    # the pose places the frame 'tip' at (0, 0, 1) turned 90 degrees about z: the body is 0.2 below it
    assert_pose(frames["tool::body"], (0, 0, 0.8), rz(math.pi / 2))


def mesh_models(tmp_path: Path, path_name: str = "models") -> Path:
    """A model path holding model 'widget' (a box mesh written twice: model:// and relative)."""
    models = tmp_path / path_name
    meshes = models / "widget" / "meshes"
    meshes.mkdir(parents=True)
    trimesh.creation.box((0.1, 0.2, 0.3)).export(meshes / "box.stl")
    write(
        models / "widget" / "model.config",
        "<?xml version='1.0'?><model><name>widget</name><sdf version='1.5'>old.sdf</sdf>"
        "<sdf version='1.6'>widget.sdf</sdf></model>",
    )
    write(
        models / "widget" / "widget.sdf",
        """<sdf version="1.6"><model name="widget">
          <pose>0 0 0.5 0 0 0</pose>
          <link name="body">
            <visual name="v"><geometry>
              <mesh><uri>model://widget/meshes/box.stl</uri><scale>2 2 2</scale></mesh>
            </geometry></visual>
            <collision name="c"><geometry><mesh><uri>meshes/box.stl</uri></mesh></geometry></collision>
          </link></model></sdf>""",
    )
    return models


ROBOT_WITH_WIDGETS = """<sdf version="1.6"><model name="cart">
  <link name="base"/>
  <include><uri>model://widget</uri><name>left</name><pose>0 0.3 0 0 0 0</pose></include>
  <include><uri>model://widget</uri><name>right</name></include>
  <joint name="left_mount" type="fixed"><parent>base</parent><child>left::body</child></joint>
  <joint name="right_mount" type="fixed"><parent>base</parent><child>right::body</child></joint>
</model></sdf>"""


@pytest.mark.parametrize("how", ["package", "search", "path named like the model"])
def test_includes_through_the_model_path_and_mesh_uris(tmp_path: Path, how: str) -> None:
    # a model path may be called like a model in it (Gazebo's layout widget/widget/model.sdf): the
    # model is the folder in it, not the search folder itself that a ROS package search would take
    models = mesh_models(tmp_path, "widget" if how == "path named like the model" else "models")
    where: dict[str, object] = {"packages": {"widget": models / "widget"}} if how == "package" else {"search": [models]}
    loaded = load(tmp_path, ROBOT_WITH_WIDGETS, "cart/model.sdf", **where)
    robot = loaded.robot
    assert [link.name for link in robot.links] == ["base", "left::body", "right::body"]
    frames = world(robot)
    assert_pose(frames["left::body"], (0, 0.3, 0), np.eye(3))  # the include's pose wins over the model's
    assert_pose(frames["right::body"], (0, 0, 0.5), np.eye(3))  # without one, the model's own pose
    body = robot.link_map["left::body"]
    relative = f"{models.name}/widget/meshes/box.stl"
    written = "package://widget/meshes/box.stl" if how != "path named like the model" else f"../{relative}"
    assert body.visuals[0].geometry == Mesh(written, (2.0, 2.0, 2.0))
    assert body.collisions[0].geometry == Mesh(f"../{relative}")  # relative to its own file
    assert body.collisions[0].location is not None
    assert body.collisions[0].location.file == f"{models.name}/widget/widget.sdf"
    assert f"{models.name}/widget/widget.sdf" in loaded.document.sources
    store = MeshStore(loaded.bundle)
    for shape in (*body.visuals, *body.collisions):
        assert isinstance(shape.geometry, Mesh)
        path = store.resolve(shape.geometry.filename)
        assert isinstance(path, Path) and path.resolve() == (models / "widget" / "meshes" / "box.stl").resolve()
        result = store.get(shape.geometry)
        assert isinstance(result, LoadedMesh)
        extent = result.vertices.max(axis=0) - result.vertices.min(axis=0)
        np.testing.assert_allclose(extent, np.array([0.1, 0.2, 0.3]) * shape.geometry.scale[0], atol=1e-9)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            '<sdf version="1.9"><model name="m"><include merge="true"><uri>model://x</uri></include></model></sdf>',
            r'merge="true"> is not supported',
        ),
        (
            '<sdf version="1.6"><model name="m"><link name="a"><pose frame="b">0 0 0 0 0 0</pose></link></model></sdf>',
            "no meaning",
        ),
        (
            '<sdf version="1.7"><model name="m"><include><uri>model://nowhere</uri></include></model></sdf>',
            "not on the model path",
        ),
        ('<sdf version="1.7"><world name="w"/></sdf>', r"holds a <world>"),
        (
            '<sdf version="1.7"><model name="m"><link name="a"><pose relative_to="b"/></link>'
            '<link name="b"><pose relative_to="a"/></link></model></sdf>',
            r"PoseRelativeToGraph cycle detected, already visited vertex \[m::[ab]\]",
        ),
        (
            '<sdf version="1.7"><model name="m"><link name="a"><pose relative_to="nope"/></link></model></sdf>',
            r"relative_to name\[nope\] specified by link with name\[a\] does not match",
        ),
        (
            '<sdf version="1.7"><model name="m"><link name="a"><pose>0 0 x 0 0 0</pose></link></model></sdf>',
            "not a list of numbers",
        ),
    ],
)
def test_what_is_not_supported_is_refused_with_its_place(tmp_path: Path, text: str, message: str) -> None:
    with pytest.raises(InputError, match=message) as caught:
        load(tmp_path, text)
    assert str(caught.value).startswith("model.sdf:")


def test_declaration_after_a_comment_is_read_as_tinyxml2_reads_it(tmp_path: Path) -> None:
    """Gazebo and urdfdom (TinyXML2) read a declaration after a licence comment; a URDF read so
    gets GC132 (xacro and libxml2-based readers refuse it), an SDFormat file, which only
    Gazebo's parser reads, none."""
    comment = "<!-- licence\n  text -->\n"
    sdf = comment + '<?xml version="1.0"?>\n<sdf version="1.5"><model name="m">\n<link name="a"/></model></sdf>'
    loaded = load(tmp_path, sdf)
    assert loaded.robot.link_map["a"].location is not None and loaded.robot.link_map["a"].location.line == 5
    assert [d.code for d in loaded.diagnostics if d.code == "GC132"] == []
    urdf = comment + '<?xml version="1.0"?>\n<robot name="r"><link name="a"/></robot>'
    loaded = load(tmp_path, urdf, "robot.urdf")
    assert [(d.code, d.data["issues"]) for d in loaded.diagnostics if d.code == "GC132"] == [
        ("GC132", ["late-declaration"])
    ]


def test_world_is_reserved_a_parent_but_never_a_child(tmp_path: Path) -> None:
    """libsdformat refuses a link named world (whatever the file's version: it reads every file
    as the latest) and a joint whose child is the world; the world as a parent is the world
    frame, a link the loader adds and no format counts."""
    text = """<sdf version="1.6"><model name="m">
      <link name="world"><pose>0 0 1 0 0 0</pose></link>
      <link name="a"/>
      <joint name="j" type="fixed"><parent>world</parent><child>a</child></joint>
    </model></sdf>"""
    with pytest.raises(InputError, match=r"model.sdf:2: The supplied link name \[world\] is reserved"):
        load(tmp_path, text)
    hanging = """<sdf version="1.6"><model name="m"><pose>0 0 2 0 0 0</pose><link name="a"/>
      <joint name="j" type="fixed"><parent>a</parent><child>world</child></joint></model></sdf>"""
    with pytest.raises(InputError, match=r"Joint with name\[j\] specified invalid child link \[world\]"):
        load(tmp_path, hanging, "hanging.sdf")
    fixed = """<sdf version="1.6"><model name="m"><pose>0 0 2 0 0 0</pose><link name="a"/>
      <joint name="j" type="fixed"><parent>world</parent><child>a</child></joint></model></sdf>"""
    robot = load(tmp_path, fixed, "fixed.sdf").robot
    assert [(link.name, link.world, link.authored) for link in robot.links] == [
        ("world", True, False),
        ("a", False, True),
    ]
    assert robot.joints[0].origin.xyz == pytest.approx((0, 0, 2))  # the model's pose above the world


def test_confined_bundle_refuses_includes_and_models_outside(tmp_path: Path) -> None:
    from geomcheck.errors import SandboxViolation

    models = mesh_models(tmp_path)
    root = write(tmp_path / "robot" / "model.sdf", ROBOT_WITH_WIDGETS.replace("model://widget", "../models/widget"))
    with pytest.raises(SandboxViolation, match="models/widget"):
        load_description(make_bundle(root, display_root=tmp_path / "robot", confined=True))
    # a model path outside the sandbox is no model path: the include names what to pass
    text = ROBOT_WITH_WIDGETS
    root = write(tmp_path / "robot" / "model.sdf", text)
    with pytest.raises(InputError, match="model 'widget' is not on the model path"):
        load_description(make_bundle(root, search=[models], display_root=tmp_path / "robot", confined=True))
    assert len(load_description(make_bundle(root, search=[models], display_root=tmp_path)).robot.links) == 3


def test_an_axis_without_xyz_is_sdformats_z(tmp_path: Path) -> None:
    text = """<sdf version="1.7"><model name="m"><link name="a"/><link name="b"/><link name="c"/>
      <joint name="no_xyz" type="revolute"><parent>a</parent><child>b</child><axis><limit/></axis></joint>
      <joint name="no_axis" type="continuous"><parent>b</parent><child>c</child></joint>
    </model></sdf>"""
    robot = load(tmp_path, text).robot
    assert [j.axis for j in robot.joints] == [(0.0, 0.0, 1.0), (0.0, 0.0, 1.0)]
    assert [j.limit for j in robot.joints][1] is None  # a continuous joint has no bounds


def test_joints_between_included_models_use_scoped_names_and_a_backwards_joint_is_one_gc117(tmp_path: Path) -> None:
    # the layout of Gazebo's turtlebot: a rack link, an included base model and an included
    # sensor model, joined by joints naming model::link; the sensor's joint is written
    # parent=sensor child=rack (the rack already hangs from the base)
    from geomcheck.checks.structure import check_robot

    models = tmp_path / "models"
    for name, link in (("base", "body"), ("sensor", "link")):
        write(
            models / name / "model.sdf",
            f'<sdf version="1.5"><model name="{name}"><link name="{link}"/></model></sdf>',
        )
    text = """<sdf version="1.5"><model name="bot">
      <link name="rack"/>
      <include><uri>model://base</uri></include>
      <include><uri>model://sensor</uri><pose>0 0 0.3 0 0 0</pose></include>
      <joint name="base_rack" type="fixed"><parent>base::body</parent><child>rack</child></joint>
      <joint name="sensor_rack" type="fixed"><parent>sensor::link</parent><child>rack</child></joint>
    </model></sdf>"""
    robot = load(tmp_path, text, "bot/model.sdf", search=[models]).robot
    assert [link.name for link in robot.links] == ["rack", "base::body", "sensor::link"]
    assert [(j.parent, j.child) for j in robot.joints] == [("base::body", "rack"), ("sensor::link", "rack")]
    found = [(d.code, d.link, d.data.get("reversed")) for d in check_robot(robot)]
    assert found == [("GC117", "rack", ["sensor_rack"])]


def test_sdformat_semantics_in_the_structure_checks_and_counts(tmp_path: Path) -> None:
    """Free links and nested models are SDFormat's free bodies (info, valid); a link two joints
    hold is valid SDFormat that Gazebo's physics refuses (error, accepted_by): every finding
    names the file's joints, never an anchor the loader made, and the counts are SDFormat's."""
    import geomcheck

    text = """<sdf version="1.7"><model name="m">
      <link name="base"/>
      <link name="arm"><pose>0 0 1 0 0 0</pose></link>
      <joint name="j1" type="revolute"><pose>0 0 0.1 0 0 0</pose><parent>base</parent><child>arm</child>
        <axis><xyz>0 0 1</xyz></axis></joint>
      <joint name="j2" type="screw"><pose>0 0 0.2 0 0 0</pose><parent>base</parent><child>arm</child>
        <axis><xyz>0 0 1</xyz></axis></joint>
      <joint name="g" type="gearbox"><parent>base</parent><child>arm</child><axis><xyz>0 0 1</xyz></axis></joint>
      <model name="crate"><link name="box"/></model>
    </model></sdf>"""
    root = write(tmp_path / "model.sdf", text)
    report = geomcheck.check(root, select=["GC1"], use_config=False)
    assert (report.robot.links, report.robot.joints) == (3, 3)  # base, arm, crate::box; j1, j2, g
    found = [(d.code, d.severity.value, d.link, d.data.get("accepted_by")) for d in report.diagnostics]
    assert found == [("GC117", "error", "arm", "libsdformat"), ("GC115", "info", "crate::box", "libsdformat")]
    gc117 = report.diagnostics[0]
    assert gc117.data["joints"] == ["j1", "j2", "g"] and "gz-physics (dartsim) refuses" in gc117.message
    assert "free body" in report.diagnostics[1].message
    robot = load(tmp_path, text).robot
    anchors = [j.name for j in robot.joints if j.synthetic]
    assert anchors == ["arm_anchor"]  # j1's frame is off arm's origin; the screw joint is held at its reference
    assert [j["type"] for j in report.sections["model"]["joints"]] == ["revolute", "screw", "gearbox"]


def test_links_collide_in_gazebo_only_where_self_collide_says(tmp_path: Path) -> None:
    """Gazebo collides two links of a model when either self-collides (a link's <self_collide>,
    else its model's) and they are not joined by a joint: the other pairs are the description's
    own collision filter, read as an SRDF's disabled pairs."""
    shape = "<collision name='c'><geometry><sphere><radius>0.1</radius></sphere></geometry></collision>"
    text = f"""<sdf version="1.7"><model name="m">
      <link name="a">{shape}</link>
      <link name="b"><pose>1 0 0 0 0 0</pose><self_collide>true</self_collide>{shape}</link>
      <link name="c"><pose>2 0 0 0 0 0</pose>{shape}</link>
      <link name="d"><pose>3 0 0 0 0 0</pose>{shape}</link>
      <joint name="ab" type="fixed"><parent>a</parent><child>b</child></joint>
      <joint name="ac" type="fixed"><parent>a</parent><child>c</child></joint>
      <joint name="cd" type="fixed"><parent>c</parent><child>d</child></joint>
    </model></sdf>"""
    declared = load(tmp_path, text).declared_collision_filter
    assert declared is not None
    assert [(d.link1, d.link2, d.reason) for d in declared.disabled] == [
        ("a", "b", "Adjacent"),
        ("a", "c", "Adjacent"),
        ("a", "d", "self_collide"),
        ("c", "d", "Adjacent"),
    ]  # b self-collides: b/c and b/d stay pairs
    colliding = text.replace('<model name="m">', '<model name="m"><self_collide>true</self_collide>')
    declared = load(tmp_path, colliding, "colliding.sdf").declared_collision_filter
    assert declared is not None and {d.reason for d in declared.disabled} == {"Adjacent"}
