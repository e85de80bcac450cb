"""The continuous-joint sweep: clipping casters, proven clearances, narrow contacts, torus sweeps."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report
from geomcheck.selfcollision.sweep import JointSweep, SweepSettings, merge_ranges, sweep_joint
from geomcheck.selfcollision.sweep_plan import sweep_groups
from geomcheck.thresholds import SelfCollisionThresholds

CORNER = math.hypot(0.18, 0.02)  # farthest point of the caster arm from the caster axis [m]


def polar(radius: float, degrees: float) -> tuple[float, float]:
    return radius * math.cos(math.radians(degrees)), radius * math.sin(math.radians(degrees))


def caster_urdf(post_radius: float, post_deg: float = 40.0) -> str:
    """A base (top plate + one post hanging down) and a caster whose housing is an arm 0.2 m long.

    The caster axis is at (0.2, 0.2); the arm reaches 0.18 m (corners 0.1811 m) from it at
    z 0.04..0.06; the 2 cm post stands at ``post_radius`` from the axis, at ``post_deg``."""
    px, py = polar(post_radius, post_deg)
    yaw = math.radians(post_deg)
    return f"""<?xml version="1.0"?>
<robot name="clip">
  <link name="base_link">
    <collision><origin xyz="0 0 0.3"/><geometry><box size="0.8 0.8 0.05"/></geometry></collision>
    <collision>
      <origin xyz="{0.2 + px} {0.2 + py} 0.05" rpy="0 0 {yaw}"/>
      <geometry><box size="0.02 0.02 0.1"/></geometry>
    </collision>
  </link>
  <joint name="caster_joint" type="continuous">
    <parent link="base_link"/><child link="caster_link"/>
    <origin xyz="0.2 0.2 0"/><axis xyz="0 0 1"/>
  </joint>
  <link name="caster_link">
    <collision><origin xyz="0.08 0 0.05"/><geometry><box size="0.2 0.04 0.02"/></geometry></collision>
  </link>
</robot>
"""


def narrow_urdf() -> str:
    """Caster A carries a thin wheel (2 mm, axis tangential) 0.25 m from its axis; caster B's housing
    is a 1 mm radial plate at 12.5 degrees around A's axis, overlapping the wheel's radii by 2 cm:
    they touch only within about +-0.35 degrees of 12.5, between the 1-degree grid points."""
    bx, by = polar(0.31, 12.5)
    return f"""<?xml version="1.0"?>
<robot name="narrow">
  <link name="base_link">
    <collision><origin xyz="0 0 0.5"/><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <joint name="a_caster_joint" type="continuous">
    <parent link="base_link"/><child link="a_caster_link"/><axis xyz="0 0 1"/>
  </joint>
  <link name="a_caster_link">
    <collision><geometry><box size="0.04 0.04 0.04"/></geometry></collision>
  </link>
  <joint name="a_wheel_joint" type="continuous">
    <parent link="a_caster_link"/><child link="a_wheel_link"/><origin xyz="0.25 0 0"/><axis xyz="0 1 0"/>
  </joint>
  <link name="a_wheel_link">
    <collision>
      <origin rpy="1.5707963267948966 0 0"/><geometry><cylinder radius="0.04" length="0.002"/></geometry>
    </collision>
  </link>
  <joint name="b_caster_joint" type="continuous">
    <parent link="base_link"/><child link="b_caster_link"/>
    <origin xyz="{bx} {by} 0" rpy="0 0 {math.radians(12.5)}"/><axis xyz="0 0 1"/>
  </joint>
  <link name="b_caster_link">
    <collision><geometry><box size="0.08 0.001 0.05"/></geometry></collision>
  </link>
</robot>
"""


def paddle_urdf() -> str:
    """A caster with a non-round 'wheel' (a 10 cm paddle spinning about y at (0.1, 0, 0.1)) and a post
    under the wheel's path at 90 degrees: the paddle reaches it only pointing down (wheel near
    +-90 degrees) with the caster near 90 degrees."""
    return """<?xml version="1.0"?>
