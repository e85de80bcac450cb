"""SRDF reading, writing (``geomcheck matrix``) and the audit (``check --srdf``, GC410-GC416)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from geomcheck.cli import main
from geomcheck.errors import InputError, UsageError
from geomcheck.load import make_bundle
from geomcheck.load.srdf import parse_srdf, read_srdf
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report
from geomcheck.report.srdf import render_srdf
from geomcheck.selfcollision.matrix import CollisionMatrix, PairClass, PairResult

# base: two blocks with a gap; slider: fits the gap only near x = 0 (base / slider Always);
# tag: inside the base (Default) and reached by the slider near x = 1 (slider / tag enabled);
# arm: a rod from the rail's centre (always touching the rail: adjacent and in contact) with a
# ball at 0.5 m that grazes the post only within a few mrad of 1 rad (found by the search).
POST = 0.5 + 0.03 - 0.00005
ROBOT = f"""<?xml version="1.0"?>
<robot name="rig">
  <link name="base">
    <collision><origin xyz="-0.785 0 0"/><geometry><box size="1.43 0.2 0.1"/></geometry></collision>
    <collision><origin xyz="0.785 0 0"/><geometry><box size="1.43 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="mount" type="fixed"><parent link="base"/><child link="rail"/><origin xyz="0 0 1"/></joint>
  <link name="rail"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="slide" type="prismatic">
    <parent link="rail"/><child link="slider"/><origin xyz="0 0 -1"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="slider"><collision><geometry><box size="0.1 0.1 0.05"/></geometry></collision></link>
  <joint name="tag_mount" type="fixed"><parent link="rail"/><child link="tag"/><origin xyz="1.0 0 -1"/></joint>
  <link name="tag"><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="swing" type="continuous"><parent link="rail"/><child link="arm"/><axis xyz="0 0 1"/></joint>
  <link name="arm">
    <collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.02 0.02"/></geometry></collision>
    <collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.01"/></geometry></collision>
  </link>
  <joint name="post_mount" type="fixed">
    <parent link="rail"/><child link="post"/><origin xyz="{POST * math.cos(1):.9f} {POST * math.sin(1):.9f} 0"/>
  </joint>
  <link name="post"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
</robot>
"""

SRDF = """<?xml version="1.0" encoding="UTF-8"?>
<robot name="{name}">
    <group name="all"><joint name="slide"/><joint name="swing"/></group>
    <group_state name="home" group="all">
        <joint name="slide" value="0"/>
        <joint name="swnig" value="0.5"/>
    </group_state>
    <!-- the first two can collide, the third has another reason, the fourth a typo -->
    <disable_collisions link1="slider" link2="tag" reason="Never"/>
    <disable_collisions link1="arm" link2="post" reason="Never"/>
    <disable_collisions link1="tag" link2="base" reason="Never"/>
    <disable_collisions link1="sldier" link2="base" reason="Never"/>
    <disable_collisions link1="rail" link2="slider" reason="Adjacent"/>
    <virtual_joint name="odom" type="planar" parent_frame="map" child_link="base"/>
    <group_state name="parked" group="all"><joint name="odom" value="0 0 0"/></group_state>
