"""Default-pose collisions (GC403): depth, adjacency, posing by --pose, mid-range and SRDF group_state."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import UsageError
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report
from geomcheck.selfcollision.default_pose import contacts_at

ROBOT = """<?xml version="1.0"?>
<robot name="hand">
  <link name="base_link">
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <joint name="arm_joint" type="revolute">
    <parent link="base_link"/><child link="arm"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/>
  </joint>
  <link name="arm">
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.05 0.05 0.05"/></geometry></collision>
  </link>
  <joint name="hand_joint" type="revolute">
    <parent link="arm"/><child link="hand"/><origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>
    <limit lower="{lower}" upper="1.5" effort="1" velocity="1"/>
  </joint>
  <link name="hand">
    <collision><origin xyz="0 0 -0.3"/><geometry><box size="0.05 0.05 0.6"/></geometry></collision>
  </link>
  <joint name="tag_joint" type="fixed"><parent link="hand"/><child link="tag"/><origin xyz="0 0 -0.65"/></joint>
  <link name="tag">
    <collision><geometry><box size="0.01 0.01 0.01"/></geometry></collision>
  </link>
</robot>
"""

SRDF = """<?xml version="1.0"?>
<robot name="hand">
  <group name="arm"><joint name="arm_joint"/><joint name="hand_joint"/></group>
  <group_state name="tucked" group="arm">
    <joint name="arm_joint" value="0"/><joint name="hand_joint" value="1.2"/>
  </group_state>
  {extra}