<robot name="paddle">
  <link name="base_link">
    <collision><origin xyz="0 0.1 0.03"/><geometry><box size="0.02 0.02 0.06"/></geometry></collision>
  </link>
  <joint name="caster_joint" type="continuous">
    <parent link="base_link"/><child link="caster_link"/><axis xyz="0 0 1"/>
  </joint>
  <link name="caster_link">
    <collision><origin xyz="0 0 0.2"/><geometry><box size="0.02 0.02 0.02"/></geometry></collision>
  </link>
  <joint name="wheel_joint" type="continuous">
    <parent link="caster_link"/><child link="wheel_link"/><origin xyz="0.1 0 0.1"/><axis xyz="0 1 0"/>
  </joint>
  <link name="wheel_link">
    <collision><geometry><box size="0.1 0.01 0.01"/></geometry></collision>
  </link>
</robot>
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    return path


def check(tmp_path: Path, text: str, **options: object) -> Report:
    return run_check(make_bundle(write(tmp_path, text), display_root=tmp_path), CheckOptions(**options))  # type: ignore[arg-type]


def sweeps(
    tmp_path: Path, text: str, backend: str = "coal"
) -> tuple[dict[str, JointSweep], Kinematics, CollisionScene]:
    bundle = make_bundle(write(tmp_path, text), display_root=tmp_path)
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    scene = CollisionScene(robot, MeshStore(bundle), get_backend(backend))
    q0 = kin.default_configuration()
    adjacent = adjacent_pairs(robot, scene.links)
    settings = SweepSettings.from_thresholds(SelfCollisionThresholds())
    out = {g.joint.name: sweep_joint(kin, scene, q0, adjacent, settings, g) for g in sweep_groups(kin, scene, q0)}
    return out, kin, scene


def pair(result: JointSweep, a: str, b: str):
    return next(p for p in result.pairs if set(p.links) == {a, b})


def findings(report: Report, code: str):
    return [d for d in report.diagnostics if d.code == code]


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_caster_housing_that_clips_the_base_is_found_at_its_angle(tmp_path: Path, backend: str) -> None:
    report = check(tmp_path, caster_urdf(0.15), backend=backend)
    [gc401] = findings(report, "GC401")
    assert gc401.links == ("base_link", "caster_link")
    assert gc401.joint == "caster_joint"
    # parent and child: MoveIt's Setup Assistant, Gazebo and MuJoCo never collide them, no consumer meets it
    assert gc401.severity.value == "info" and "(parent and child: " in gc401.message
    assert gc401.location is not None and gc401.location.line == 15  # the arm's <collision>
    assert gc401.data["angle_deg"] == pytest.approx(40.0, abs=0.5)
    assert gc401.data["max_depth_mm"] == pytest.approx(30.0, abs=0.5)  # the 4 cm arm through the 2 cm post
    [[lo, hi]] = gc401.data["ranges_deg"]
    assert 25.0 < lo < 35.0 < 45.0 < hi < 55.0
    assert "shrink or move caster_link's or base_link's collision shapes" in gc401.help
    assert "from " in gc401.message and "deepest 30.0 mm at 40.0°" in gc401.message
    [section] = report.sections["sweeps"]
    assert section["joint"] == "caster_joint" and section["proven"] is True
    [entry] = section["pairs"]
    assert entry["links"] == ["base_link", "caster_link"] and entry["adjacent"] is True
    assert math.degrees(entry["min_angle"]) == pytest.approx(40.0, abs=0.5)
    assert len(entry["angles"]) == len(entry["clearance"]) == 360
    assert not findings(report, "GC403")  # clear at the default angle 0


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_caster_clearing_by_one_millimetre_is_proven_not_colliding(tmp_path: Path, backend: str) -> None:
    report = check(tmp_path, caster_urdf(CORNER + 0.001 + 0.01), backend=backend)
    assert not findings(report, "GC401") and not findings(report, "GC404")
    [warning] = findings(report, "GC402")  # below the 5 mm margin at some angles, far at others
    assert warning.severity.value == "info"  # a clearance, not a contact: no consumer sees it
    assert warning.data["min_clearance_mm"] == pytest.approx(1.0, abs=0.01)
    # the arm's corners point at the post at 40 -+ 6.34 degrees
    assert min(abs(warning.data["angle_deg"] - a) for a in (33.66, 46.34)) < 0.2
    entry = report.sections["sweeps"][0]["pairs"][0]
    assert entry["proven"] is True and entry["colliding_ranges"] == []
    # proven: no angle of the turn comes closer than the resolution (0.1 mm) below the minimum found
    assert 0.001 - 1e-4 - 1e-6 <= entry["clearance_bound"] <= entry["min_clearance"] <= 0.001 + 1e-6


