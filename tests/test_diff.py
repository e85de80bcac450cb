"""``geomcheck diff``: matching findings across two runs, and the git gate on the bundled example."""

from __future__ import annotations

import html
import json
import re
import shutil
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

from geomcheck.cli import main
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.diff import compare, corresponding_roots, diff_report, metric_direction, translate_about, worsened
from geomcheck.gitrev import map_into
from geomcheck.model import SourceLocation
from geomcheck.report import FORMATS
from geomcheck.report.model import Report, RobotSummary
from tests.gittools import git

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pr2_base"
ROOT_FILE = Path("pr2_base") / "robots" / "pr2_base.urdf.xacro"


def diag(
    code: str,
    link: str,
    *,
    line: int = 1,
    sev: Severity = Severity.ERROR,
    data: dict[str, Any] | None = None,
    message: str = "m",
) -> Diagnostic:
    return Diagnostic(
        code,
        "x",
        sev,
        message,
        "h",
        link=link,
        about="collision[0]",
        location=SourceLocation("r.urdf", line),
        data=data or {},
    )


# --- comparison ----------------------------------------------------------------------------


def test_new_fixed_and_unchanged_by_fingerprint_not_line() -> None:
    base = [diag("GC301", "a", line=10), diag("GC301", "b", line=20)]
    head = [diag("GC301", "a", line=99), diag("GC301", "c", line=30)]
    result = compare(base, head)
    assert [d.link for d in result.new] == ["c"]
    assert [d.link for d in result.fixed] == ["b"]
    assert result.unchanged == 1
    assert result.regressions == ()


def test_duplicate_fingerprints_match_as_a_multiset() -> None:
    result = compare([diag("GC301", "a")], [diag("GC301", "a"), diag("GC301", "a")])
    assert len(result.new) == 1 and result.unchanged == 1


def test_metric_regression_beyond_tolerance() -> None:
    base = [diag("GC301", "a", data={"coverage": 0.80, "protrusion_max_mm": 40.0, "label": "x"})]
    head = [diag("GC301", "a", data={"coverage": 0.60, "protrusion_max_mm": 40.2, "label": "y"})]
    (regression,) = compare(base, head).regressions
    assert [(m.name, m.before, m.after) for m in regression.metrics] == [("coverage", 0.80, 0.60)]
    assert regression.describe() == "GC301 link a: coverage 0.8 -> 0.6"


def test_improvement_and_noise_are_not_regressions() -> None:
    base = [diag("GC402", "a", data={"min_clearance": 0.0100, "min_clearance_mm": 10.0})]
    head = [diag("GC402", "a", data={"min_clearance": 0.00999, "min_clearance_mm": 9.99})]
    assert compare(base, head).regressions == ()
    base = [diag("GC301", "a", data={"coverage": 0.60, "protrusion_max_mm": 40.0})]
    head = [diag("GC301", "a", data={"coverage": 0.65, "protrusion_max_mm": 30.0})]
    result = compare(base, head)
    assert result.regressions == () and result.unchanged == 1


def test_severity_rise_is_a_regression() -> None:
    (regression,) = compare([diag("GC301", "a", sev=Severity.WARNING)], [diag("GC301", "a")]).regressions
    assert regression.severity_before is Severity.WARNING
    assert regression.describe() == "GC301 link a: severity warning -> error"