</robot>
"""


def audit(tmp_path: Path, name: str = "rig", srdf: str = SRDF) -> Report:
    (tmp_path / "robot.urdf").write_text(ROBOT)
    (tmp_path / "robot.srdf").write_text(srdf.format(name=name))
    bundle = make_bundle(tmp_path / "robot.urdf", display_root=tmp_path)
    options = CheckOptions(srdf=tmp_path / "robot.srdf", sweep=False, samples=300, workers=1)
    return run_check(bundle, options)


def findings(report: Report, prefix: str = "GC41") -> list[tuple[str, tuple[str, str] | None, int | None]]:
    return [
        (d.code, d.links, d.location.line if d.location else None)
        for d in report.diagnostics
        if d.code.startswith(prefix)
    ]


@pytest.fixture(scope="module")
def audited(tmp_path_factory: pytest.TempPathFactory) -> Report:
    return audit(tmp_path_factory.mktemp("audit"), name="rig2")


def test_audit_findings_with_their_lines(audited: Report) -> None:
    assert sorted(findings(audited)) == [
        ("GC410", ("arm", "post"), 10),
        ("GC410", ("slider", "tag"), 9),
        ("GC411", ("base", "sldier"), 12),
        ("GC412", ("base", "slider"), 2),
        ("GC413", ("arm", "rail"), 2),
        ("GC414", ("base", "tag"), 11),
        ("GC415", None, 4),
        ("GC416", None, 2),
    ]
    assert audited.failed and "matrix" in audited.sections


def test_disabled_pair_that_can_collide_names_the_witness(audited: Report) -> None:
    by_pair = {d.links: d for d in audited.diagnostics if d.code == "GC410"}
    searched = by_pair[("arm", "post")]
    assert searched.severity.value == "error" and searched.name == "srdf-disabled-pair-can-collide"
    assert searched.location is not None and searched.location.file == "robot.srdf"
    assert searched.data["source"] == "search" and list(searched.data["configuration"]) == ["swing"]
    assert searched.data["configuration"]["swing"] == pytest.approx(1.0, abs=0.004)
    assert searched.message.startswith(
        "robot.srdf disables collision checking between arm and post (reason Never) but they collide: "
    )
    assert "found by the witness search" in searched.message
    sampled = by_pair[("slider", "tag")]
    assert sampled.data["source"] == "sample" and sampled.data["configuration"]["slide"] > 0.925
    assert "random samples" in sampled.message


def test_other_audit_messages(audited: Report) -> None:
    messages = {d.code: d.message for d in audited.diagnostics if d.code.startswith("GC41")}
    assert messages["GC411"] == (
        "<disable_collisions> in robot.srdf names link 'sldier', which the robot does not have (did you mean 'slider'?)"
    )
    assert messages["GC414"] == "robot.srdf disables base / tag as 'Never', the collision matrix finds 'Default'"
    assert messages["GC415"].startswith("group_state 'home' in robot.srdf sets joint 'swnig'")
    assert len([d for d in audited.diagnostics if d.code == "GC415"]) == 1  # not the virtual joint
    assert "(did you mean 'swing'?)" in messages["GC415"]
    assert messages["GC416"] == "robot.srdf is written for robot 'rig2', the description is 'rig'"
    assert messages["GC413"].startswith("adjacent links arm and rail are in collision at the default pose")
    assert messages["GC412"].startswith("base and slider are in collision in ")


def test_enabled_adjacent_contacts_name_the_line_to_add(tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_text("""<?xml version="1.0"?>
<robot name="leg">
  <link name="shin"><collision><geometry><box size="0.04 0.04 0.3"/></geometry></collision></link>
  <joint name="ankle" type="fixed"><parent link="shin"/><child link="foot"/><origin xyz="0 0 -0.15"/></joint>
  <link name="foot"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
  <joint name="knee" type="revolute"><parent link="shin"/><child link="thigh"/><origin xyz="0 0 0.15"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="thigh"><collision><geometry><sphere radius="0.03"/></geometry></collision></link>
</robot>
""")
    (tmp_path / "robot.srdf").write_text('<?xml version="1.0"?>\n<robot name="leg"/>\n')
    bundle = make_bundle(tmp_path / "robot.urdf", display_root=tmp_path)
    report = run_check(bundle, CheckOptions(srdf=tmp_path / "robot.srdf", sweep=False, samples=50, workers=1))
    found = {d.links: d for d in report.diagnostics if d.code == "GC413"}
    assert sorted(found) == [("foot", "shin"), ("shin", "thigh")]
    foot, knee = found[("foot", "shin")], found[("shin", "thigh")]
    assert foot.message == (
        "adjacent links foot and shin are in collision at the default pose (20.0 mm deep), and so in every pose "
        "(only fixed joint ankle joins them), but robot.srdf leaves their collision checking on"
    )
    assert foot.help == 'Disable the pair: `<disable_collisions link1="foot" link2="shin" reason="Adjacent"/>`.'
    assert foot.data["fixed_joints"] == ["ankle"]
    assert knee.message == (
        "adjacent links shin and thigh are in collision at the default pose (30.0 mm deep), "
        "but robot.srdf leaves their collision checking on"
    )
    assert 'link1="shin" link2="thigh"' in knee.help and knee.data["fixed_joints"] == []


def test_srdf_of_another_variant_is_one_info_finding_per_kind(tmp_path: Path) -> None:
    # written for a leg with a hip link and joint this one lacks, posing pinocchio's free-flyer:
    # the shin / foot contact on the fixed ankle is one body for pinocchio (info), shin / thigh is not
    (tmp_path / "robot.urdf").write_text("""<?xml version="1.0"?>