def test_uniformly_far_adjacent_pair_gives_no_finding(tmp_path: Path) -> None:
    report = check(tmp_path, caster_urdf(0.35))
    assert not [d for d in report.diagnostics if d.code.startswith("GC4")]
    assert report.sections["sweeps"][0]["proven"] is True


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_narrow_contact_between_grid_points_is_found(tmp_path: Path, backend: str) -> None:
    result, kin, scene = sweeps(tmp_path, narrow_urdf(), backend)
    swept = result["a_caster_joint"]
    wheel = pair(swept, "a_wheel_link", "b_caster_link")
    assert wheel.colliding and wheel.proven
    [(lo, hi)] = wheel.colliding_ranges
    assert 12.0 < math.degrees(lo) < 12.5 < math.degrees(hi) < 13.0
    assert hi - lo < math.radians(1.0)
    # the grid points on either side are clear: the contact lies between them
    q = np.zeros((2, len(kin.joints)))
    q[:, kin.index("a_caster_joint")] = np.radians([12.0, 13.0])
    frames = kin.link_transforms(q, ["a_wheel_link", "b_caster_link"])
    for f in frames:
        assert scene.pair_distance("a_wheel_link", f[0], "b_caster_link", f[1]) > 5e-4  # tolerance: 1e-4
    # the wheel's own spin is checked only inside caster A: one pair, far apart (the broad phase proves it)
    own = result["a_wheel_joint"]
    assert own.group.scope == frozenset({"a_caster_link", "a_wheel_link"})
    assert own.pairs == () and own.far_pairs == 1 and own.proven


def test_narrow_contact_is_an_error_with_the_same_findings_on_both_backends(tmp_path: Path) -> None:
    reports = [check(tmp_path, narrow_urdf(), backend=b) for b in ("coal", "fcl")]
    keys = [[(d.code, d.links, d.joint) for d in r.diagnostics if d.code.startswith("GC4")] for r in reports]
    assert keys[0] == keys[1] == [("GC401", ("a_wheel_link", "b_caster_link"), "a_caster_joint")]
    # only continuous joints between the wheel and the other caster: they turn freely, nothing plans them apart
    assert {d.severity.value for r in reports for d in r.diagnostics if d.code == "GC401"} == {"error"}


def test_contact_that_a_limited_joint_between_the_links_can_leave_is_info(tmp_path: Path) -> None:
    # caster B on a revolute joint (an arm's joint, say): at its default angle the wheel of A clips it
    text = narrow_urdf().replace(
        '<joint name="b_caster_joint" type="continuous">', '<joint name="b_caster_joint" type="revolute">'
    )
    text = text.replace(
        '<axis xyz="0 0 1"/>\n  </joint>\n  <link name="b_caster_link">',
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>\n  </joint>\n'
        '  <link name="b_caster_link">',
    )
    assert 'type="revolute"' in text and "<limit" in text
    [gc401] = findings(check(tmp_path, text), "GC401")
    assert gc401.links == ("a_wheel_link", "b_caster_link") and gc401.severity.value == "info"
    assert gc401.message.endswith(
        "with b_caster_joint at the default pose: limited joints that a planner moves to part them"
    )