@pytest.mark.parametrize(
    ("code", "name", "direction"),
    [
        ("GC301", "coverage", "higher"),
        ("GC301", "protrusion_max_mm", "lower"),
        ("GC301", "protrusion_p95_mm", "lower"),
        ("GC302", "slack", "lower"),
        ("GC303", "mesh_inside", "higher"),
        ("GC303", "in_hull", "higher"),
        ("GC303", "outside_own_mesh", "lower"),
        ("GC306", "reverse_coverage", "higher"),
        ("GC306", "surface_distance_max_mm", "lower"),
        ("GC306", "overshoot_max_mm", "lower"),
        ("GC401", "min_clearance", "higher"),
        ("GC401", "max_depth_mm", "lower"),
        ("GC402", "min_clearance_mm", "higher"),
        ("GC403", "depth", "lower"),
        ("GC412", "fraction", "lower"),
        ("GC504", "excess", "lower"),
        ("GC506", "distance", "lower"),
        ("GC507", "mass_ratio", "lower"),
        ("GC508", "density", "lower"),
        # declared, but descriptive: never a regression
        ("GC301", "tolerance", None),
        ("GC301", "hull_volume", None),
        ("GC401", "angle_deg", None),
        ("GC402", "margin_mm", None),
        ("GC502", "mass", "higher"),
        ("GC505", "radius_of_gyration", "lower"),
        ("GC505", "moments", None),
        ("GC508", "mass_share", None),
        # not declared by that rule, or a rule this version does not know
        ("GC508", "coverage", None),
        ("GC301", "min_clearance", None),
        ("GC999", "coverage", None),
    ],
)
def test_metric_direction_is_the_rules_declaration(code: str, name: str, direction: str | None) -> None:
    assert metric_direction(code, name) == direction


def test_metrics_the_name_guess_did_not_compare_now_regress() -> None:
    """The key names used to decide: "surface_distance_max_mm" matched no word list, so a
    collision mesh drifting further off its visual, a triangle inequality broken by more, or
    an element sliding further off its own mesh were never regressions."""
    base = [
        diag("GC306", "a", data={"surface_distance_max_mm": 30.0, "overshoot_max_mm": 25.0, "slack": 1.2}),
        diag("GC504", "b", data={"excess": 0.010, "mass": 2.0}),
        diag("GC303", "c", data={"outside_own_mesh": 0.60, "link_coverage": 0.95, "tolerance": 0.01}),
    ]
    head = [
        diag("GC306", "a", data={"surface_distance_max_mm": 60.0, "overshoot_max_mm": 40.0, "slack": 1.2}),
        diag("GC504", "b", data={"excess": 0.020, "mass": 4.0}),
        diag("GC303", "c", data={"outside_own_mesh": 0.80, "link_coverage": 0.95, "tolerance": 0.002}),
    ]
    described = sorted(r.describe() for r in compare(base, head).regressions)
    assert described == [
        "GC303 link c: outside_own_mesh 0.6 -> 0.8",
        "GC306 link a: overshoot_max_mm 25 -> 40, surface_distance_max_mm 30 -> 60",
        "GC504 link b: excess 0.01 -> 0.02",
    ]


def test_metrics_measured_per_direction_worsen_when_any_direction_does() -> None:
    """GC505's radius of gyration is one number per direction: a tensor raised by a third is
    a regression (0.495 -> 0.570 m against a 0.399 m reach), a reordered or shorter list is
    not compared, and the numbers are named as lists."""
    before = {"radius_of_gyration": [0.495, 0.3, 0.2], "reach": [0.399, 0.4, 0.3]}
    after = {"radius_of_gyration": [0.570, 0.3, 0.2], "reach": [0.399, 0.4, 0.3]}
    (regression,) = compare([diag("GC505", "base", data=before)], [diag("GC505", "base", data=after)]).regressions
    assert regression.describe() == "GC505 link base: radius_of_gyration [0.495, 0.3, 0.2] -> [0.57, 0.3, 0.2]"
    assert regression.metrics[0].to_dict() == {
        "name": "radius_of_gyration",
        "before": [0.495, 0.3, 0.2],
        "after": [0.57, 0.3, 0.2],
    }
    assert not worsened("GC505", "radius_of_gyration", [0.57, 0.3, 0.2], [0.495, 0.3, 0.2], 0.01)
    assert not worsened("GC505", "radius_of_gyration", [0.495, 0.3], [0.57, 0.3, 0.2], 0.01)
    assert not worsened("GC505", "radius_of_gyration", [], [], 0.01)
    assert worsened("GC503", "principal_moments", [-0.01, 0.2, 0.3], [-0.05, 0.2, 0.3], 0.01)


