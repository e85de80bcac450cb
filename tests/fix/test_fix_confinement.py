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
    status, _, err = run(capfd, "fix", "--select", "GC120", "r.urdf.xacro")
    assert status == 2
    assert err == "geomcheck: error: ../outside/part.xacro is outside the checked folder: fixes write only inside it\n"
    assert outside.read_text() == PART


@pytest.mark.parametrize("diff", [False, True])
def test_fix_never_writes_through_a_symbolic_link(
    layout: tuple[Path, Path], capfd: pytest.CaptureFixture[str], diff: bool
) -> None:
    repo, outside = layout
    (repo / "part.xacro").symlink_to(outside)  # absolute: the verifying copy keeps it pointing outside
    (repo / "r.urdf.xacro").write_text(XACRO.format(body=BASE + '<xacro:include filename="part.xacro"/>'))
    status, _, err = run(capfd, "fix", *(["--diff"] if diff else []), "--select", "GC120", "r.urdf.xacro")
    assert status == 2
    assert "symbolic link" in err or "outside the checked folder" in err
    assert err.count("\n") == 1
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