def test_round_wheels_are_exact_and_non_round_ones_are_swept_as_a_torus(tmp_path: Path) -> None:
    result, _, _ = sweeps(tmp_path, narrow_urdf())
    assert result["a_caster_joint"].group.dimensions == ("a_caster_joint",)  # the round wheel adds nothing
    assert [c.name for c in result["a_caster_joint"].group.children] == ["a_wheel_joint"]
    result, _, _ = sweeps(tmp_path, paddle_urdf())
    swept = result["caster_joint"]
    assert swept.group.dimensions == ("caster_joint", "wheel_joint")
    hit = pair(swept, "wheel_link", "base_link")
    assert hit.colliding and hit.proven
    assert any(lo <= math.pi / 2 <= hi for lo, hi in hit.colliding_ranges)
    assert all(lo > 0.5 and hi < 2.6 for lo, hi in hit.colliding_ranges)
    # with the paddle at its default angle (horizontal) it would have cleared the post
    assert hit.max_depth > 0


def test_a_two_joint_sweep_says_both_joints_turn_and_where_each_is_at_the_deepest(tmp_path: Path) -> None:
    """A caster's non-round paddle turns with the caster: a contact found with the paddle
    pointing down must say so (a judge reading "while caster_joint turns" kept the paddle
    horizontal and found the parts apart)."""
    report = check(tmp_path, paddle_urdf())
    [hit] = [d for d in findings(report, "GC401") if set(d.links or ()) == {"wheel_link", "base_link"}]
    assert hit.message.startswith(
        "wheel_link touches base_link while caster_joint and wheel_joint turn (every combination of their "
        "angles): in contact at caster_joint from "
    )
    deepest = re.search(r"deepest [0-9.]+ mm at caster_joint (-?[0-9.]+)°, wheel_joint (-?[0-9.]+)°", hit.message)
    assert deepest is not None, hit.message
    caster, wheel = (float(v) for v in deepest.groups())
    assert 30.0 < caster < 150.0 and abs(abs(wheel) - 90.0) < 45.0  # the paddle pointing down, over the post


def test_merge_ranges_wraps_through_180_degrees() -> None:
    assert merge_ranges([(3.0, 3.5), (-2.0, -1.0), (-1.0, -0.5)]) == (
        (-math.pi, 3.5 - 2 * math.pi),
        (-2.0, -0.5),
        (3.0, math.pi),
    )
    assert merge_ranges([(-math.pi - 0.01, math.pi - 0.01)]) == ((-math.pi, math.pi),)


def test_sweep_can_be_switched_off(tmp_path: Path) -> None:
    report = check(tmp_path, caster_urdf(0.15), sweep=False)
    assert "sweeps" not in report.sections
    assert not findings(report, "GC401")


@pytest.mark.corpus
def test_pr2_base_sweeps_every_caster_and_wheel(pr2_root: Path) -> None:
    bundle = make_bundle(pr2_root / "pr2_description" / "robots" / "pr2_base.urdf.xacro", search=[pr2_root])
    report = run_check(bundle, CheckOptions())
    sections = {s["joint"]: s for s in report.sections["sweeps"]}
    casters = [f"{c}_caster_rotation_joint" for c in ("fl", "fr", "bl", "br")]
    wheels = [f"{c}_caster_{s}_wheel_joint" for c in ("fl", "fr", "bl", "br") for s in ("l", "r")]
    assert sorted(sections) == sorted(casters + wheels)
    assert all(s["proven"] for s in sections.values())
    for caster in casters:
        # caster box and both wheels against the base's thin collision box, 8.5 / 8.7 cm below it
        entry = {tuple(p["links"]): p for p in sections[caster]["pairs"]}
        prefix = caster.replace("_rotation_joint", "")
        assert entry[("base_link", f"{prefix}_rotation_link")]["min_clearance"] == pytest.approx(0.0853, abs=1e-4)
        assert entry[("base_link", f"{prefix}_l_wheel_link")]["min_clearance"] == pytest.approx(0.0870, abs=1e-4)
    for wheel in wheels:
        # a round wheel spinning on its axis: one query per pair settles the whole turn
        assert all(p["queries"] == 1 and len(p["clearance"]) == 360 for p in sections[wheel]["pairs"])
    assert not [d for d in report.diagnostics if d.code in ("GC401", "GC402", "GC403", "GC404")]