def test_every_measuring_rule_declares_which_way_is_worse() -> None:
    """Every fit, self-collision and inertia rule whose findings carry numbers declares of at
    least one of them which way it gets worse: otherwise ``geomcheck diff`` could never call
    such a finding regressed, whatever happened to it."""
    from geomcheck.rules import all_rules

    measuring = [r for r in all_rules() if r.code[:3] in ("GC3", "GC4", "GC5") and any(m.numeric for m in r.metrics)]
    assert len(measuring) >= 20
    undirected = [r.code for r in measuring if all(m.better == "none" for m in r.metrics if m.numeric)]
    assert undirected == []


def test_non_numbers_never_worsen() -> None:
    assert not worsened("GC301", "coverage", True, False, 0.01)
    assert not worsened("GC301", "coverage", "0.9", "0.1", 0.01)
    assert not worsened("GC301", "coverage", float("nan"), 0.1, 0.01)
    assert worsened("GC301", "coverage", 0.9, 0.1, 0.01)


def test_diff_report_keeps_new_findings_and_describes_the_rest() -> None:
    head = Report(
        RobotSummary("r", "r.urdf", 2, 1),
        (diag("GC301", "a"), diag("GC302", "b", sev=Severity.WARNING)),
        "0.1.0",
        "2026-01-01T00:00:00Z",
    )
    out = diff_report([diag("GC302", "b", sev=Severity.WARNING), diag("GC501", "c")], head, "main")
    assert [d.code for d in out.diagnostics] == ["GC301"]
    section = out.sections["diff"]
    assert section["new"] == 1 and section["unchanged"] == 1
    assert [d["code"] for d in section["fixed"]] == ["GC501"]
    assert out.failed


def test_a_new_member_of_a_group_the_base_has_is_reported_at_its_own_severity() -> None:
    # the base has upper's missing mass; the head adds wheel's, grouped under upper's finding (info)
    upper = diag("GC501", "upper")
    wheel = diag("GC501", "wheel").grouped_under(upper, " (reported with upper)")
    assert wheel.severity is Severity.INFO and wheel.data["severity_alone"] == "error"
    head = Report(RobotSummary("r", "r.urdf", 3, 2), (upper, wheel), "0.1.0", "2026-01-01T00:00:00Z")
    out = diff_report([upper], head, "main")
    [new] = out.diagnostics
    assert (new.link, new.severity) == ("wheel", Severity.ERROR)
    assert new.message.endswith("(its group is in main; this part is not)")
    assert out.failed


def test_corresponding_roots_and_translated_about(tmp_path: Path) -> None:
    old = tmp_path / "v1" / "pkg" / "robots" / "r.xacro"
    new = tmp_path / "v2" / "pkg" / "robots" / "r.xacro"
    assert corresponding_roots(old, new) == (tmp_path / "v1", tmp_path / "v2")
    legacy = Diagnostic("GC103", "x", Severity.WARNING, "m", "h", about="v1/pkg/urdf/a.xacro")
    (moved,) = translate_about([legacy], "v1", "v2", lambda rest: rest == "pkg/urdf/a.xacro")
    assert moved.about == "v2/pkg/urdf/a.xacro"
    assert translate_about([legacy], "v3", "v2", lambda rest: True) == (legacy,)
    assert translate_about([legacy], "v1", "v2", lambda rest: False) == (legacy,)
    (here,) = translate_about([replace(legacy, about="pkg/a.xacro")], ".", "../v2", lambda rest: True)
    assert here.about == "../v2/pkg/a.xacro"


def test_map_into_keeps_outside_paths(tmp_path: Path) -> None:
    root, tree = tmp_path / "repo", tmp_path / "tree"
    (root / "pkg").mkdir(parents=True)
    assert map_into(root / "pkg", root.resolve(), tree) == tree / "pkg"
    assert map_into(tmp_path / "elsewhere", root.resolve(), tree) == tmp_path / "elsewhere"


