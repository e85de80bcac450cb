"""Fixes write only files inside the checked folder, never through a symbolic link (not even
in the scratch copy that verifies them), and ``geomcheck fix`` honours untrusted mode."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.cli import main

XACRO = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n{body}\n</robot>\n'
# GC120: an axis of length 2, fixed to length 1 in the file that holds it
PART = XACRO.format(
    body='<link name="arm"/>\n<joint type="continuous" name="j"><parent link="base"/><child link="arm"/>'
    '<axis xyz="0 0 2"/></joint>'
)
BASE = '<link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>\n'


@pytest.fixture
def layout(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> tuple[Path, Path]:
    """(the checked repository, a file outside it that the description reaches)."""
    repo, outside = tmp_path / "repo", tmp_path / "outside"
    repo.mkdir()
    outside.mkdir()
    (outside / "part.xacro").write_text(PART, encoding="utf-8")
    monkeypatch.chdir(repo)
    monkeypatch.delenv("CI", raising=False)
    monkeypatch.delenv("GEOMCHECK_UNTRUSTED", raising=False)
    return repo, outside / "part.xacro"


def run(capfd: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capfd.readouterr()
    return status, out, err


def test_fix_writes_an_included_file_inside_the_folder(
    layout: tuple[Path, Path], capfd: pytest.CaptureFixture[str]
) -> None:
    repo, _ = layout
    (repo / "part.xacro").write_text(PART, encoding="utf-8")
    (repo / "r.urdf.xacro").write_text(XACRO.format(body=BASE + '<xacro:include filename="part.xacro"/>'))
    status, _, err = run(capfd, "fix", "--select", "GC120", "r.urdf.xacro")
    assert status == 0, err
    assert "fixed 1 finding in part.xacro" in err
    assert '<axis xyz="0 0 1"/>' in (repo / "part.xacro").read_text()


def test_fix_never_writes_through_a_parent_include(
    layout: tuple[Path, Path], capfd: pytest.CaptureFixture[str]
) -> None:
    repo, outside = layout
    (repo / "r.urdf.xacro").write_text(XACRO.format(body=BASE + '<xacro:include filename="../outside/part.xacro"/>'))
    status, out, err = run(capfd, "fix", "--select", "GC120", "r.urdf.xacro")
    # the finding's fix is neither offered nor counted (was: "[*] 1 fixable", then refused at the write)
    assert status == 0
    assert err.splitlines() == [
        "geomcheck: fixed nothing",
        "geomcheck: not fixed automatically: GC120 joint j: normalise the axis to unit length: "
        "../outside/part.xacro is outside the checked folder: fixes write only inside it",
    ]
    assert "fixable" not in out and "[*]" not in out
    assert outside.read_text() == PART


@pytest.mark.parametrize("diff", [False, True])
def test_fix_never_writes_through_a_symbolic_link(
    layout: tuple[Path, Path], capfd: pytest.CaptureFixture[str], diff: bool
) -> None:
    repo, outside = layout
    (repo / "part.xacro").symlink_to(outside)  # absolute: the verifying copy keeps it pointing outside
    (repo / "r.urdf.xacro").write_text(XACRO.format(body=BASE + '<xacro:include filename="part.xacro"/>'))
    status, out, err = run(capfd, "fix", *(["--diff"] if diff else []), "--select", "GC120", "r.urdf.xacro")
    assert status == 0
    assert err.splitlines() == [
        f"geomcheck: {'would fix' if diff else 'fixed'} nothing",
        "geomcheck: not fixed automatically: GC120 joint j: normalise the axis to unit length: "
        "part.xacro is reached through a symbolic link: fixes never write through one",
    ]
    assert "[*]" not in out
    assert outside.read_text() == PART


def test_fix_is_untrusted_where_ci_is_true(
    layout: tuple[Path, Path], capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    repo, outside = layout
    monkeypatch.setenv("CI", "true")
    (repo / "r.urdf.xacro").write_text(XACRO.format(body=BASE + f'<xacro:include filename="{outside}"/>'))
    status, out, err = run(capfd, "fix", "--select", "GC120", "r.urdf.xacro")
    assert status == 2
    assert out == ""
    assert "outside" in err and err.count("\n") == 1  # the confined child refused to read it
    assert outside.read_text() == PART


def test_a_model_part_outside_the_folder_is_not_offered_as_fixable(
    layout: tuple[Path, Path], capfd: pytest.CaptureFixture[str]
) -> None:
    repo, outside = layout
    part = outside.parent / "parts.xml"
    part.write_text(
        '<mujoco>\n  <body name="arm" pos="0 0 0.5">\n    <joint name="j" axis="0 1 0"/>\n'
        '    <geom name="g" type="box" size="0.3 0.3 0.3" mass="1"/>\n'
        '    <geom name="v" type="sphere" size="0.05" contype="0" conaffinity="0"/>\n  </body>\n</mujoco>\n'
    )
    (repo / "robot.xml").write_text(
        '<mujoco model="r"><worldbody><body name="base"><geom type="box" size="0.1 0.1 0.1"/>\n'
        '<include file="../outside/parts.xml"/></body></worldbody></mujoco>\n'
    )
    before = part.read_text()
    status, out, err = run(capfd, "fix", "--unsafe-fixes", "--select", "GC302", "--format", "concise", "robot.xml")
    # was: "not fixed automatically", and yet the report said "[*] 1 fixable with geomcheck fix --unsafe-fixes"
    assert status == 0
    assert err.splitlines() == [
        "geomcheck: fixed nothing",
        "geomcheck: not fixed automatically: GC302 link arm: use the fitted box: "
        "../outside/parts.xml is outside the checked folder: fixes write only inside it",
    ]
    assert "GC302" in out and "[*]" not in out and "fixable" not in out
    assert part.read_text() == before
    status, out, _ = run(capfd, "check", "--select", "GC302", "--format", "concise", "robot.xml")
    assert status == 0 and "GC302" in out and "fixable" not in out