</robot>
"""


def check(tmp_path: Path, lower: float = -1.5, srdf: str | None = None, **options: object) -> Report:
    root = tmp_path / "robot.urdf"
    root.write_text(ROBOT.format(lower=lower))
    if srdf is not None:
        (tmp_path / "robot.srdf").write_text(srdf)
        options["srdf"] = tmp_path / "robot.srdf"
    return run_check(make_bundle(root, display_root=tmp_path), CheckOptions(sweep=False, **options))  # type: ignore[arg-type]


def gc403(report: Report) -> list[tuple[tuple[str, str] | None, float]]:
    return [(d.links, d.data["depth_mm"]) for d in report.diagnostics if d.code == "GC403"]


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_non_adjacent_pair_in_collision_at_zero_is_an_error_with_its_depth(tmp_path: Path, backend: str) -> None:
    report = check(tmp_path, backend=backend)
    # the hand hangs 0.6 m down into the base; hand/arm and hand/tag are adjacent, base/arm are apart
    [d] = [d for d in report.diagnostics if d.code == "GC403"]
    assert d.links == ("base_link", "hand")
    assert d.data["depth_mm"] == pytest.approx(125.0, abs=0.5)  # out sideways: 0.1 + 0.025 m
    # the hand and the arm swing over +-1.5 rad: the hand reaches into the base in 23 of 100 poses
    assert d.message == (
        "base_link and hand are in collision at the default pose: 125.0 mm deep, "
        "and in 23 of 100 sampled poses of the joints between them"
    )
    assert (d.data["collisions"], d.data["tested"]) == (23, 100)
    assert d.location is not None and d.location.line == 4  # base_link's <collision>
    assert d.severity.value == "error" and report.failed


def test_pose_and_mid_range_move_the_hand_out(tmp_path: Path) -> None:
    assert gc403(check(tmp_path, pose={"hand_joint": 1.2})) == []
    assert gc403(check(tmp_path, lower=0.5)) == []  # 0 is outside [0.5, 1.5]: the default is 1.0
    with pytest.raises(UsageError, match=r"invalid joint 'wrist'; valid choices: arm_joint, hand_joint"):
        check(tmp_path, pose={"wrist": 1.0})


def test_named_pose_from_the_srdf(tmp_path: Path) -> None:
    assert gc403(check(tmp_path, srdf=SRDF.format(extra=""), pose_name="tucked")) == []
    with pytest.raises(UsageError, match="tucked"):
        check(tmp_path, srdf=SRDF.format(extra=""), pose_name="home")
    with pytest.raises(UsageError, match="needs an SRDF"):
        check(tmp_path, pose_name="tucked")
    # --pose wins over the named pose
    report = check(tmp_path, srdf=SRDF.format(extra=""), pose_name="tucked", pose={"hand_joint": 0.0})
    assert gc403(report) == [(("base_link", "hand"), pytest.approx(125.0, abs=0.5))]
    assert "pose 'tucked' with hand_joint=0" in report.diagnostics[0].message


def test_pairs_the_srdf_disables_are_not_reported(tmp_path: Path) -> None:
    extra = '<disable_collisions link1="hand" link2="base_link" reason="Default"/>'
    assert gc403(check(tmp_path, srdf=SRDF.format(extra=extra))) == []


def test_rigidly_attached_overlap_is_left_to_the_matrix_and_the_srdf_audit(tmp_path: Path) -> None:
    root = tmp_path / "robot.urdf"
    text = ROBOT.format(lower=-1.5).replace('<origin xyz="0 0 -0.65"/>', '<origin xyz="0 0 -0.1"/>')
    # the tag now sits inside the hand box, adjacent; add a second tag below it, rigid but not adjacent
    text = text.replace(
        "</robot>",
        '<joint name="tag2_joint" type="fixed"><parent link="tag"/><child link="tag2"/></joint>\n'
        '<link name="tag2"><collision><geometry><box size="0.01 0.01 0.01"/></geometry></collision></link>\n'
        "</robot>",
    )
    root.write_text(text)
    bundle = make_bundle(root, display_root=tmp_path)
    # hand / tag2 overlap in every configuration: not a default-pose defect
    report = run_check(bundle, CheckOptions(sweep=False, pose={"hand_joint": 1.2}))
    assert gc403(report) == []
    # the matrix classes the pair Default (MoveIt's precedence), and an SRDF leaving it on is GC413
    (tmp_path / "robot.srdf").write_text(SRDF.format(extra=""))
    options = CheckOptions(sweep=False, pose={"hand_joint": 1.2}, srdf=tmp_path / "robot.srdf", samples=50, workers=1)
    report = run_check(bundle, options)
    assert gc403(report) == []
    pairs = {tuple(p["links"]): p["class"] for p in report.sections["matrix"]["pairs"]}
    assert pairs[("hand", "tag2")] == "default" and pairs[("hand", "tag")] == "adjacent"
    found = {d.links: d for d in report.diagnostics if d.code == "GC413"}
    assert sorted(found) == [("hand", "tag"), ("hand", "tag2"), ("tag", "tag2")]
    rigid = found[("hand", "tag2")]
    assert rigid.message == (
        "rigidly attached links hand and tag2 are in collision at the default pose (30.0 mm deep), and so in every "
        "pose (only fixed joints tag2_joint, tag_joint join them), but robot.srdf leaves their collision checking on"
    )
    assert rigid.help == 'Disable the pair: `<disable_collisions link1="hand" link2="tag2" reason="Default"/>`.'
    assert found[("hand", "tag")].message.startswith("adjacent links hand and tag are in collision")


def test_contacts_at_uses_the_broad_phase_and_skips_adjacent_pairs(tmp_path: Path) -> None:
    root = tmp_path / "robot.urdf"
    root.write_text(ROBOT.format(lower=-1.5))
    bundle = make_bundle(root, display_root=tmp_path)
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    scene = CollisionScene(robot, MeshStore(bundle), get_backend("coal"))
    adjacent = adjacent_pairs(robot, scene.links)
    assert adjacent == {("arm", "base_link"), ("arm", "hand"), ("hand", "tag")}
    [contact] = contacts_at(kin, scene, kin.default_configuration(), adjacent)
    assert contact.links == ("base_link", "hand") and contact.distance == pytest.approx(-0.125)
    assert len(contacts_at(kin, scene, kin.default_configuration(), ())) == 2  # with arm / hand, adjacent
    q = kin.default_configuration({"hand_joint": 1.2})
    assert contacts_at(kin, scene, q, adjacent) == []
    assert np.all(np.isfinite(q))


LINKAGE = """<?xml version="1.0"?>
<robot name="gripper">
  <link name="palm"><collision><origin xyz="0 0 -0.5"/><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="knuckle_joint" type="revolute">
    <parent link="palm"/><child link="knuckle"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.8" effort="1" velocity="1"/>
  </joint>
  <link name="knuckle">
    <collision><origin xyz="0.1 0 0"/><geometry><box size="0.1 0.02 0.02"/></geometry></collision>
  </link>
  <joint name="finger_joint" type="revolute">
    <parent link="palm"/><child link="finger"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.8" effort="1" velocity="1"/>{mimic}
  </joint>
  <link name="finger">
    <collision><origin xyz="0.15 0 0"/><geometry><box size="0.1 0.02 0.02"/></geometry></collision>
  </link>
  <joint name="left_joint" type="prismatic">
    <parent link="palm"/><child link="left"/><origin xyz="0 0 -0.3"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="1" velocity="1"/>
  </joint>
  <link name="left">
    <collision><origin xyz="0 0.01 0"/><geometry><box size="0.02 0.02 0.02"/></geometry></collision>
  </link>
  <joint name="right_joint" type="prismatic">
    <parent link="palm"/><child link="right"/><origin xyz="0 0 -0.3"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.04" effort="1" velocity="1"/><mimic joint="left_joint"/>
  </joint>
  <link name="right">
    <collision><origin xyz="0 -0.01 0"/><geometry><box size="0.02 0.02 0.02"/></geometry></collision>
  </link>
