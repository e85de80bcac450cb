"""``geomcheck fix`` and ``check --fix``: safe fixes of a plain URDF written byte for byte,
``--diff`` writing nothing, the selection honoured, markers in the reports, and the bundled
example's unsafe fixes as a diff of its xacro files."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import trimesh

from geomcheck.cli import main

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "pr2_base"

# GC201 (mesh path in the wrong case), GC105 (<orgin>), GC120 (axis of length 2), GC501 (no fix)
ROBOT = """<robot name="r">
  <!-- a comment, odd spacing and attribute order stay as they are -->
  <link name="base">
    <visual><geometry><mesh   filename="meshes/part.stl"/></geometry></visual>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <link name="arm"/>
  <joint type="continuous" name="j">
    <parent link="base"/><child link="arm"/>
    <orgin rpy="0 0 0" xyz="0 0 1.000"></orgin>
    <axis xyz="0 0 2"/>
  </joint>
</robot>
"""
FIXED = (
    ROBOT.replace('filename="meshes/part.stl"', 'filename="meshes/Part.STL"')
    .replace('<orgin rpy="0 0 0" xyz="0 0 1.000"></orgin>', '<origin rpy="0 0 0" xyz="0 0 1.000"></origin>')
    .replace('<axis xyz="0 0 2"/>', '<axis xyz="0 0 1"/>')
)


@pytest.fixture
def work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "meshes").mkdir()
    trimesh.creation.box((0.1, 0.1, 0.1)).export(tmp_path / "meshes" / "Part.STL")
    (tmp_path / "r.urdf").write_text(ROBOT)
    return tmp_path


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_fix_writes_the_safe_fixes_and_nothing_else(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "fix", "--format", "concise", "r.urdf")
    assert (work / "r.urdf").read_text() == FIXED
    assert err.splitlines()[0] == "geomcheck: fixed 3 findings in r.urdf"
    # GC501 remains: no link has an <inertial>, a kinematics-only description (info)
    assert status == 0
    assert [line.split()[1] for line in out.splitlines()[:-1]] == ["GC501"]
    assert "[info]" in out.splitlines()[0]
    status, _, err = run(capsys, "fix", "r.urdf")
    assert err.splitlines()[0] == "geomcheck: fixed nothing"
    assert (work / "r.urdf").read_text() == FIXED


def test_diff_prints_the_fixes_and_writes_nothing(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "check", "--diff", "r.urdf")
    assert status == 1
    assert (work / "r.urdf").read_text() == ROBOT
    assert out.startswith("--- a/r.urdf\n+++ b/r.urdf\n@@ -1,13 +1,13 @@\n")
    changed = [line for line in out.splitlines() if line[:1] in "+-" and line[:3] not in ("+++", "---")]
    assert changed == [
        '-    <visual><geometry><mesh   filename="meshes/part.stl"/></geometry></visual>',
        '+    <visual><geometry><mesh   filename="meshes/Part.STL"/></geometry></visual>',
        '-    <orgin rpy="0 0 0" xyz="0 0 1.000"></orgin>',
        '-    <axis xyz="0 0 2"/>',
        '+    <origin rpy="0 0 0" xyz="0 0 1.000"></origin>',
        '+    <axis xyz="0 0 1"/>',
    ]
    assert err == "geomcheck: would fix 3 findings in r.urdf\n"


def test_check_fix_honours_the_selection(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run(capsys, "check", "--fix", "--ignore", "GC105,GC2", "r.urdf")
    assert (work / "r.urdf").read_text() == ROBOT.replace('<axis xyz="0 0 2"/>', '<axis xyz="0 0 1"/>')
    (work / "geomcheck.toml").write_text('select = ["GC105"]\n')
    run(capsys, "fix", "r.urdf")
    assert "<origin " in (work / "r.urdf").read_text() and "meshes/part.stl" in (work / "r.urdf").read_text()


def test_reports_mark_fixable_findings(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "check", "--format", "concise", "r.urdf")
    lines = out.splitlines()
    assert "r.urdf:4:5: GC201 [error] link base: [*] visual[0] of link 'base': mesh file not found" in lines[0]
    assert lines[-1].endswith("; [*] 3 fixable with geomcheck fix -> FAIL (fail on error)")
    _, out, _ = run(capsys, "check", "r.urdf")
    assert "r.urdf:10:5: GC105 [warning] unknown-urdf-element [*]\n" in out
    assert "  = fix (safe): rename <orgin> to <origin> (geomcheck fix)\n" in out
    _, out, _ = run(capsys, "check", "--format", "json", "r.urdf")
    fixes = {d["code"]: d["fix"] for d in json.loads(out)["diagnostics"]}
    assert fixes["GC501"] is None
    assert fixes["GC120"] == {
        "applicability": "safe",
        "title": "normalise the axis to unit length",
        "element": "joint",
        "changes": ['axis xyz="0 0 1"'],
    }
    _, out, _ = run(capsys, "check", "--format", "html", "r.urdf")
    assert '<span class="fixable" title="fixable: geomcheck fix">[*]</span>' in out
    assert "[*] 3 fixable with geomcheck fix" in out


@pytest.fixture
def example(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    shutil.copytree(EXAMPLE, tmp_path / "pr2_base")
    monkeypatch.chdir(tmp_path)
    return tmp_path / "pr2_base"


def test_example_unsafe_diff_shows_the_base_collision_and_the_wheel_inertias(
    example: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    before = {p: p.read_bytes() for p in example.rglob("*") if p.is_file()}
    status, out, err = run(capsys, "fix", "--unsafe-fixes", "--diff", "pr2_base/robots/pr2_base.urdf.xacro")
    assert status == 1
    assert {p: p.read_bytes() for p in example.rglob("*") if p.is_file()} == before
    files = [line[6:] for line in out.splitlines() if line.startswith("+++ b/")]
    assert files == [  # the four legacy files modernised (safe fixes apply with the unsafe ones)
        "pr2_base/robots/pr2_base.urdf.xacro",
        "pr2_base/urdf/base.urdf.xacro",
        "pr2_base/urdf/common.xacro",
        "pr2_base/urdf/laser.urdf.xacro",
    ]
    changed = [line for line in out.splitlines() if line[:1] in "+-" and line[:3] not in ("+++", "---")]
    # the base box, fitted to the whole shell, would take the caster wells and hit the wheels
    # over their turn: it is refitted as boxes of the shell's parts, clear of the wheels
    assert '-        <origin xyz="0 0 ${base_size_z-base_collision_size_z/2}" rpy="0 0 0" />' in changed
    assert '-          <box size="${base_size_x} ${base_size_y} ${base_collision_size_z}" />' in changed
    boxes = [line for line in changed if line.startswith("+") and "<box size=" in line]
    assert '+        <geometry><box size="0.14 0.38 0.669703"/></geometry>' in boxes  # the spine housing
    assert sum(line == "+      <collision>" for line in changed) == len(boxes) - 2  # and the caster's box
    # each caster's box: the whole housing (its fit no longer ends where the wheels' cylinders take over)
    assert '+          <box size="0.187 0.15 0.193" />' in changed
    # the wheel macro's tensor, once for the eight wheels: a solid wheel of 0.44036 kg, axis y
    assert '+        <inertia ixx="0.00071258" ixy="0" ixz="0"' in changed
    assert '+                 iyy="0.00134263" iyz="0" izz="0.00071258" />' in changed
    assert '+        <inertia ixx="4.16874e-7" ixy="0" ixz="0" iyy="4.16874e-7" iyz="0" izz="5.93976e-7" />' in changed
    done, refitted = err.splitlines()
    assert done == (
        "geomcheck: would fix 8 findings in pr2_base/robots/pr2_base.urdf.xacro, pr2_base/urdf/base.urdf.xacro, "
        "pr2_base/urdf/common.xacro, pr2_base/urdf/laser.urdf.xacro"
    )
    # the base's fix is not the one box its finding suggests: the line says why
    assert refitted.startswith(
        "geomcheck: fixed otherwise than suggested: GC301 link base_link: replace the box by 5 boxes fitted"
    )
    assert refitted.endswith(": the fitted box would overlap them by up to 103 mm")


def test_example_safe_fix_names_the_unsafe_ones(example: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status, _, err = run(capsys, "fix", "pr2_base/robots/pr2_base.urdf.xacro")
    assert status == 1
    assert err.splitlines() == [
        "geomcheck: fixed 4 findings in pr2_base/robots/pr2_base.urdf.xacro, pr2_base/urdf/base.urdf.xacro, "
        "pr2_base/urdf/common.xacro, pr2_base/urdf/laser.urdf.xacro",
        "geomcheck: 4 more fixes available with --unsafe-fixes",
    ]


def test_rule_documentation_names_the_automatic_fix(capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "rule", "GC106")
    assert (
        "\nAutomatic fix\nSafe fix: `geomcheck fix` applies it when the finding carries the values to write "
        "(docs/fix.md); reports mark such findings [*].\n"
    ) in out
    _, out, _ = run(capsys, "rule", "GC507")
    assert "Automatic fix" not in out


def test_a_mesh_path_fix_stands_though_the_mesh_it_loads_reveals_findings(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    # the package moved its meshes to assets/ and kept the references; once the path is fixed the
    # 0.3 m part is read, and its 0.1 m collision box is found too small: a finding the mesh
    # reveals, there all along, which does not withdraw the fix that lets the check see it
    monkeypatch.chdir(tmp_path)
    (tmp_path / "assets").mkdir()
    trimesh.creation.box((0.3, 0.3, 0.3)).export(tmp_path / "assets" / "part.stl")
    (tmp_path / "r.urdf").write_text(ROBOT.replace("<orgin", "<origin").replace("</orgin>", "</origin>"))
    status, out, err = run(capsys, "fix", "--format", "concise", "r.urdf")
    assert 'filename="assets/part.stl"' in (tmp_path / "r.urdf").read_text()
    assert err.splitlines()[0] == "geomcheck: fixed 2 findings in r.urdf"  # the path and the axis
    assert status == 1
    assert any(" GC301 [error] link base:" in line for line in out.splitlines())