def test_progress_is_heard_only_by_a_listener(capsys: pytest.CaptureFixture[str]) -> None:
    from geomcheck import progress

    with progress.Progress(3, "sweep", unit="joint") as bar:  # nobody listens: nothing done
        assert not bar.enabled
        bar.advance(note="caster_joint")
    assert capsys.readouterr() == ("", "")
    heard: list[progress.StageProgress] = []
    with progress.listening(heard.append):
        progress.stage("selfcollision", 5, 8)
        with progress.Progress(3, "sweep", unit="joint") as bar:
            assert bar.enabled
            bar.advance(note="caster_joint")
    assert [(p.name, round(p.fraction, 3)) for p in heard] == [("selfcollision", 0.0), ("selfcollision", 0.333)]
    assert capsys.readouterr() == ("", "")


def test_report_is_deterministic(tmp_path: Path) -> None:
    from geomcheck.report import render

    first = render(check(tmp_path, narrow_urdf()), "json")
    assert render(check(tmp_path, narrow_urdf()), "json") == first


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_mesh_housing_gives_the_primitive_answer(tmp_path: Path, backend: str) -> None:
    import trimesh

    trimesh.creation.box(extents=(0.2, 0.04, 0.02)).export(tmp_path / "arm.stl")
    text = caster_urdf(0.15).replace('<box size="0.2 0.04 0.02"/>', '<mesh filename="arm.stl"/>')
    result, _, _ = sweeps(tmp_path, text, backend)
    hit = pair(result["caster_joint"], "caster_link", "base_link")
    [(lo, hi)] = hit.colliding_ranges
    assert math.degrees(lo) == pytest.approx(27.7, abs=0.2) and math.degrees(hi) == pytest.approx(52.3, abs=0.2)
    assert hit.max_depth == pytest.approx(0.03, abs=1e-3) and hit.proven  # the convex hull's depth
    far = caster_urdf(CORNER + 0.003 + 0.01).replace('<box size="0.2 0.04 0.02"/>', '<mesh filename="arm.stl"/>')
    clear = pair(sweeps(tmp_path, far, backend)[0]["caster_joint"], "caster_link", "base_link")
    assert not clear.colliding and clear.proven
    assert clear.min_clearance == pytest.approx(0.003, abs=1e-6)


def test_query_budget_exhausted_is_reported_unproven(tmp_path: Path) -> None:
    from geomcheck.thresholds import Thresholds

    tight = Thresholds().with_overrides({"self_collision": {"sweep_max_queries": 400}})
    report = check(tmp_path, caster_urdf(CORNER + 0.001 + 0.01), thresholds=tight)
    [unproven] = findings(report, "GC404")
    assert unproven.links == ("base_link", "caster_link") and unproven.data["queries"] <= 400
    assert report.sections["sweeps"][0]["proven"] is False
    # 1 mm found: the parts graze, and the model should say whether they touch
    assert unproven.severity.value == "warning" and unproven.data["min_clearance_mm"] < 5.0


def test_a_pair_undecided_far_from_contact_is_info(tmp_path: Path) -> None:
    """Minitaur's two-joint leg sweeps run out of queries with 17 mm found: not a graze, nothing
    to change in the file."""
    from dataclasses import replace

    from geomcheck.checks.selfcollision import unproven_finding

    result, _, _ = sweeps(tmp_path, caster_urdf(CORNER + 0.017 + 0.01))
    swept = result["caster_joint"]
    undecided = replace(pair(swept, "caster_link", "base_link"), proven=False, queries=20000)
    far = unproven_finding(swept, undecided, None, {}, margin=0.005)
    assert far.severity.value == "info" and far.code == "GC404"
    assert far.message.startswith(
        "the sweep of caster_joint could not decide caster_link / base_link over the whole turn within 20000 "
        "distance queries; smallest clearance found 17.0 mm"
    )
    assert far.message.endswith("(beyond the 5.0 mm margin: the parts do not graze)")
    close = unproven_finding(swept, replace(undecided, min_clearance=0.001), None, {}, margin=0.005)
    assert close.severity.value == "warning" and "margin" not in close.message