</robot>
"""


def linkage(tmp_path: Path, mimic: bool) -> dict[tuple[str, str] | None, Diagnostic]:
    root = tmp_path / "gripper.urdf"
    root.write_text(LINKAGE.format(mimic='<mimic joint="knuckle_joint"/>' if mimic else ""))
    report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(sweep=False))
    return {d.links: d for d in report.diagnostics if d.code == "GC403"}


def test_overlap_at_the_pin_of_a_linkage_is_info_with_the_srdf_line(tmp_path: Path) -> None:
    # finger_joint mimics knuckle_joint: the knuckle (x 0.05..0.15) and the finger (x 0.1..0.2)
    # turn together and overlap by 5 cm in every pose, as a four-bar linkage's links at their pin
    found = linkage(tmp_path, mimic=True)
    pin = found[("finger", "knuckle")]
    assert pin.severity.value == "info"
    assert (pin.data["collisions"], pin.data["tested"], pin.data["depth_mm"]) == (100, 100, pytest.approx(20.0))
    assert pin.message == (
        "finger and knuckle are in collision at the default pose, with knuckle_joint at its lower limit (0 rad): "
        "20.0 mm deep, and in 100 of 100 sampled poses of the joints between them: an overlap by design, which no "
        "pose removes"
    )
    line = '<disable_collisions link1="finger" link2="knuckle" reason="Default"/>'
    assert pin.data["srdf_line"] == line and line in (pin.help or "")


def test_links_turned_independently_collide_in_some_poses_only_an_error(tmp_path: Path) -> None:
    pin = linkage(tmp_path, mimic=False)[("finger", "knuckle")]
    assert pin.severity.value == "error"
    assert 0 < pin.data["collisions"] < 95 and pin.data["tested"] == 100


def test_closed_fingers_that_touch_are_info(tmp_path: Path) -> None:
    # the two finger boxes meet at y = 0 when closed (both prismatic joints at 0) and part as they open
    touch = linkage(tmp_path, mimic=True)[("left", "right")]
    assert touch.severity.value == "info" and touch.data["depth_mm"] == 0.0
    assert touch.message == (
        "left and right touch at the default pose, with left_joint at its lower limit (0 m) (apart after a 0.1 mm "
        "shift; in contact in 0 of 100 sampled poses of the joints between them): faces meeting by design, such as "
        "closed gripper fingers"
    )


def test_block_resting_flush_in_an_l_shaped_mesh_touches_though_the_hulls_overlap(tmp_path: Path) -> None:
    import trimesh

    # an L: a floor 0.2 x 0.2 x 0.02 and a wall 0.02 thick, one mesh; the block sits on the floor
    # against nothing else, inside the L's convex hull (the hulls overlap by 2 cm), its face on the floor's
    floor = trimesh.creation.box((0.2, 0.2, 0.02), trimesh.transformations.translation_matrix((0, 0, -0.01)))
    wall = trimesh.creation.box((0.02, 0.2, 0.2), trimesh.transformations.translation_matrix((0.09, 0, 0.1)))
    trimesh.util.concatenate([floor, wall]).export(tmp_path / "l.stl")
    (tmp_path / "robot.urdf").write_text("""<?xml version="1.0"?>
<robot name="shelf">
  <link name="base"><collision><geometry><mesh filename="l.stl"/></geometry></collision></link>
  <joint name="a" type="revolute"><parent link="base"/><child link="post"/><origin xyz="-0.5 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="post"><collision><geometry><sphere radius="0.01"/></geometry></collision></link>
  <joint name="b" type="revolute"><parent link="post"/><child link="block"/><origin xyz="0.5 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="block"><collision><origin xyz="0 0 0.02"/><geometry><box size="0.04 0.04 0.04"/></geometry></collision>
  </link>
