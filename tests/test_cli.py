"""The command line: exit codes, formats, output files, statistics, configuration end to end,
and the rules reference."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from geomcheck.cli import main
from geomcheck.report.rules_markdown import render as rules_markdown
from geomcheck.rules import all_rules

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"

CLEAN = '<robot name="clean"><link name="base"/></robot>\n'
# a typo'd attribute on line 4 (GC106, warning) and a moving link without mass (GC501, error; the
# base's mass makes it more than a kinematics-only description)
FINDINGS = """<robot name="arm">
  <link name="base"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link><link name="upper"/>
  <joint name="shoulder" type="continuous"><origin xzy="0 0 1"/>
    <parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
  </joint>
</robot>
"""


@pytest.fixture
def work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "clean.urdf").write_text(CLEAN)
    (tmp_path / "arm.urdf").write_text(FINDINGS)
    return tmp_path


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def codes(capsys: pytest.CaptureFixture[str], *argv: str) -> list[tuple[str, str]]:
    status, out, err = run(capsys, "check", "--format", "json", *argv)
    assert status in (0, 1), err
    return [(d["code"], d["severity"]) for d in json.loads(out)["diagnostics"]]


# --- exit status -------------------------------------------------------------------------------


def test_clean_exits_0(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "check", "clean.urdf")
    assert status == 0
    assert out.endswith(
        "clean: 1 link, 0 joints, 0/0 meshes loaded; 0 errors, 0 warnings, 0 info -> PASS (fail on error)\n"
    )


def test_errors_exit_1_and_exit_zero_overrides(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "check", "arm.urdf")[0] == 1
    assert run(capsys, "check", "--exit-zero", "arm.urdf")[0] == 0


def test_fail_on_decides_which_severity_fails(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "check", "--ignore", "GC501", "arm.urdf")[0] == 0
    assert run(capsys, "check", "--ignore", "GC501", "--fail-on", "warning", "arm.urdf")[0] == 1
    status, _, err = run(capsys, "check", "--fail-on", "fatal", "arm.urdf")
    assert status == 2 and "--fail-on: invalid value 'fatal'" in err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["check", "missing.urdf"], "no such file: missing.urdf"),
        (["check", "broken.urdf"], "GC101"),
        (["check", "--format", "yaml", "clean.urdf"], "--format: invalid value 'yaml'"),
        (["check", "--package", "nodir", "clean.urdf"], "--package must be NAME=VALUE"),
        (["check", "--pose", "elbow=up", "clean.urdf"], "--pose elbow must be a number"),
        (["check", "--config", "none.toml", "clean.urdf"], "--config: no such file: none.toml"),
        (["check", "--format", "json", "clean.urdf", "arm.urdf"], "--format json takes one description"),
        (["rule", "GC999"], "invalid rule 'GC999'"),
    ],
)
def test_usage_and_input_errors_exit_2_with_one_line(
    work: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    (work / "broken.urdf").write_text("<robot name='x'>\n<link>\n")
    status, out, err = run(capsys, *argv)
    assert status == 2
    assert message in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert out == ""


def test_argparse_errors_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check"]) == 2
    assert main(["frobnicate"]) == 2
    assert main(["--version"]) == 0


def test_github_format_annotates_an_unreadable_file(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (work / "broken.urdf").write_text("<robot name='x'>\n<link>\n")
    status, out, _ = run(capsys, "check", "--format", "github", "broken.urdf")
    assert status == 2
    assert out.startswith("::error file=broken.urdf,line=")
    assert "title=GC101 malformed-xml::" in out


# --- output ------------------------------------------------------------------------------------


def test_output_file(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "check", "--format", "sarif", "-o", "out.sarif", "arm.urdf")
    assert (status, out) == (1, "")
    log = json.loads((work / "out.sarif").read_text())
    assert {r["ruleId"] for r in log["runs"][0]["results"]} >= {"GC106", "GC501"}


def test_concise_location_of_a_finding(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "check", "--format", "concise", "arm.urdf")
    assert "arm.urdf:4:3: GC106 [warning] joint shoulder: " in out


def test_github_annotation_per_finding_with_file_and_line(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "check", "--format", "github", "arm.urdf")
    annotations = [line for line in out.splitlines() if line.startswith("::")]
    found = codes(capsys, "arm.urdf")
    assert len(annotations) == len(found)
    assert any(a.startswith("::warning file=arm.urdf,line=4,title=GC106 ") for a in annotations)


def test_junit_output_parses(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from junitparser import JUnitXml

    assert run(capsys, "check", "--format", "junit", "-o", "report.xml", "arm.urdf")[0] == 1
    xml = JUnitXml.fromfile(str(work / "report.xml"))
    assert xml.failures >= 1
    names = {case.name for suite in xml for case in suite}
    assert {"robot", "link upper", "joint shoulder"} <= names


def test_statistics(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "check", "--statistics", "arm.urdf", "arm.urdf")
    assert status == 1
    lines = out.splitlines()
    assert lines[0].split() == ["count", "code", "name", "severity", "fixable"]
    rows = {line.split()[1]: int(line.split()[0]) for line in lines[1:] if line.split()[0].isdigit()}
    assert rows["GC106"] == 2 and rows["GC501"] == 2
    assert lines[-1].startswith("[*] ") or lines[-1].startswith("Found ")
    assert f"Found {sum(rows.values())} findings." in lines
    _, out, _ = run(capsys, "check", "--statistics", "--format", "json", "arm.urdf")
    table = json.loads(out)
    (gc106,) = [r for r in table if r["code"] == "GC106"]
    assert gc106 == {"code": "GC106", "name": "unknown-urdf-attribute", "severity": "warning", "count": 1, "fixable": 1}


def test_several_descriptions_in_line_formats(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "check", "--format", "concise", "clean.urdf", "arm.urdf")
    assert status == 1
    summaries = [line for line in out.splitlines() if " -> " in line]
    assert [s.split(":")[0] for s in summaries] == ["clean", "arm"]


def test_same_input_same_bytes(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    for fmt in ("json", "sarif", "junit", "full", "github"):
        first = run(capsys, "check", "--format", fmt, "arm.urdf")[1]
        assert run(capsys, "check", "--format", fmt, "arm.urdf")[1] == first


# --- configuration end to end ------------------------------------------------------------------


def test_config_select_and_severity_change_the_result(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert ("GC501", "error") in codes(capsys, "arm.urdf")
    (work / "geomcheck.toml").write_text('[severity]\nGC501 = "warning"\n')
    assert ("GC501", "warning") in codes(capsys, "arm.urdf")
    assert run(capsys, "check", "arm.urdf")[0] == 0
    (work / "geomcheck.toml").write_text('select = ["structure"]\n')
    assert {c for c, _ in codes(capsys, "arm.urdf")} <= {f"GC1{n:02d}" for n in range(100)}


def test_config_per_link_and_per_joint_ignores(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (work / "geomcheck.toml").write_text(
        '[per-link-ignores]\nupper = ["GC5"]\n[per-joint-ignores]\nshoulder = ["GC106"]\n'
    )
    assert codes(capsys, "arm.urdf") == []


def test_config_fail_on_and_output_format(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (work / "pyproject.toml").write_text(
        '[tool.geomcheck]\nfail-on = "warning"\noutput-format = "concise"\nignore = ["GC501"]\n'
    )
    status, out, _ = run(capsys, "check", "arm.urdf")
    assert status == 1
    assert out.splitlines()[0].startswith("arm.urdf:4:3: GC106 [warning]")


def test_config_thresholds_reach_the_checks(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    heavy = CLEAN.replace(
        '<link name="base"/>',
        '<link name="base"><inertial><mass value="0"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>'
        '</inertial></link><link name="tip"><inertial><mass value="0.5"/>'
        '<inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>'
        '<joint name="j" type="continuous"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/></joint>',
    )
    (work / "heavy.urdf").write_text(heavy)
    assert ("GC502", "error") not in codes(capsys, "heavy.urdf")
    (work / "geomcheck.toml").write_text("[thresholds.inertia]\nmin_mass_kg = 1.0\n")
    assert ("GC502", "error") in codes(capsys, "heavy.urdf")


def test_config_packages_and_args(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pkg = work / "deps" / "my_robot"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>my_robot</name></package>")
    (pkg / "urdf" / "part.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="${prefix}base"/></robot>'
    )
    (work / "main.urdf.xacro").write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:arg name="prefix" default=""/>'
        '<xacro:property name="prefix" value="$(arg prefix)"/>'
        '<xacro:include filename="$(find my_robot)/urdf/part.xacro"/></robot>'
    )
    assert run(capsys, "check", "main.urdf.xacro")[0] == 2
    (work / "geomcheck.toml").write_text('[packages]\nmy_robot = "deps/my_robot"\n[args]\nprefix = "left_"\n')
    status, out, err = run(capsys, "check", "--format", "json", "main.urdf.xacro")
    assert status == 0, err
    assert json.loads(out)["options"]["args"] == {"prefix": "left_"}
    (work / "geomcheck.toml").write_text('search = ["deps"]\n')
    assert run(capsys, "check", "main.urdf.xacro")[0] == 0


def test_config_matrix_options_reach_the_report(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (work / "geomcheck.toml").write_text('samples = 64\nseed = 3\nbackend = "fcl"\nsweep = false\n')
    _, out, _ = run(capsys, "check", "--format", "json", "clean.urdf")
    options = json.loads(out)["options"]
    assert (options["samples"], options["seed"], options["backend"], options["sweep"]) == (64, 3, "fcl", False)
    _, out, _ = run(capsys, "check", "--format", "json", "--seed", "9", "clean.urdf")
    assert json.loads(out)["options"]["seed"] == 9


def test_unknown_config_key_exits_2_naming_it(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (work / "pyproject.toml").write_text('[tool.geomcheck]\nsamples = 10\nignores = ["GC3"]\n')
    status, _, err = run(capsys, "check", "clean.urdf")
    assert status == 2
    assert "pyproject.toml: unknown configuration key 'ignores'; did you mean 'ignore'?" in err


# --- rules reference ---------------------------------------------------------------------------


def test_rules_table_and_json(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "rules")
    assert status == 0 and len(out.splitlines()) == len(all_rules())
    _, out, _ = run(capsys, "rules", "--format", "json")
    assert [r["code"] for r in json.loads(out)] == [r.code for r in all_rules()]
    gc301 = next(r for r in json.loads(out) if r["code"] == "GC301")
    coverage = next(m for m in gc301["metrics"] if m["name"] == "mesh_inside")
    assert (coverage["unit"], coverage["better"]) == ("1", "higher")


def test_rule_documentation(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "rule", "GC101")
    assert status == 0 and out.startswith("GC101 malformed-xml (error)")
    assert "Metrics" not in out  # GC101 carries no data
    _, out, _ = run(capsys, "rule", "GC301")
    assert "Metrics (data key, unit, better)\n" in out
    assert any(line.split()[:3] == ["mesh_inside", "[1]", "higher"] for line in out.splitlines())


def test_docs_rules_md_is_in_sync_with_the_registry() -> None:
    """docs/rules.md is generated; regenerate it with `geomcheck rules --format markdown -o docs/rules.md`."""
    checked_in = (REPO / "docs" / "rules.md").read_text(encoding="utf-8")
    assert checked_in == rules_markdown(all_rules()), (
        "docs/rules.md is out of date: run `geomcheck rules --format markdown -o docs/rules.md`"
    )


def test_rules_markdown_has_every_rule_documented() -> None:
    text = rules_markdown(all_rules())
    for rule in all_rules():
        assert f"### {rule.code} {rule.name}\n" in text
        assert f"[{rule.code}](#{rule.code.lower()}-{rule.name})" in text


def test_console_script_runs_as_a_module() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "geomcheck", "rules"], capture_output=True, text=True, check=False, timeout=60
    )
    assert proc.returncode == 0 and proc.stdout.startswith("GC101")


@pytest.mark.skipif(not EXAMPLE.is_file(), reason="bundled example not present")
def test_bundled_example_in_every_format(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)
    status, out, err = run(capsys, "check", "--format", "json", str(EXAMPLE.relative_to(REPO)))
    assert status in (0, 1), err
    report = json.loads(out)
    assert report["robot"]["links"] == 15
    count = len(report["diagnostics"])
    _, out, _ = run(capsys, "check", "--format", "github", str(EXAMPLE.relative_to(REPO)))
    annotations = [line for line in out.splitlines() if line.startswith("::")]
    assert len(annotations) == count
    assert all(",line=" in a and "file=examples/pr2_base/" in a for a in annotations)


def test_render_a_saved_report_in_another_format(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "check", "--format", "json", "-o", "report.json", "arm.urdf")[0] == 1
    direct = run(capsys, "check", "--format", "sarif", "arm.urdf")[1]
    status, again, _ = run(capsys, "render", "report.json", "--format", "sarif")
    assert (status, again) == (1, direct)
    assert run(capsys, "render", "report.json", "--format", "github", "--exit-zero")[0] == 0
    (work / "other.json").write_text("{}")
    status, _, err = run(capsys, "render", "other.json")
    assert status == 2 and "is not a geomcheck JSON report" in err


def test_internal_errors_exit_2_with_one_line(
    work: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import geomcheck.pipeline

    def broken(*args: object, **kwargs: object) -> None:
        raise RuntimeError("boom")

    monkeypatch.setattr(geomcheck.pipeline, "run_check", broken)  # the CLI imports it when a check runs
    status, _, err = run(capsys, "check", "clean.urdf")
    assert status == 2
    assert err == "geomcheck: internal error: RuntimeError: boom (set GEOMCHECK_DEBUG=1 for the traceback)\n"
    monkeypatch.setenv("GEOMCHECK_DEBUG", "1")
    with pytest.raises(RuntimeError, match="boom"):
        main(["check", "clean.urdf"])


@pytest.mark.corpus
def test_ci_formats_on_the_2009_pr2_base(
    pr2_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """One check of real legacy xacro, rendered in every CI format: locations name files that exist."""
    from junitparser import JUnitXml

    monkeypatch.chdir(pr2_root)
    saved = tmp_path / "report.json"
    status, _, err = run(
        capsys,
        "check",
        "pr2_description/robots/pr2_base.urdf.xacro",
        "--search",
        ".",
        "--format",
        "json",
        "-o",
        str(saved),
    )
    assert status in (0, 1), err
    report = json.loads(saved.read_text())
    count = len(report["diagnostics"])
    assert report["robot"]["links"] == 14 and count > 0
    _, out, _ = run(capsys, "render", str(saved), "--format", "sarif")
    results = json.loads(out)["runs"][0]["results"]
    assert len(results) == count
    for result in results:
        uri = result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
        assert (pr2_root / uri).is_file(), uri
    _, out, _ = run(capsys, "render", str(saved), "--format", "github")
    assert len([line for line in out.splitlines() if line.startswith("::")]) == count
    _, out, _ = run(capsys, "render", str(saved), "--format", "junit", "-o", str(tmp_path / "junit.xml"))
    xml = JUnitXml.fromfile(str(tmp_path / "junit.xml"))
    failing = sum(1 for d in report["diagnostics"] if d["severity"] == "error")
    assert (xml.failures > 0) == (failing > 0)
