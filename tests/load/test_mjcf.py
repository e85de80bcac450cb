"""MJCF loading: format recognition, MuJoCo's compiler as the authority, mapping onto the model."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
import trimesh

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.load import load_description, make_bundle
from geomcheck.load.formats import detect, formats
from geomcheck.load.meshes import MeshStore
from geomcheck.load.xmlsafe import parse_bytes
from geomcheck.model import Box, Capsule, Cylinder, Mesh, Sphere

mujoco = pytest.importorskip("mujoco")

ARM = """<mujoco model="arm">
  <compiler angle="degree"/>
  <default>
    <default class="link">
      <joint axis="0 1 0" range="-90 45"/>
      <geom type="capsule" size="0.02"/>
    </default>
    <default class="visual">
      <geom contype="0" conaffinity="0" group="2"/>
    </default>
  </default>
  <worldbody>
    <body name="base">
      <geom name="base_box" type="box" size="0.1 0.1 0.05"/>
      <body name="upper" pos="0 0 0.05" childclass="link">
        <joint name="shoulder"/>
        <geom name="upper_capsule" fromto="0 0 0 0 0 0.3"/>
        <geom name="upper_visual" class="visual" type="sphere" size="0.05"/>
        <body name="lower" pos="0 0 0.3">
          <joint name="elbow" range="-10 10" pos="0 0 0.01"/>
          <joint name="twist" type="slide" axis="0 0 1" range="0 0.1"/>
          <geom name="lower_capsule" fromto="0 0 0 0.2 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
  <contact>
    <exclude body1="base" body2="lower"/>
  </contact>