</robot>
""")
    report = run_check(make_bundle(tmp_path / "robot.urdf", display_root=tmp_path), CheckOptions(sweep=False))
    [d] = [d for d in report.diagnostics if d.code == "GC403"]
    # the hulls overlap by centimetres; the triangles part after a shift of a tenth of a millimetre
    assert d.links == ("base", "block") and d.data["hull_depth_mm"] > 10.0 and d.data["depth_mm"] <= 0.1
    assert d.severity.value == "info" and "(apart after a 0.1 mm shift" in d.message


def test_the_message_names_the_joints_at_a_limit_or_mid_range_between_the_pair(tmp_path: Path) -> None:
    """A default pose is 0, or mid-range where 0 is outside a joint's limits: the message says
    which joints between the pair sit at a limit or off zero, so that nobody reproduces the
    contact at another pose (a judge of a Panda's finding took its elbow at 0)."""
    from geomcheck.checks.selfcollision import pose_between

    urdf = tmp_path / "arm.urdf"
    joint = '<joint name="{0}" type="{1}"><parent link="{2}"/><child link="{3}"/><axis xyz="0 0 1"/>{4}</joint>'
    limit = '<limit lower="{0}" upper="{1}" effort="1" velocity="1"/>'
    urdf.write_text(
        '<robot name="arm">'
        + "".join(f'<link name="{n}"/>' for n in ("base", "upper", "fore", "hand", "tip"))
        + joint.format("shoulder", "revolute", "base", "upper", limit.format(-1, 1))
        + joint.format("elbow", "revolute", "upper", "fore", limit.format(-3.0718, -0.0698))
        + joint.format("wrist", "revolute", "fore", "hand", limit.format(0, 2))
        + joint.format("slide", "prismatic", "hand", "tip", limit.format(0, 0.04))
        + "</robot>"
    )
    kin = Kinematics(load_description(make_bundle(urdf)).robot)
    q = kin.default_configuration()
    assert pose_between(kin, q, "base", "upper") == ""
    assert pose_between(kin, q, "upper", "tip") == (
        ", with elbow at -1.571 rad (mid-range: 0 is outside its limits), slide at its lower limit (0 m) and "
        "wrist at its lower limit (0 rad)"  # by name, whatever the order of the joints in the file
    )
    assert pose_between(kin, kin.default_configuration({"wrist": 2.0}), "fore", "hand") == (
        ", with wrist at its upper limit (2 rad)"
    )


MJCF_ARMS = """<mujoco model="arms">
  <worldbody>
    <body name="torso">
      <geom name="torso" type="box" size="0.1 0.1 0.1"/>
      <body name="left" pos="0 0.15 0.1">
        <joint name="left_joint" axis="1 0 0" range="-1 1"/>
        <geom name="left" type="capsule" fromto="0 0 0 0 0 0.2" size="0.03"/>
      </body>
      <body name="right" pos="0 {right_y} 0.1">
        <joint name="right_joint" axis="1 0 0" range="-1 1"/>
        <geom name="right" type="{kind}" {shape}/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def check_mjcf(tmp_path: Path, right_y: float, kind: str, shape: str) -> Report:
    root = tmp_path / "arms.xml"
    root.write_text(MJCF_ARMS.format(right_y=right_y, kind=kind, shape=shape))
    return run_check(make_bundle(root, display_root=tmp_path), CheckOptions(workers=1, sweep=False))


def test_an_mjcf_pair_in_collision_is_told_to_exclude_in_mujocos_terms(tmp_path: Path) -> None:
    """MuJoCo reads no SRDF: an intended contact is excluded by the model's own <contact>."""
    report = check_mjcf(tmp_path, 0.19, "capsule", 'fromto="0 0 0 0 0 0.2" size="0.03"')
    (finding,) = [d for d in report.diagnostics if d.code == "GC403"]
    assert finding.links == ("left", "right") and finding.data["depth_mm"] == pytest.approx(20.0, abs=0.01)
    assert '`<contact><exclude body1="left" body2="right"/></contact>`' in finding.help
    assert "SRDF" not in finding.help


@pytest.mark.parametrize(
    ("right_y", "kind", "shape"),
    [
        # end past end, 40 mm apart sideways: the capsules clear by 4 mm, their enclosing
        # cylinders' rims overlap 20 mm
        (0.19, "capsule", 'fromto="0 0 0.25 0 0 0.45" size="0.03"'),
        # an ellipsoid (a sphere) whose enclosing box reaches into the capsule's end, the
        # ellipsoid 12 mm short of it
        (0.21, "ellipsoid", 'pos="0 0 0.27" size="0.05 0.05 0.05"'),
    ],
    ids=["capsule", "ellipsoid"],
)
def test_mjcf_capsules_and_ellipsoids_collide_as_mujoco_collides_them(
    tmp_path: Path, right_y: float, kind: str, shape: str
) -> None:
    mujoco = pytest.importorskip("mujoco")
    report = check_mjcf(tmp_path, right_y, kind, shape)
    assert not [d for d in report.diagnostics if d.code == "GC403"]
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "arms.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert data.ncon == 0  # MuJoCo's own contacts at the default pose: none either


def test_the_contact_help_names_each_formats_own_means() -> None:
    from geomcheck.checks.selfcollision import contact_help

    srdf = '<disable_collisions link1="a" link2="b" reason="Default"/>'
    assert contact_help("urdf", ("a", "b"), srdf, by_design=False) is None  # the rule's own: the SRDF
    assert contact_help("urdf", ("a", "b"), srdf, by_design=True) == (
        f"MoveIt's Setup Assistant disables this pair; add it to the SRDF: `{srdf}`."
    )
    mjcf = contact_help("mjcf", ("a", "b"), srdf, by_design=True)
    exclude = '<contact><exclude body1="a" body2="b"/></contact>'
    assert mjcf == f"MuJoCo collides this pair unless the model excludes it: `{exclude}`."
    sdf = contact_help("sdf", ("a", "b"), srdf, by_design=False)
    assert sdf is not None and "<collide_bitmask>" in sdf and "SRDF" not in sdf


def test_parts_drawn_overlapping_at_the_pose_are_a_pose_the_robot_cannot_take(tmp_path: Path) -> None:
    """The hand hangs into the base as drawn too: inside every joint's range that pose is one the
    robot cannot take (info, told to check another pose); at a joint's limit the limit lets the
    parts meet, the description's own error."""
    drawn = ROBOT.replace(
        '<collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>',
        '<visual><geometry><box size="0.2 0.2 0.2"/></geometry></visual>'
        '<collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>',
    ).replace(
        '<collision><origin xyz="0 0 -0.3"/><geometry><box size="0.05 0.05 0.6"/></geometry></collision>',
        '<visual><origin xyz="0 0 -0.3"/><geometry><box size="0.05 0.05 0.6"/></geometry></visual>'
        '<collision><origin xyz="0 0 -0.3"/><geometry><box size="0.05 0.05 0.6"/></geometry></collision>',
    )
    assert drawn.count("<visual>") == 2

    def only_gc403(lower: float) -> Diagnostic:
        root = tmp_path / "robot.urdf"
        root.write_text(drawn.format(lower=lower))
        report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(sweep=False))
        [d] = [d for d in report.diagnostics if d.code == "GC403"]
        return d

    inside = only_gc403(-1.5)
    assert inside.links == ("base_link", "hand") and inside.severity.value == "info"
    # as drawn the boxes are the collision boxes: they part after the same 125 mm
    assert "their visual geometry overlaps there too (125.0 mm deep): the parts themselves collide" in inside.message
    assert inside.help is not None and "--pose-name NAME" in inside.help
    at_limit = only_gc403(0.0)
    assert at_limit.severity.value == "error"
    assert at_limit.message.endswith(
        "their visual geometry overlaps there too (125.0 mm deep): "
        "hand_joint's lower limit lets the parts themselves meet"
    )