def test_the_check_s_sweeps_share_one_budget_and_skip_the_joints_it_does_not_reach(tmp_path: Path) -> None:
    """A robot whose legs are continuous joints (PyBullet's mini cheetah: 12 of them, 34 mesh
    pairs in a sweep) is bounded: once the check's queries are spent, the joints left are not
    swept and the report says so for each of them."""
    from geomcheck.thresholds import Thresholds

    full = check(tmp_path, narrow_urdf())
    assert [s["joint"] for s in full.sections["sweeps"]] == ["a_caster_joint", "a_wheel_joint", "b_caster_joint"]
    assert [s for s in full.skipped if s.check == "sweep"] == []
    [first] = full.sections["sweeps"][0]["pairs"]
    assert first["queries"] > 360  # its first grid, then halvings near the 1 mm plate
    tight = Thresholds(self_collision=SelfCollisionThresholds(sweep_max_queries_total=200))
    bounded = check(tmp_path, narrow_urdf(), thresholds=tight)
    [swept] = bounded.sections["sweeps"]
    [cut] = swept["pairs"]
    assert (swept["joint"], cut["links"]) == ("a_caster_joint", first["links"])
    assert 360 <= cut["queries"] < first["queries"]  # the first grid is asked whatever the budget
    why = (
        "not swept: the check's sweeps spent their budget of 200 distance queries (one between meshes counting 10) "
        "on the joints before it"
    )
    assert [(s.subject, s.reason) for s in bounded.skipped if s.check == "sweep"] == [
        ("a_wheel_joint", why),
        ("b_caster_joint", why),
    ]


def test_a_query_between_meshes_weighs_as_ten_in_the_check_s_budget(tmp_path: Path) -> None:
    """Against primitives a query costs about 10 us, between meshes of thousands of triangles
    about 0.4 ms: the check's budget counts what the sweeps cost, not how many answers they got."""
    import trimesh

    from geomcheck.selfcollision.sweep import weight_of

    trimesh.creation.icosphere(subdivisions=3, radius=0.05).export(tmp_path / "ball.stl")
    text = caster_urdf(0.15).replace(
        '<collision><origin xyz="0.08 0 0.05"/><geometry><box size="0.2 0.04 0.02"/></geometry></collision>',
        '<collision><origin xyz="0.08 0 0.05"/><geometry><mesh filename="ball.stl"/></geometry></collision>',
    )
    _, _, scene = sweeps(tmp_path, text)
    settings = SweepSettings.from_thresholds(SelfCollisionThresholds())
    assert (settings.max_queries_total, settings.mesh_query_weight) == (1_000_000, 10)
    assert weight_of(scene, settings, ("base_link", "caster_link")) == 10
    _, _, boxes = sweeps(tmp_path, caster_urdf(0.15))
    assert weight_of(boxes, settings, ("base_link", "caster_link")) == 1


def test_a_contact_whose_search_stopped_is_one_finding_saying_its_ranges_may_be_incomplete(tmp_path: Path) -> None:
    """The paddle's contact is found, but 1,500 queries do not decide every angle of the caster
    and the paddle: one GC401 says so; no GC404 restates the same pair."""
    from geomcheck.thresholds import Thresholds

    few = Thresholds(self_collision=SelfCollisionThresholds(sweep_max_queries=1500))
    report = check(tmp_path, paddle_urdf(), thresholds=few)
    [gc401] = [d for d in findings(report, "GC401") if set(d.links or ()) == {"wheel_link", "base_link"}]
    stopped = re.search(
        r"; the search stopped after (\d+) distance queries, before every angle was decided: more contact may lie "
        r"outside these ranges$",
        gc401.message,
    )
    assert stopped is not None, gc401.message
    assert gc401.data["proven"] is False and gc401.data["queries"] == int(stopped.group(1)) <= 2 * 1500
    assert [d.links for d in findings(report, "GC404") if set(d.links or ()) == {"wheel_link", "base_link"}] == []
    decided = check(tmp_path, paddle_urdf())
    [whole] = [d for d in findings(decided, "GC401") if set(d.links or ()) == {"wheel_link", "base_link"}]
    assert "proven" not in whole.data and "the search stopped" not in whole.message