# --- the git gate on the bundled example ----------------------------------------------------


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A git repository holding a copy of the bundled example, one commit, as the cwd."""
    if not (EXAMPLE / "robots" / "pr2_base.urdf.xacro").is_file():
        pytest.skip("the bundled example examples/pr2_base is not there yet")
    root = tmp_path / "repo"
    shutil.copytree(EXAMPLE, root / "pr2_base")
    git(root, "init", "-q", "-b", "main")
    git(root, "add", "-A")
    git(root, "commit", "-q", "-m", "example")
    monkeypatch.chdir(root)
    return root


def run_diff(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any]]:
    status = main(["diff", "--format", "json", *argv])
    captured = capsys.readouterr()
    assert status != 2, captured.err
    return status, json.loads(captured.out)


def shrink_laser_box(repo: Path) -> None:
    """Shrink the laser's collision box to 10 x 10 x 5 mm: far too small for its mesh."""
    laser = repo / "pr2_base" / "urdf" / "laser.urdf.xacro"
    text = laser.read_text()
    for name, size in (("x", "0.01"), ("y", "0.01"), ("z", "0.005")):
        text, count = re.subn(
            rf'<property name="laser_size_{name}" value="[^"]*" />',
            f'<property name="laser_size_{name}" value="{size}" />',
            text,
        )
        assert count == 1
    laser.write_text(text)


def reformat(path: Path) -> None:
    """Re-indent, reverse every element's attributes and every link's children, and add
    comments: the same robot in a different text."""
    tree = etree.parse(str(path), etree.XMLParser(remove_blank_text=True))
    for element in tree.getroot().iter():
        if not isinstance(element.tag, str):
            continue
        items = list(element.attrib.items())
        element.attrib.clear()
        for key, value in reversed(items):
            element.set(key, value)
        if element.tag == "link" and len(element):
            children = list(element)
            for child in children:
                element.remove(child)
            for child in reversed(children):
                element.append(child)
            element.insert(0, etree.Comment(" reordered by the reformat test "))
    tree.getroot().insert(0, etree.Comment(" reformatted:\n     four-space indent, attributes reversed "))
    etree.indent(tree, space="    ")
    path.write_bytes(etree.tostring(tree, xml_declaration=True, encoding="utf-8") + b"\n\n")