def test_padded_collision_meeting_only_at_a_joints_stop_is_info(tmp_path: Path) -> None:
    """A lift on a prismatic joint, at its bottom stop at 0: its padded collision box reaches 15 mm
    into the base's, while the parts as drawn stay 5 mm apart; 5% of the 1 m travel up they part."""
    lift = """<?xml version="1.0"?>
<robot name="lift">
  <link name="base"><visual><geometry><box size="0.3 0.3 0.2"/></geometry></visual>
    <collision><geometry><box size="0.3 0.3 0.2"/></geometry></collision></link>
  <joint name="mast" type="fixed"><parent link="base"/><child link="mast_link"/><origin xyz="0.3 0 0"/></joint>
  <link name="mast_link"><visual><origin xyz="0 0 0.6"/><geometry><box size="0.02 0.02 1"/></geometry></visual>
    <collision><origin xyz="0 0 0.6"/><geometry><box size="0.02 0.02 1"/></geometry></collision></link>
  <joint name="lift_joint" type="prismatic">
    <parent link="mast_link"/><child link="carriage"/><origin xyz="-0.3 0 {z}"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="carriage"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
    <collision><geometry><box size="0.1 0.1 {padded}"/></geometry></collision></link>
</robot>
"""

    def gc403(z: float, padded: float) -> Diagnostic:
        root = tmp_path / "lift.urdf"
        root.write_text(lift.format(z=z, padded=padded))
        report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(sweep=False))
        [d] = [d for d in report.diagnostics if d.code == "GC403"]
        return d

    # the carriage's bottom 5 mm above the base's top (0.1 + 0.05 + 0.005), its box 40 mm taller
    at_stop = gc403(0.155, 0.14)
    assert at_stop.links == ("base", "carriage") and at_stop.severity.value == "info"
    assert at_stop.data["depth_mm"] == pytest.approx(15.0, abs=0.1)
    assert at_stop.message.endswith(
        "the parts as drawn are apart there, and with that joint moved 5% of its range off the limit the "
        "collision geometry parts too: its margins meet at the stop"
    )
    # 80 mm taller, the box still reaches into the base 50 mm up: not only at the stop
    assert gc403(0.155, 0.22).severity.value == "error"