<robot name="leg">
  <link name="shin"><collision><geometry><box size="0.04 0.04 0.3"/></geometry></collision></link>
  <joint name="ankle" type="fixed"><parent link="shin"/><child link="foot"/><origin xyz="0 0 -0.15"/></joint>
  <link name="foot"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
  <joint name="knee" type="revolute"><parent link="shin"/><child link="thigh"/><origin xyz="0 0 0.15"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="thigh"><collision><geometry><sphere radius="0.03"/></geometry></collision></link>
</robot>
""")
    (tmp_path / "robot.srdf").write_text("""<?xml version="1.0"?>
<robot name="leg">
  <group_state name="stand" group="leg">
    <joint name="root_joint" value="0 0 0.3 0 0 0 1"/>
    <joint name="hip_abduction" value="0.1"/>
    <joint name="knee" value="0.5"/>
    <joint name="kneee" value="0.5"/>
  </group_state>
  <disable_collisions link1="pelvis" link2="thigh" reason="Adjacent"/>
  <disable_collisions link1="pelvis" link2="hip" reason="Adjacent"/>
  <disable_collisions link1="shinn" link2="thigh" reason="Never"/>
</robot>
""")
    bundle = make_bundle(tmp_path / "robot.urdf", display_root=tmp_path)
    report = run_check(bundle, CheckOptions(srdf=tmp_path / "robot.srdf", sweep=False, samples=50, workers=1))
    audit = [d for d in report.diagnostics if "GC411" <= d.code < "GC5"]
    got = sorted((d.code, d.severity.value, d.links, d.joint, d.about) for d in audit)
    assert got == [
        ("GC411", "info", None, None, "other variant"),
        ("GC411", "warning", ("shinn", "thigh"), None, "shinn"),
        ("GC413", "info", ("foot", "shin"), None, ""),
        ("GC413", "warning", ("shin", "thigh"), None, ""),
        ("GC415", "info", None, None, "other variant"),
    ]
    by = {(d.code, d.severity.value): d for d in report.diagnostics}
    assert by["GC411", "info"].message == (
        "3 collision entries in robot.srdf name links the robot does not have and none of its links resembles "
        "(hip, pelvis): entries for another variant of the robot, which MoveIt and pinocchio skip"
    )
    assert by["GC411", "info"].data == {"element": "disable_collisions", "unknown_link": "hip, pelvis"}
    # hip_abduction resembles no joint; kneee resembles knee, which the pose already sets: not a misspelling
    assert by["GC415", "info"].message == (
        "3 values of group_states in robot.srdf set joints the robot does not have (hip_abduction, kneee, "
        "root_joint), none a misspelling of a joint the pose leaves unset: MoveIt and pinocchio skip them and "
        "apply the rest; root_joint holds 7 values, a floating base: MoveIt wants it declared as a <virtual_joint>"
    )
    assert by["GC413", "info"].message.endswith(
        "; the SRDF poses pinocchio's free-flyer 'root_joint' (7 values, no <virtual_joint>), and pinocchio makes "
        "links joined by fixed joints one body, which it never collides with itself, but robot.srdf leaves their "
        "collision checking on"
    )


def test_pinocchio_semantics_drops_findings_on_one_rigid_body(tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_text(ROBOT)
    (tmp_path / "robot.srdf").write_text('<?xml version="1.0"?>\n<robot name="rig"/>\n')
    bundle = make_bundle(tmp_path / "robot.urdf", display_root=tmp_path)
    found = {}
    for semantics in ("moveit", "pinocchio"):
        options = CheckOptions(srdf=tmp_path / "robot.srdf", sweep=False, samples=100, workers=1, semantics=semantics)
        report = run_check(bundle, options)
        found[semantics] = sorted((d.code, d.links) for d in report.diagnostics if d.code in ("GC403", "GC413"))
    # base / tag overlap on fixed joints only (base, rail and tag are one body): in contact in every pose,
    # no GC403 but the SRDF that leaves them on is GC413, as for arm / rail that touch at the swing
    assert found["moveit"] == [("GC413", ("arm", "rail")), ("GC413", ("base", "tag"))]
    assert found["pinocchio"] == [("GC413", ("arm", "rail"))]


def test_a_clean_srdf_has_no_findings(tmp_path: Path) -> None:
    clean = """<?xml version="1.0"?>
<robot name="{name}">
  <disable_collisions link1="arm" link2="rail" reason="Adjacent"/>
  <disable_collisions link1="base" link2="slider" reason="Always"/>
  <disable_collisions link1="base" link2="tag" reason="Default"/>
  <disable_collisions link1="arm" link2="base" reason="Never"/>
