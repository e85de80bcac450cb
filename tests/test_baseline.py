"""Baselines: record today's findings, then fail only on new ones."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from geomcheck.baseline import BASELINE_SCHEMA, Baseline, apply_baseline, match
from geomcheck.cli import main
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.errors import UsageError
from geomcheck.model import SourceLocation
from geomcheck.report.model import Report, RobotSummary

# a typo'd attribute (GC106, warning) and a moving link without mass (GC501, error)
ROBOT = """<robot name="arm">
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="upper"/>
  <link name="lower"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/>
    <limit lower="1" upper="-1" effort="1" velocity="1"/>
  </joint>
  <joint name="elbow" type="fixed">
    <origin xzy="0 0 0.3"/>
    <parent link="upper"/><child link="lower"/>
  </joint>
</robot>
"""


def diag(code: str, link: str, message: str = "m", line: int = 1) -> Diagnostic:
    return Diagnostic(code, "x", Severity.ERROR, message, "h", link=link, location=SourceLocation("r.urdf", line))


def test_file_round_trip_is_sorted_and_deterministic(tmp_path: Path) -> None:
    baseline = Baseline.from_diagnostics([diag("GC501", "b"), diag("GC301", "z"), diag("GC301", "a")])
    path = tmp_path / "baseline.json"
    baseline.write(path)
    doc = json.loads(path.read_text())
    assert doc["schema"] == BASELINE_SCHEMA
    assert [(e["code"], e["subject"]) for e in doc["findings"]] == [
        ("GC301", "link a"),
        ("GC301", "link z"),
        ("GC501", "link b"),
    ]
    assert set(doc["findings"][0]) == {"fingerprint", "code", "subject", "message"}
    assert Baseline.load(path) == baseline
    again = Baseline.from_diagnostics([diag("GC301", "a"), diag("GC301", "z"), diag("GC501", "b")])
    assert again.to_json() == path.read_text()


def test_match_ignores_lines_and_messages_and_counts_stale() -> None:
    baseline = Baseline.from_diagnostics([diag("GC301", "a", "old", 3), diag("GC301", "gone")])
    result = match([diag("GC301", "a", "new numbers", 40), diag("GC302", "a")], baseline)
    assert [d.code for d in result.new] == ["GC302"]
    assert result.matched == 1
    assert [e.subject for e in result.stale] == ["link gone"]


def test_match_is_a_multiset() -> None:
    baseline = Baseline.from_diagnostics([diag("GC301", "a")])
    result = match([diag("GC301", "a"), diag("GC301", "a")], baseline)
    assert len(result.new) == 1 and result.matched == 1 and result.stale == ()


def test_apply_baseline_adds_a_section_and_passes() -> None:
    report = Report(RobotSummary("r", "r.urdf", 1, 0), (diag("GC301", "a"),), "0.1.0", "2026-01-01T00:00:00Z")
    (out,), _ = apply_baseline([report], Baseline.from_diagnostics([diag("GC301", "a"), diag("GC1", "b")]), "b.json")
    assert out.diagnostics == () and not out.failed
    assert out.sections["baseline"]["matched"] == 1
    assert [e["subject"] for e in out.sections["baseline"]["stale"]] == ["link b"]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("not json", "is not JSON"),
        ('{"schema": "other"}', "not a geomcheck baseline"),
        ('{"schema": "geomcheck.baseline/1", "findings": [{}]}', "malformed entry"),
    ],
)
def test_bad_baseline_files(tmp_path: Path, text: str, expected: str) -> None:
    path = tmp_path / "b.json"
    path.write_text(text)
    with pytest.raises(UsageError, match=expected):
        Baseline.load(path)
    with pytest.raises(UsageError, match="cannot read baseline"):
        Baseline.load(tmp_path / "missing.json")


# --- through the command line ----------------------------------------------------------------


@pytest.fixture
def robot(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "arm.urdf"
    path.write_text(ROBOT)
    return path


def test_write_then_check_against_the_baseline(robot: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", "--no-config", str(robot)]) == 1
    capsys.readouterr()
    assert main(["check", "--no-config", "--write-baseline", "baseline.json", str(robot)]) == 0
    assert "findings to baseline baseline.json" in capsys.readouterr().err
    codes = sorted(e["code"] for e in json.loads(Path("baseline.json").read_text())["findings"])
    assert {"GC106", "GC501"} <= set(codes)
    assert main(["check", "--no-config", "--baseline", "baseline.json", "--format", "concise", str(robot)]) == 0
    out = capsys.readouterr().out
    assert out.splitlines() == [
        "arm: 3 links, 2 joints, 0/0 meshes loaded; 0 errors, 0 warnings, 0 info; "
        f"baseline baseline.json: {len(codes)} known, 0 no longer occur -> PASS (fail on error)"
    ]


def test_only_new_findings_fail_and_stale_entries_are_counted(robot: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", "--no-config", "--write-baseline", "baseline.json", str(robot)]) == 0
    # shift every line, fix the typo, and add a wheel without mass
    wheel = (
        '<link name="wheel"/><joint name="spin" type="continuous"><parent link="lower"/><child link="wheel"/></joint>'
    )
    changed = (
        ROBOT.replace("<robot", "<!-- moved -->\n\n<robot")
        .replace("xzy=", "xyz=")
        .replace("</robot>", f"{wheel}</robot>")
    )
    robot.write_text(changed)
    capsys.readouterr()
    status = main(["check", "--no-config", "--baseline", "baseline.json", "--format", "json", str(robot)])
    captured = capsys.readouterr()
    report = json.loads(captured.out)
    assert status == 1
    assert [(d["code"], d["link"]) for d in report["diagnostics"]] == [("GC501", "wheel")]
    # alone, the wheel's finding is one of a group reported on upper's, which the baseline accepts:
    # it is reported on its own, at its own severity, so the grouping hides no new defect
    [wheel] = report["diagnostics"]
    assert wheel["severity"] == "error" and wheel["data"]["grouped_with"] is not None
    assert wheel["message"].endswith("(its group is in the baseline; this part is not)")
    assert report["sections"]["baseline"]["matched"] >= 1
    assert [e["code"] for e in report["sections"]["baseline"]["stale"]] == ["GC106"]
    assert "1 baseline entries no longer occur" in captured.err


def test_baseline_from_the_configuration(robot: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", "--no-config", "--write-baseline", "ci/baseline.json", str(robot)]) == 2
    assert "cannot write baseline" in capsys.readouterr().err
    Path("ci").mkdir()
    assert main(["check", "--no-config", "--write-baseline", "ci/baseline.json", str(robot)]) == 0
    Path("geomcheck.toml").write_text('baseline = "ci/baseline.json"\n')
    assert main(["check", str(robot)]) == 0


def test_missing_baseline_is_a_usage_error(robot: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", "--no-config", "--baseline", "nope.json", str(robot)]) == 2
    assert "cannot read baseline nope.json" in capsys.readouterr().err