</mujoco>
"""


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def test_formats_are_recognised_by_root_element_not_suffix() -> None:
    names = [f.name for f in formats()]
    assert names[:2] == ["urdf", "mjcf"]
    assert detect(parse_bytes(b"<mujoco/>", "a.xml"), "a.xml").name == "mjcf"
    assert detect(parse_bytes(b"<robot name='r'/>", "a.xml"), "a.xml").name == "urdf"
    assert detect(parse_bytes(b"<mujoco/>", "robot.urdf"), "robot.urdf").name == "mjcf"
    assert detect(None, "robot.urdf.xacro").name == "urdf"  # unparsed (undeclared xacro prefix): by suffix
    assert detect(parse_bytes(b"<sdf/>", "m.sdf"), "m.sdf").name == "sdf"


def test_defaults_fromto_degrees_and_joints(tmp_path: Path) -> None:
    loaded = load_description(make_bundle(write(tmp_path / "arm.xml", ARM), display_root=tmp_path))
    robot = loaded.robot
    assert loaded.format == "mjcf"
    assert [link.name for link in robot.links] == ["world", "base", "upper", "lower", "lower::elbow"]
    assert [link.synthetic for link in robot.links] == [False, False, False, False, True]
    upper = robot.link_map["upper"]
    # fromto capsule of radius 0.02 over 0.3 m: the enclosing cylinder, 0.34 m long, centred at z 0.15
    (capsule,) = upper.collisions
    assert capsule.geometry == Capsule(0.02, pytest.approx(0.34))  # named a capsule, measured as its enclosing cylinder
    assert capsule.origin.xyz == pytest.approx((0.0, 0.0, 0.15))
    assert capsule.name == "upper_capsule"
    assert capsule.location is not None and (capsule.location.file, capsule.location.line) == ("arm.xml", 17)
    # the visual class: contype 0 / conaffinity 0 makes a visual element
    (visual,) = upper.visuals
    assert visual.geometry == Sphere(0.05)
    (lower_capsule,) = robot.link_map["lower"].collisions
    assert lower_capsule.origin.xyz == pytest.approx((0.1, 0.0, 0.0))
    assert np.allclose(np.abs(lower_capsule.origin.rotation()[:, 2]), (1.0, 0.0, 0.0))  # the cylinder axis along x
    assert robot.link_map["base"].collisions[0].geometry == Box((0.2, 0.2, 0.1))
    joints = robot.joint_map
    assert joints["base_fixed"].type == "fixed" and joints["base_fixed"].parent == "world"
    shoulder = joints["shoulder"]
    assert (shoulder.type, shoulder.parent, shoulder.child, shoulder.axis) == ("revolute", "base", "upper", (0, 1, 0))
    assert shoulder.limit is not None
    assert (shoulder.limit.lower, shoulder.limit.upper) == pytest.approx((-math.pi / 2, math.pi / 4))  # degrees read
    assert shoulder.origin.xyz == pytest.approx((0.0, 0.0, 0.05))
    # a body with two joints: a frame for the hinge, which turns about its anchor 0.01 m up the body
    elbow, twist = joints["elbow"], joints["twist"]
    assert (elbow.parent, elbow.child, twist.parent, twist.child) == ("upper", "lower::elbow", "lower::elbow", "lower")
    assert elbow.origin.xyz == pytest.approx((0.0, 0.0, 0.31))
    assert twist.origin.xyz == pytest.approx((0.0, 0.0, -0.01))
    assert twist.limit is not None
    assert (twist.type, twist.limit.lower, twist.limit.upper) == ("prismatic", 0.0, pytest.approx(0.1))
    assert "lower_anchor" not in joints  # the last joint is at the body origin: no fixed joint after it
    # inertia MuJoCo inferred from the geoms (no <inertial>): said so, mass from the capsule's volume
    inertial = robot.link_map["upper"].inertial
    assert inertial is not None and inertial.from_geometry
    volume = math.pi * 0.02**2 * 0.3 + 4 / 3 * math.pi * 0.02**3 + 4 / 3 * math.pi * 0.05**3  # + the visual sphere
    assert inertial.mass == pytest.approx(1000.0 * volume, rel=1e-6)
    # MuJoCo's collision filter: the <exclude>, and the parent/child pair MuJoCo never collides;
    # base is welded to the world, and MuJoCo does collide a world-welded body with its child
    declared = loaded.declared_collision_filter
    assert declared is not None
    assert sorted((d.link1, d.link2, d.reason) for d in declared.disabled) == [
        ("base", "lower", "exclude"),
        ("upper", "lower", "Adjacent"),
    ]


def test_explicit_inertial_and_unlimited_hinge(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo warns of this model's mass matrix: no MUJOCO_LOG.TXT may appear
    text = """<mujoco><worldbody><body name="wheel">
      <freejoint name="float"/>
      <body name="rim"><joint name="spin" axis="0 0 1"/><joint name="tilt" ref="30" range="10 90"/>
        <inertial pos="0 0 0.1" mass="2" diaginertia="0.1 0.2 0.3"/>
        <geom type="cylinder" size="0.1 0.02"/></body>
      <geom type="sphere" size="0.01"/></body></worldbody></mujoco>"""
    robot = load_description(make_bundle(write(tmp_path / "w.xml", text), display_root=tmp_path)).robot
    tilt = robot.joint_map["tilt"]  # limits counted from the reference pose, the body's written pose
    assert tilt.limit is not None
    assert (tilt.limit.lower, tilt.limit.upper) == pytest.approx((math.radians(-20), math.radians(60)))
    assert robot.joint_map["float"].type == "floating"
    spin = robot.joint_map["spin"]
    assert (spin.type, spin.limit, spin.parent, spin.child) == ("continuous", None, "wheel", "rim::spin")
    inertial = robot.link_map["rim"].inertial
    assert inertial is not None and not inertial.from_geometry
    assert inertial.mass == 2.0 and inertial.origin.xyz == pytest.approx((0.0, 0.0, 0.1))
    assert sorted((inertial.ixx, inertial.iyy, inertial.izz)) == pytest.approx([0.1, 0.2, 0.3])
    assert robot.link_map["rim"].collisions[0].geometry == Cylinder(0.1, pytest.approx(0.04))
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def test_include_locates_elements_in_the_included_file(tmp_path: Path) -> None:
    body = '<mujoco>\n<body name="arm">\n  <geom name="g" type="sphere" size="0.1"/>\n</body>\n</mujoco>\n'
    write(tmp_path / "parts" / "arm_body.xml", body)
    root = write(
        tmp_path / "robot.xml",
        '<mujoco>\n  <worldbody>\n    <include file="parts/arm_body.xml"/>\n  </worldbody>\n</mujoco>\n',
    )
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    arm = loaded.robot.link_map["arm"]
    assert arm.location is not None and (arm.location.file, arm.location.line) == ("parts/arm_body.xml", 2)
    (shape,) = arm.collisions
    assert shape.location is not None and (shape.location.file, shape.location.line) == ("parts/arm_body.xml", 3)
    assert list(loaded.document.sources) == ["robot.xml", "parts/arm_body.xml"]


def test_scaled_mesh_is_placed_where_mujoco_compiles_it(tmp_path: Path) -> None:
    # an off-centre, rotated box: MuJoCo re-centres it at its centroid and turns it to its principal axes
    part = trimesh.creation.box((40.0, 20.0, 10.0))
    part.apply_transform(trimesh.transformations.rotation_matrix(0.4, (0, 0, 1)))
    part.apply_translation((100.0, 50.0, 0.0))
    (tmp_path / "meshes").mkdir()
    part.export(tmp_path / "meshes" / "part.stl")
    text = """<mujoco><compiler meshdir="meshes" angle="radian"/>
      <asset><mesh name="part" file="part.stl" scale="0.001 0.001 0.001"/></asset>
      <worldbody><body name="b" pos="0 0 1">
        <geom type="mesh" mesh="part" pos="0.1 0 0" euler="0 0 0.5"/>
      </body></worldbody>
    </mujoco>"""
    root = write(tmp_path / "m.xml", text)
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    (shape,) = loaded.robot.link_map["b"].collisions
    assert shape.geometry == Mesh("meshes/part.stl", (0.001, 0.001, 0.001))
    mesh = MeshStore(loaded.bundle).get(shape.geometry)
    placed = mesh.vertices @ shape.origin.rotation().T + np.asarray(shape.origin.xyz)  # type: ignore[union-attr]
    model = mujoco.MjModel.from_xml_path(str(root))
    first, count = model.mesh_vertadr[0], model.mesh_vertnum[0]
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, model.geom_quat[0])
    compiled = model.mesh_vert[first : first + count] @ rotation.reshape(3, 3).T + model.geom_pos[0]
    assert np.allclose(np.sort(placed, axis=0), np.sort(compiled, axis=0), atol=1e-7)
    # the file's own frame: the box centre 0.1 m off the geom origin along the turned x axis
    centre = placed.mean(axis=0)
    turn = trimesh.transformations.rotation_matrix(0.5, (0, 0, 1))[:3, :3]  # the geom's euler, not MuJoCo's geom_quat
    expected = np.array([0.1, 0.0, 0.0]) + turn @ np.array([0.1, 0.05, 0.0])
    assert centre == pytest.approx(expected, abs=1e-9)


def test_compiler_error_is_an_input_error(tmp_path: Path) -> None:
    from geomcheck.errors import InputError

    text = '<mujoco><worldbody><body><geom type="mesh" mesh="nope"/></body></worldbody></mujoco>'
    root = write(tmp_path / "bad.xml", text)
    with pytest.raises(InputError, match=r"MuJoCo's compiler rejects the model: .*nope"):
        load_description(make_bundle(root, display_root=tmp_path))


def mjcf_robots(corpus: Path) -> dict[str, dict[str, object]]:
    with (corpus / "robots.toml").open("rb") as handle:
        return {k: v for k, v in tomllib.load(handle).items() if v.get("format") == "mjcf"}


def test_corpus_mjcf_counts_equal_mujoco(corpus: Path) -> None:
    robots = mjcf_robots(corpus)
    assert len(robots) == 13
    for name, entry in robots.items():
        root = (corpus / str(entry["root"])).resolve()
        loaded = load_description(make_bundle(root, display_root=corpus))
        model = mujoco.MjModel.from_xml_path(str(root))
        robot = loaded.robot
        bodies = [link for link in robot.links if not link.synthetic]
        body_names = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}" for b in range(model.nbody)}
        assert {link.name for link in bodies} == body_names, name
        assert len(bodies) == model.nbody, name
        shapes = [s for link in robot.links for s in (*link.visuals, *link.collisions)]
        assert len(shapes) == model.ngeom, name
        colliding = int(np.count_nonzero((model.geom_contype != 0) | (model.geom_conaffinity != 0)))
        assert sum(len(link.collisions) for link in robot.links) == colliding, name
        assert len([j for j in robot.joints if j.type != "fixed"]) == model.njnt, name
        assert all(s.location is not None and s.location.line is not None for s in shapes), name


def caster_mjcf(free_base: bool) -> str:
    """A base (plate and a post) with a caster whose arm passes through the post as it turns."""
    px, py = 0.15 * math.cos(math.radians(40.0)), 0.15 * math.sin(math.radians(40.0))
    free = "<freejoint/>" if free_base else ""
    return f"""<mujoco><compiler angle="radian"/><worldbody>
      <body name="base_link">{free}
        <geom type="box" pos="0 0 0.3" size="0.4 0.4 0.025"/>
        <geom type="box" pos="{0.2 + px} {0.2 + py} 0.05" euler="0 0 {math.radians(40.0)}" size="0.01 0.01 0.05"/>
        <body name="caster_link" pos="0.2 0.2 0">
          <joint name="caster_joint" axis="0 0 1"/>
          <geom type="box" pos="0.08 0 0.05" size="0.1 0.02 0.01"/>
        </body>
      </body></worldbody></mujoco>"""


def test_mesh_without_a_file_is_skipped(tmp_path: Path) -> None:
    text = """<mujoco><asset><mesh name="t" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset>
      <worldbody><body name="b"><geom type="mesh" mesh="t"/><geom type="sphere" size="0.1"/></body></worldbody>
    </mujoco>"""
    robot = load_description(make_bundle(write(tmp_path / "t.xml", text), display_root=tmp_path)).robot
    assert [s.geometry for s in robot.link_map["b"].collisions] == [Sphere(0.1)]


def test_cli_checks_an_mjcf_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from geomcheck.cli import main

    root = write(tmp_path / "caster.xml", caster_mjcf(free_base=False))
    out = tmp_path / "report.json"
    # the caster clips its parent over its turn: info (parent and child: MoveIt, Gazebo and MuJoCo
    # do not collide them, no consumer meets it)
    assert main(["check", str(root), "--format", "json", "-o", str(out), "--no-untrusted"]) == 0
    report = json.loads(out.read_text())
    assert report["robot"]["name"] == "caster"
    assert [(d["code"], d["links"]) for d in report["diagnostics"] if d["code"] == "GC401"] == [
        ("GC401", ["base_link", "caster_link"])
    ]
    assert [d["severity"] for d in report["diagnostics"] if d["code"] == "GC401"] == ["info"]
    assert "links" in report["sections"] and "fixes" not in report["sections"]  # fixes edit URDF/xacro only


def test_confined_bundle_refuses_assets_outside_before_mujoco_reads_them(tmp_path: Path) -> None:
    from geomcheck.errors import SandboxViolation

    trimesh.creation.box((1.0, 1.0, 1.0)).export(tmp_path / "outside.stl")
    text = '<mujoco><asset><mesh name="m" file="../outside.stl"/></asset>'
    text += '<worldbody><body><geom type="mesh" mesh="m"/></body></worldbody></mujoco>'
    root = write(tmp_path / "robot" / "r.xml", text)
    with pytest.raises(SandboxViolation, match=r"outside\.stl"):
        load_description(make_bundle(root, display_root=tmp_path / "robot", confined=True))
    assert len(load_description(make_bundle(root, display_root=tmp_path / "robot")).robot.links) == 2


def frame_error(root: Path, seed: int = 0) -> float:
    """Largest difference between geomcheck's link frames and MuJoCo's body frames (positions [m]
    and rotation matrix entries) at a random configuration of the hinge and slide joints."""
    from geomcheck.kinematics import Kinematics

    robot = load_description(make_bundle(root, display_root=root.parent)).robot
    model = mujoco.MjModel.from_xml_path(str(root))
    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    kin = Kinematics(robot)
    names = [j.name for j in kin.joints]
    q = np.zeros(len(names))
    rng = np.random.default_rng(seed)
    for j in range(model.njnt):
        if model.jnt_type[j] in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
            low, high = model.jnt_range[j] if model.jnt_limited[j] else (-1.0, 1.0)
            value, address = rng.uniform(low, high), model.jnt_qposadr[j]
            data.qpos[address] = value
            q[names.index(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j))] = value - model.qpos0[address]
    mujoco.mj_kinematics(model, data)
    frames = kin.link_transforms(q[None])[0]
    error = 0.0
    for b in range(1, model.nbody):
        frame = frames[kin.link_index(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}")]
        error = max(error, float(np.abs(frame[:3, 3] - data.xpos[b]).max()))
        error = max(error, float(np.abs(frame[:3, :3] - data.xmat[b].reshape(3, 3)).max()))
    return error


def test_frames_follow_mujoco_with_anchors_refs_and_several_joints(tmp_path: Path) -> None:
    text = ARM.replace('<joint name="shoulder"/>', '<joint name="shoulder" ref="20" pos="0 0.01 0.02"/>')
    root = write(tmp_path / "arm.xml", text)
    assert frame_error(root, seed=1) < 1e-12


def test_corpus_frames_follow_mujoco(corpus: Path) -> None:
    for name, entry in mjcf_robots(corpus).items():
        assert frame_error((corpus / str(entry["root"])).resolve()) < 1e-12, name


LINKAGE = """<mujoco model="linkage">
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.05"/>
      <body name="crank" pos="0 0 0.05"><joint name="a"/><geom size="0.01"/>
        <site name="crank_tip" pos="0.1 0 0"/></body>
      <body name="rod" pos="0 0 0.1"><joint name="b"/><geom size="0.01"/>
        <site name="rod_end" pos="0.1 0 0"/></body>
      <body name="lever" pos="0 0 0.2"><joint name="c"/><geom size="0.01"/></body>
    </body>
    <body name="free" pos="1 0 0"><freejoint/><geom size="0.01"/></body>
  </worldbody>
  <equality>
    <connect body1="rod" body2="lever" anchor="0.1 0 0"/>
    <connect site1="crank_tip" site2="rod_end"/>
    <weld body1="free"/>
    <connect body1="crank" body2="lever" anchor="0 0 0" active="false"/>
    <joint joint1="a" joint2="c"/>
  </equality>