</robot>
"""
    report = audit(tmp_path, srdf=clean)
    assert findings(report) == []
    assert findings(report, "GC403") == []  # base / tag is disabled: no default-pose finding either


def test_reading_collision_entries_and_named_poses() -> None:
    text = b"""<?xml version="1.0"?>
<robot name="r">
  <!-- a comment -->
  <disable_collisions link1="b" link2="a" reason="Never"/>
  <disable_collisions link1="a" link2="c"/>
  <disable_default_collisions link="d"/>
  <enable_collisions link1="d" link2="a"/>
  <virtual_joint name="world_joint" type="floating" parent_frame="world" child_link="a"/>
  <group_state name="up" group="g">
    <joint name="j" value="0.5"/>
    <joint name="root" value="0 0 0.2 0 0 0 1"/>
  </group_state>
</robot>"""
    srdf = parse_srdf(text, "r.srdf")
    assert srdf.robot_name == "r"
    first, second = srdf.disabled
    assert first.pair == ("a", "b") and first.reason == "Never" and first.location.line == 4
    assert second.reason == "" and second.moveit_reason == "User"
    assert srdf.is_disabled("a", "b") and srdf.is_disabled("c", "a")
    assert srdf.is_disabled("d", "x") and not srdf.is_disabled("a", "d")  # re-enabled
    assert not srdf.is_disabled("a", "x")
    state = srdf.group_state("up")
    assert state.values["root"] == (0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 1.0)
    assert state.single_values() == {"j": 0.5} and state.location.line == 9
    assert srdf.virtual_joints == ("world_joint",)
    with pytest.raises(UsageError, match=r"invalid named pose .* 'down'; valid choices: up"):
        srdf.group_state("down")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            b"<robot><disable_collisions link1='a'/></robot>",
            r"r.srdf:1: <disable_collisions> lacks the attribute 'link2'",
        ),
        (b"<robot><group_state name='s'><joint name='j' value='x'/></group_state></robot>", "not a number"),
        (b"<robt/>", r"not an SRDF: the root element is <robt>"),
        (b"<robot><disable_collisions", r"r.srdf:1:\d+: GC101 malformed-xml"),
    ],
)
def test_unreadable_srdf_is_an_input_error(text: bytes, message: str) -> None:
    with pytest.raises(InputError, match=message):
        parse_srdf(text, "r.srdf")


def test_missing_srdf_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such file"):
        read_srdf(tmp_path / "nope.srdf", "nope.srdf")


def _matrix(pairs: list[PairResult]) -> CollisionMatrix:
    return CollisionMatrix(
        samples=100,
        seed=3,
        backend="coal",
        always_fraction=0.95,
        links=("a&b", "c", "d"),
        pairs=tuple(pairs),
        default_configuration={},
    )


def test_writer_sorts_escapes_and_marks_certified_pairs() -> None:
    matrix = _matrix(
        [
            PairResult(("c", "d"), PairClass.NEVER, certified=True, clearance_bound=0.01234),
            PairResult(("a&b", "d"), PairClass.ENABLED),
            PairResult(("a&b", "c"), PairClass.ADJACENT),
        ]
    )
    text = render_srdf(matrix, "bot")
    lines = text.splitlines()
    assert lines[0] == '<?xml version="1.0" encoding="UTF-8"?>'
    assert lines[3] == '<robot name="bot">'
    assert lines[4:] == [
        '    <disable_collisions link1="a&amp;b" link2="c" reason="Adjacent"/>',
        '    <disable_collisions link1="c" link2="d" reason="Never"/> <!-- certified: clearance >= 0.0123 m -->',
        "</robot>",
    ]
    assert "100 samples, seed 3, backend coal" in lines[1]
    back = parse_srdf(text.encode(), "out.srdf")
    assert [(d.pair, d.reason) for d in back.disabled] == [(("a&b", "c"), "Adjacent"), (("c", "d"), "Never")]


def test_matrix_command_takes_the_semantics(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "robot.urdf").write_text(ROBOT)
    out = tmp_path / "pinocchio.srdf"
    args = [str(tmp_path / "robot.urdf"), "--samples", "100", "--no-config", "--semantics", "pinocchio"]
    assert main(["matrix", *args, "--srdf-out", str(out)]) == 0
    # base, rail, tag and post are one rigid body: 15 pairs less their 6
    assert capsys.readouterr().out.startswith("rig: 9 pairs of 6 links: 2 adjacent, 0 default, 1 always, ")
    text = out.read_text()
    assert "Pinocchio semantics" in text and 'link1="base" link2="tag"' not in text
    assert main(["matrix", *args[:-1], "moveit"]) == 0
    assert 'link1="base" link2="tag" reason="Default"' in capsys.readouterr().out
    assert main(["matrix", *args[:-1], "drake"]) == 2
    assert "semantics: invalid value 'drake'" in capsys.readouterr().err


def test_matrix_command_writes_the_same_srdf_twice(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "robot.urdf").write_text(ROBOT)
    out1, out2 = tmp_path / "one.srdf", tmp_path / "two.srdf"
    args = [str(tmp_path / "robot.urdf"), "--samples", "200", "--seed", "4", "--no-config"]
    assert main(["matrix", *args, "--srdf-out", str(out1)]) == 0
    summary = capsys.readouterr().out
    assert summary.startswith("rig: 15 pairs of 6 links: 5 adjacent, 1 default, 1 always, ")
    assert summary.rstrip().endswith(f"wrote {out1}")
    assert main(["matrix", *args, "--srdf-out", str(out2), "--backend", "fcl"]) == 0
    capsys.readouterr()
    one = out1.read_text()
    assert one.replace("backend coal", "backend fcl") == out2.read_text()
    assert '<disable_collisions link1="base" link2="tag" reason="Default"/>' in one
    assert 'link1="arm" link2="post"' not in one  # they can collide: not disabled
    assert main(["matrix", *args]) == 0  # without --srdf-out: the SRDF on stdout
    assert capsys.readouterr().out == one
    assert main(["matrix", *args, "--backend", "bullet"]) == 2
    assert "invalid" in capsys.readouterr().err


def proxied(size: float) -> str:
    """Part ``a`` sliding past part ``b``, each with a proxy link of a box of ``size`` fixed to it:
    capsule links in the style of Franka's ``*_sc``, which an SRDF collides in place of the parts."""
    return f"""<?xml version="1.0"?>
<robot name="rig">
  <link name="base"><collision><origin xyz="0 0 -1"/><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="a_slide" type="prismatic">
    <parent link="base"/><child link="a"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="a"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="b_mount" type="fixed"><parent link="base"/><child link="b"/><origin xyz="0.5 0 0"/></joint>
  <link name="b"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="a_sc_joint" type="fixed"><parent link="a"/><child link="a_sc"/></joint>
  <link name="a_sc"><collision><geometry><box size="{size} {size} {size}"/></geometry></collision></link>
  <joint name="b_sc_joint" type="fixed"><parent link="b"/><child link="b_sc"/></joint>
  <link name="b_sc"><collision><geometry><box size="{size} {size} {size}"/></geometry></collision></link>
</robot>
"""