def test_a_pair_cut_short_by_the_check_s_shared_budget_is_info(tmp_path: Path) -> None:
    from geomcheck.thresholds import Thresholds

    tight = Thresholds(self_collision=SelfCollisionThresholds(sweep_max_queries_total=200))
    report = check(tmp_path, narrow_urdf(), thresholds=tight)
    [gc404] = findings(report, "GC404")
    assert (gc404.severity.value, gc404.joint, gc404.data["budget_shared"]) == ("info", "a_caster_joint", True)
    assert gc404.message.endswith(
        "(the check's budget of sweep queries, shared by its continuous joints, cut this pair's)"
    )
    alone = findings(check(tmp_path, narrow_urdf()), "GC404")
    assert alone == []  # with its own budget the pair is decided


POSTS_URDF = """<?xml version="1.0"?>
<robot name="posts">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="near_post_joint" type="fixed"><parent link="base"/><child link="near_post"/>
    <origin xyz="0.4 0 0"/></joint>
  <link name="near_post"><collision><geometry><cylinder radius="0.05" length="0.3"/></geometry></collision></link>
  <joint name="far_post_joint" type="fixed"><parent link="base"/><child link="far_post"/>
    <origin xyz="-0.45 0 0"/></joint>
  <link name="far_post"><collision><geometry><cylinder radius="0.05" length="0.3"/></geometry></collision></link>
  <joint name="spin" type="continuous"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/></joint>
  <link name="arm"><collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.04 0.04"/></geometry>
    </collision></link>
</robot>
"""


def test_one_turn_meeting_several_parts_is_one_finding(tmp_path: Path) -> None:
    # an arm written continuous sweeps into two posts: one cause (a joint that cannot turn a full
    # turn, or geometry that misses the parts), one error naming both pairs; the other pair is info
    report = check(tmp_path, POSTS_URDF)
    contacts = findings(report, "GC401")
    loud = [d for d in contacts if d.severity.value != "info"]
    assert [(d.links, d.severity.value) for d in loud] == [(("arm", "near_post"), "error")]
    assert loud[0].message.endswith("; 1 more pairs of parts meet in the same turn: arm / far_post")
    assert loud[0].help.startswith("If spin cannot turn a full turn, declare it revolute with the range it has")
    assert loud[0].data["also_pairs"] == [["arm", "far_post"]]
    [quiet] = [d for d in contacts if d.severity.value == "info"]
    assert quiet.links == ("arm", "far_post") and quiet.message.endswith(
        "(reported with arm / near_post: the same turn)"
    )


def test_a_two_joint_sweep_halves_no_cell_within_a_range_already_in_contact(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the ranges reported lie along the swept joint: a cell whose angles of it are already in
    # contact (at some angle of the joint below) changes nothing when halved further
    from geomcheck.selfcollision import sweep as sweep_module

    found, _, _ = sweeps(tmp_path, paddle_urdf())
    pruned = pair(found["caster_joint"], "wheel_link", "base_link")
    monkeypatch.setattr(
        sweep_module._Sweeper, "within_contact", staticmethod(lambda s, rows: np.zeros(len(rows), dtype=bool))
    )
    found, _, _ = sweeps(tmp_path, paddle_urdf())
    halved = pair(found["caster_joint"], "wheel_link", "base_link")
    assert pruned.colliding and pruned.colliding_ranges == halved.colliding_ranges
    assert pruned.max_depth == pytest.approx(halved.max_depth, abs=1e-4)
    assert pruned.queries < halved.queries