def hollow_section(name: str, width: float, half_height: float) -> str:
    """A 0.3 m section drawn as two 1 cm plates ``half_height`` above and below its axis, its
    collision one solid box around both."""
    plate = f'<geometry><box size="0.3 {width} 0.01"/></geometry>'
    return (
        f'<link name="{name}">'
        f'<visual><origin xyz="0 0 {half_height}"/>{plate}</visual>'
        f'<visual><origin xyz="0 0 {-half_height}"/>{plate}</visual>'
        f'<collision><geometry><box size="0.3 {width} {2 * half_height + 0.01:g}"/></geometry></collision>'
        "</link>"
    )


def slide(name: str, parent: str, child: str, kind: str, axis: str) -> str:
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><axis xyz="{axis}"/>'
        '<limit lower="-0.05" upper="0.3" effort="1" velocity="1"/></joint>'
    )


def telescope(kind: str, axis: str) -> str:
    """Three nested sections: ``middle`` slides in ``outer`` by a ``kind`` joint along ``axis``,
    ``inner`` (a solid bar) slides in ``middle`` along x."""
    inner = (
        '<link name="inner"><visual><geometry><box size="0.3 0.06 0.02"/></geometry></visual>'
        '<collision><geometry><box size="0.3 0.06 0.02"/></geometry></collision></link>'
    )
    return (
        '<?xml version="1.0"?><robot name="telescope">'
        + hollow_section("outer", 0.1, 0.05)
        + slide("middle_joint", "outer", "middle", kind, axis)
        + hollow_section("middle", 0.08, 0.03)
        + slide("inner_joint", "middle", "inner", "prismatic", "1 0 0")
        + inner
        + "</robot>"
    )


def test_nested_sections_of_a_telescope_are_info(tmp_path: Path) -> None:
    """Three nested sections drawn as hollow (two plates each): the outer section's solid box holds
    the inner one, whose own plates it never touches. Only prismatic joints along x move them: by
    design. A middle section sliding along z instead is no telescope, and stays an error."""

    def gc403(kind: str, axis: str) -> Diagnostic:
        root = tmp_path / "telescope.urdf"
        root.write_text(telescope(kind, axis))
        report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(sweep=False))
        [d] = [d for d in report.diagnostics if d.code == "GC403"]
        return d

    nested = gc403("prismatic", "1 0 0")
    assert nested.links == ("inner", "outer") and nested.severity.value == "info"
    assert nested.message.endswith(
        "only prismatic joints along one direction move them: nested sections, whose solid collision shapes "
        "fill the hollow the other slides in"
    )
    assert nested.help is not None and '<disable_collisions link1="inner" link2="outer"' in nested.help
    crossing = gc403("prismatic", "0 0 1")
    assert crossing.links == ("inner", "outer") and crossing.severity.value == "error"