</mujoco>
"""


def test_loop_closing_equalities_pair_their_bodies(tmp_path: Path) -> None:
    # connect by bodies or by sites closes a loop; a weld to the world, an inactive constraint and
    # a joint coupling do not
    robot = load_description(make_bundle(write(tmp_path / "linkage.xml", LINKAGE))).robot
    assert robot.closures == (("rod", "lever"), ("crank", "rod"))


def test_the_loaders_frames_and_welds_are_neither_counted_nor_named(tmp_path: Path) -> None:
    """MuJoCo's bodies but the world and its joints are the report's links and joints; the
    frames geomcheck adds (a body with several joints, a joint anchored off the body's origin)
    and the welds of bodies without joints are the loader's, named so no file name is taken."""
    import geomcheck

    text = """<mujoco model="gripper"><worldbody>
      <body name="palm">
        <joint name="x" type="slide" axis="1 0 0" range="-1 1"/>
        <joint name="y" type="slide" axis="0 1 0"/>
        <joint name="z" type="ball" pos="0 0 0.1"/>
        <geom type="box" size="0.05 0.05 0.02"/>
        <body name="finger" pos="0.05 0 0"><joint name="camera_fixed" type="hinge" range="0 1" pos="0.01 0 0"/>
          <geom type="capsule" size="0.01 0.03"/></body>
        <body name="camera" pos="0 0 0.05"><geom type="sphere" size="0.01"/></body>
      </body></worldbody></mujoco>"""
    path = write(tmp_path / "gripper.xml", text)
    model = mujoco.MjModel.from_xml_path(str(path))
    robot = load_description(make_bundle(path, display_root=tmp_path)).robot
    assert [link.name for link in robot.authored_links] == ["palm", "finger", "camera"]
    assert len(robot.authored_links) == model.nbody - 1 and len(robot.authored_joints) == model.njnt
    assert [j.name for j in robot.authored_joints] == ["x", "y", "z", "camera_fixed"]
    joints = robot.joint_map
    # MuJoCo leaves a slide without a range unlimited: no range of [0, 0]
    assert joints["y"].limit is not None and joints["y"].limit.unlimited and joints["y"].limit.lower is None
    assert joints["z"].type == "ball"
    # the loader's joints: the camera's weld, the anchors back to the palm's and finger's origins
    made = [(j.name, j.child, j.author) for j in robot.joints if j.synthetic]
    assert made == [  # the camera's weld may not take the name of the finger's joint
        ("palm_anchor", "palm", "z"),
        ("finger_anchor", "finger", "camera_fixed"),
        ("camera_fixed2", "camera", None),
    ]
    assert robot.link_map["world"].world and not robot.link_map["world"].authored
    report = geomcheck.check(path, select=["GC1"], use_config=False)
    assert (report.robot.links, report.robot.joints) == (3, 4)
    assert not [d for d in report.diagnostics if d.code.startswith("GC1")]  # no GC121 on the unlimited slide
    section = {j["name"]: j for j in report.sections["model"]["joints"]}
    assert list(section) == ["x", "y", "z", "camera_fixed"]
    assert [(j["parent"], j["child"]) for j in section.values()] == [("world", "palm")] * 3 + [("palm", "finger")]
    assert section["camera_fixed"]["origin"]["xyz"] == pytest.approx([0.05, 0.0, 0.0])  # the body's pose
    assert section["y"]["limit"] == {"lower": None, "upper": None, "effort": None, "velocity": None}
    assert [s["type"] for s in report.sections["model"]["links"][1]["collisions"]] == ["capsule"]