def test_shrunk_collision_box_is_exactly_one_new_finding(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shrink_laser_box(repo)
    git(repo, "commit", "-q", "-am", "shrink the laser box")
    status, report = run_diff(capsys, "--base", "HEAD~1", str(ROOT_FILE))
    assert status == 1
    (finding,) = report["diagnostics"]
    assert finding["code"].startswith("GC3")
    assert finding["severity"] == "error"
    assert finding["link"] == "base_laser_link"
    assert finding["about"] == "collision[0]"
    assert finding["location"]["file"] == "pr2_base/urdf/laser.urdf.xacro"
    section = report["sections"]["diff"]
    assert section["base"].startswith("HEAD~1 (")
    assert section["new"] == 1 and section["fixed"] == []


def test_reformatting_reordering_and_comments_change_nothing(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    for path in sorted((repo / "pr2_base").rglob("*.xacro")):
        reformat(path)
    git(repo, "commit", "-q", "-am", "reformat")
    assert "reordered by the reformat test" in (repo / "pr2_base" / "urdf" / "laser.urdf.xacro").read_text()
    status, report = run_diff(capsys, "--base", "HEAD~1", str(ROOT_FILE))
    section = report["sections"]["diff"]
    assert (status, report["diagnostics"], section["fixed"], section["regressions"]) == (0, [], [], [])
    assert section["unchanged"] > 0


def test_working_tree_changes_are_compared_with_head(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shrink_laser_box(repo)  # not committed
    status, report = run_diff(capsys, "--base", "HEAD", str(ROOT_FILE))
    assert status == 1
    (finding,) = report["diagnostics"]
    assert finding["link"] == "base_laser_link"


def test_concise_output_and_exit_zero(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shrink_laser_box(repo)
    assert main(["diff", "--base", "HEAD", str(ROOT_FILE), "--format", "concise", "--exit-zero"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("pr2_base/urdf/laser.urdf.xacro:")
    assert "link base_laser_link" in lines[0]
    assert "; against HEAD (" in lines[-1]
    assert lines[-1].endswith("): 1 new, 0 fixed, 0 regressed -> FAIL (fail on error)")


def test_fixing_the_box_is_a_fixed_finding(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shrink_laser_box(repo)
    git(repo, "commit", "-q", "-am", "shrink")
    git(repo, "revert", "--no-edit", "HEAD")
    status, report = run_diff(capsys, "--base", "HEAD~1", str(ROOT_FILE))
    assert status == 0 and report["diagnostics"] == []
    (fixed,) = report["sections"]["diff"]["fixed"]
    assert fixed["link"] == "base_laser_link"


def test_two_paths(repo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    old = tmp_path / "old"
    shutil.copytree(repo / "pr2_base", old / "pr2_base")
    shrink_laser_box(repo)
    status, report = run_diff(capsys, str(old / ROOT_FILE), str(ROOT_FILE))
    assert status == 1
    assert [d["link"] for d in report["diagnostics"]] == ["base_laser_link"]


def test_new_file_has_every_finding_new(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copytree(repo / "pr2_base", repo / "copy")
    status, report = run_diff(capsys, "--base", "HEAD", "copy/robots/pr2_base.urdf.xacro")
    assert report["sections"]["diff"]["base_exists"] is False
    assert len(report["diagnostics"]) == sum(report["summary"].values()) > 0
    assert status == 1


def test_unknown_revision_is_a_usage_error(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["diff", "--base", "no-such-branch", str(ROOT_FILE)]) == 2
    assert "unknown git revision 'no-such-branch'" in capsys.readouterr().err


def test_outside_a_repository_is_a_usage_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    description = tmp_path / "r.urdf"
    description.write_text('<robot name="r"><link name="a"/></robot>')
    assert main(["diff", "--base", "HEAD", str(description)]) == 2
    assert "git rev-parse --show-toplevel failed" in capsys.readouterr().err


def test_wrong_number_of_paths_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["diff", "a.urdf"]) == 2
    assert "two descriptions" in capsys.readouterr().err


def test_links_out_of_the_tree_are_not_exported(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from geomcheck.gitrev import exported_tree, repo_root, resolve_commit

    root = tmp_path / "repo"
    root.mkdir()
    (root / "r.urdf").write_text('<robot name="r"><link name="a"/></robot>')
    (root / "outside").symlink_to("/etc")
    (root / "inside").symlink_to("r.urdf")
    git(root, "init", "-q")
    git(root, "add", "-A")
    git(root, "commit", "-q", "-m", "links")
    top = repo_root(root / "r.urdf")
    with exported_tree(top, resolve_commit(top, "HEAD")) as tree:
        assert (tree / "r.urdf").is_file() and (tree / "inside").is_symlink()
        assert not (tree / "outside").exists()


@pytest.mark.corpus
def test_fingerprints_survive_reformatting_the_2009_pr2(
    pr2_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The legacy-syntax PR2 base, reformatted, reordered and commented, has the same findings."""
    monkeypatch.chdir(tmp_path)
    old, new = tmp_path / "old" / "pr2_description", tmp_path / "new" / "pr2_description"
    shutil.copytree(pr2_root / "pr2_description", old)
    shutil.copytree(pr2_root / "pr2_description", new)
    for path in sorted(new.rglob("*.xacro")):
        reformat(path)
    root = Path("robots") / "pr2_base.urdf.xacro"
    status, report = run_diff(capsys, str(old.relative_to(tmp_path) / root), str(new.relative_to(tmp_path) / root))
    section = report["sections"]["diff"]
    assert (report["diagnostics"], section["fixed"], section["regressions"]) == ([], [], [])
    assert section["unchanged"] > 0 and status == 0


# --- the gate fails on regressions and says why in every format --------------------------------


def move_base_box_off_the_mesh(repo: Path) -> None:
    """Lift the base collision box 0.3 m: the base_link finding (an error) stays, with worse numbers."""
    base = repo / "pr2_base" / "urdf" / "base.urdf.xacro"
    text = base.read_text()
    old = '<origin xyz="0 0 ${base_size_z-base_collision_size_z/2}" rpy="0 0 0" />'
    assert text.count(old) == 1
    base.write_text(text.replace(old, '<origin xyz="0 0 ${base_size_z-base_collision_size_z/2+0.3}" rpy="0 0 0" />'))


def shrink_caster_boxes(repo: Path) -> None:
    """The caster collision boxes to 2 x 2 x 1 mm: their findings rise from warning to error."""
    base = repo / "pr2_base" / "urdf" / "base.urdf.xacro"
    text = base.read_text()
    assert text.count('<box size="0.192 0.164 0.013" />') == 1
    base.write_text(text.replace('<box size="0.192 0.164 0.013" />', '<box size="0.002 0.002 0.001" />'))


def test_a_finding_raised_to_error_fails_the_gate_by_default(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shrink_caster_boxes(repo)
    status, report = run_diff(capsys, "--base", "HEAD", str(ROOT_FILE))
    assert status == 1
    regressions = report["sections"]["diff"]["regressions"]
    # the caster macro's box: one finding for the four casters, raised from warning to error
    (raised,) = [r["diagnostic"] for r in regressions if r["severity_before"] == "warning"]
    assert [raised["link"], *raised["data"]["also"]] == [f"{c}_caster_rotation_link" for c in ("bl", "br", "fl", "fr")]
    gated = [d for d in report["diagnostics"] if "regressed since HEAD" in d["message"]]
    (caster,) = [d for d in gated if d["severity"] == "error" and d["link"] == raised["link"]]
    assert "severity warning -> error" in caster["message"]
    assert report["verdict"] == "fail"


def test_worse_numbers_on_an_error_fail_the_gate(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    move_base_box_off_the_mesh(repo)
    status, report = run_diff(capsys, "--base", "HEAD", str(ROOT_FILE))
    assert status == 1
    (regression,) = [r for r in report["sections"]["diff"]["regressions"] if r["diagnostic"]["link"] == "base_link"]
    assert regression["severity_before"] == "error"
    names = {m["name"] for m in regression["metrics"]}
    assert names & {"coverage", "surface_coverage", "max_protrusion"}
    for m in regression["metrics"]:
        assert m["before"] != pytest.approx(m["after"], rel=0.01)


def test_the_gate_can_be_told_to_ignore_regressions(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    move_base_box_off_the_mesh(repo)
    status, report = run_diff(capsys, "--base", "HEAD", "--no-fail-on-regression", str(ROOT_FILE))
    assert (status, report["diagnostics"]) == (0, [])
    assert report["sections"]["diff"]["gated"] is False
    assert [r["diagnostic"]["link"] for r in report["sections"]["diff"]["regressions"]] == ["base_link"]


def raise_wheel_tensor(repo: Path) -> None:
    """The wheels' inertia tensor (already flagged GC505: too large for a 0.079 m wheel) raised by a third."""
    base = repo / "pr2_base" / "urdf" / "base.urdf.xacro"
    text = base.read_text()
    old = (
        '<inertia ixx="0.012411765597" ixy="-0.000711733678" ixz="0.00050272983"\n'
        '                 iyy="0.015218160428" iyz="-0.000004273467" izz="0.011763977943" />'
    )
    new = (
        '<inertia ixx="0.016549020796" ixy="-0.000948978237" ixz="0.000670306440"\n'
        '                 iyy="0.020290880571" iyz="-0.000005697956" izz="0.015685303924" />'
    )
    assert text.count(old) == 2  # the wheel and the caster hub
    base.write_text(text.replace(old, new, 1))


def move_laser_centre_of_mass(repo: Path, x: float) -> None:
    """The laser's centre of mass ``x`` m forward of its 6 cm box: outside its geometry (GC506)."""
    laser = repo / "pr2_base" / "urdf" / "laser.urdf.xacro"
    text = laser.read_text()
    text, count = re.subn(r'(<mass value="0.001" />\s*<origin xyz=")[^"]*(")', rf"\g<1>{x} 0 0\g<2>", text)
    assert count == 1
    laser.write_text(text)


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_a_worse_inertia_tensor_regresses_with_its_numbers_in_every_format(
    repo: Path, capsys: pytest.CaptureFixture[str], fmt: str
) -> None:
    raise_wheel_tensor(repo)
    status = main(["diff", "--base", "HEAD", str(ROOT_FILE), "--format", fmt, "--fail-on", "info"])
    out = capsys.readouterr().out
    assert status == 1
    # the message of the regressed finding names what got worse, in whatever the format writes
    shown = html.unescape(out) if fmt in ("html", "junit") else out
    named = r"regressed since HEAD[^:]*: radius_of_gyration \[0\.1\d+, [^]]*\] -> \[0\.\d+"
    assert re.search(named, shown), shown[-2000:]
    assert "wheel_link" in shown


def test_a_moved_centre_of_mass_regresses(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    move_laser_centre_of_mass(repo, 0.1)
    git(repo, "commit", "-q", "-am", "laser centre of mass off its box")
    move_laser_centre_of_mass(repo, 0.2)
    status, report = run_diff(capsys, "--base", "HEAD", str(ROOT_FILE), "--fail-on", "info")
    assert status == 1
    (regression,) = [r for r in report["sections"]["diff"]["regressions"] if r["diagnostic"]["code"] == "GC506"]
    (distance,) = regression["metrics"]
    assert distance["name"] == "distance" and distance["after"] - distance["before"] == pytest.approx(0.1, abs=1e-3)


def test_a_worse_coverage_regresses(repo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    move_base_box_off_the_mesh(repo)
    _, report = run_diff(capsys, "--base", "HEAD", str(ROOT_FILE))
    (regression,) = report["sections"]["diff"]["regressions"]
    coverage = {m["name"]: m for m in regression["metrics"]}["coverage"]
    assert coverage["after"] < coverage["before"] - 0.01


@pytest.mark.parametrize("fmt", ["concise", "github", "sarif", "junit"])
def test_a_failing_gate_names_the_regression_in_every_ci_format(
    repo: Path, capsys: pytest.CaptureFixture[str], fmt: str
) -> None:
    shrink_caster_boxes(repo)
    status = main(["diff", "--base", "HEAD", str(ROOT_FILE), "--format", fmt])
    out = capsys.readouterr().out
    assert status == 1
    if fmt == "concise":
        lines = [line for line in out.splitlines() if "regressed since HEAD" in line]
        assert len([line for line in lines if "[error]" in line and "caster_rotation_link" in line]) == 1
        assert out.rstrip().endswith("-> FAIL (fail on error)")
    elif fmt == "github":
        errors = [line for line in out.splitlines() if line.startswith("::error ")]
        assert len([line for line in errors if "caster_rotation_link" in line and "regressed since HEAD" in line]) == 1
    elif fmt == "sarif":
        results = json.loads(out)["runs"][0]["results"]
        failing = [r for r in results if r["level"] == "error" and "regressed since HEAD" in r["message"]["text"]]
        assert len([r for r in failing if "caster_rotation_link" in r["message"]["text"]]) == 1
    else:
        suite = etree.fromstring(out.encode())
        failures = [
            f for f in suite.iter("failure") if "regressed since HEAD" in (f.get("message") or "") + (f.text or "")
        ]
        assert len(failures) >= 1
