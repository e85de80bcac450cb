"""The fixes as a patch: lines cut at ``\\n`` only (a CR, U+2028 or NEL inside a fixed line),
file names with spaces or quotes, applied by ``patch -p1`` and ``git apply`` to give what
``geomcheck fix`` writes."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from geomcheck.cli import main
from geomcheck.patch.apply import patch_name

ODD = "a\u2028b\x85c\rd comment"  # line breaks to str.splitlines, none to patch
ROBOT = (
    '<robot name="r">\n  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>'
    '</link>\n  <link name="arm"/>\n  <joint type="continuous" name="j"><parent link="base"/><child link="arm"/>'
    f'<axis xyz="0 0 2"/><!-- {ODD} --></joint>\n</robot>\n'
)


@pytest.mark.parametrize("name", ["r.urdf", "my robot.urdf", 'q"uote.urdf'])
@pytest.mark.parametrize("tool", ["patch", "git"])
def test_the_patch_applies_to_give_what_fix_writes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], name: str, tool: str
) -> None:
    if shutil.which(tool) is None:
        pytest.skip(f"{tool} is not installed")
    work, copy = tmp_path / "work", tmp_path / "copy"
    work.mkdir()
    (work / name).write_bytes(ROBOT.encode())
    shutil.copytree(work, copy)
    monkeypatch.chdir(work)
    assert main(["fix", "--diff", "--select", "GC120", name]) == 1
    patch = capsys.readouterr().out
    assert main(["fix", "--select", "GC120", name]) == 0
    capsys.readouterr()
    fixed = (work / name).read_bytes()
    assert fixed == ROBOT.replace('<axis xyz="0 0 2"/>', '<axis xyz="0 0 1"/>').encode()
    command = ["patch", "-p1", "--batch", "--no-backup-if-mismatch"] if tool == "patch" else ["git", "apply", "-"]
    done = subprocess.run(command, cwd=copy, input=patch.encode(), capture_output=True, timeout=60)
    assert done.returncode == 0, (done.stdout + done.stderr).decode()
    assert (copy / name).read_bytes() == fixed


def test_names_are_written_as_git_writes_them() -> None:
    assert patch_name("a/r.urdf") == "a/r.urdf"
    assert patch_name("a/my robot.urdf") == "a/my robot.urdf\t"
    assert patch_name('a/q"uote.urdf') == '"a/q\\"uote.urdf"'
    assert patch_name("a/tab\there") == '"a/tab\\there"'