PROXY_SRDF = """<?xml version="1.0" encoding="UTF-8"?>
<robot name="rig">
    <disable_collisions link1="a" link2="b" reason="Never"/>
    <disable_collisions link1="a" link2="b_sc" reason="Never"/>
    <disable_collisions link1="a_sc" link2="b" reason="Never"/>
    <disable_collisions link1="a" link2="a_sc" reason="Adjacent"/>
    <disable_collisions link1="b" link2="b_sc" reason="Adjacent"/>
</robot>
"""


@pytest.mark.parametrize(("size", "proxied_by"), [(0.12, ("a_sc", "b_sc")), (0.001, None)])
def test_a_pair_the_srdf_checks_through_proxy_links(
    tmp_path: Path, size: float, proxied_by: tuple[str, str] | None
) -> None:
    (tmp_path / "robot.urdf").write_text(proxied(size))
    (tmp_path / "robot.srdf").write_text(PROXY_SRDF)
    bundle = make_bundle(tmp_path / "robot.urdf", display_root=tmp_path)
    report = run_check(bundle, CheckOptions(srdf=tmp_path / "robot.srdf", sweep=False, samples=300, workers=1))
    [d] = [d for d in report.diagnostics if d.code == "GC410" and d.links == ("a", "b")]
    assert d.data["checked_through"] == (list(proxied_by) if proxied_by else None)
    if proxied_by:  # the proxies, enabled, hold the parts and collide where they do: nothing is lost
        assert d.severity.value == "info"
        assert d.message.endswith("through a_sc and b_sc, fixed to them, which collide there too: no contact is lost")
    else:  # proxies too small to stand for the parts
        assert d.severity.value == "error"
