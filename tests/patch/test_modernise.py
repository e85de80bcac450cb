"""GC103's safe fix: pre-2013 xacro written in today's syntax, the expansion unchanged, and
the real xacro package then expands the file it could not before."""

from __future__ import annotations

import contextlib
import io
import shutil
from pathlib import Path

import pytest
import xacro

from geomcheck.cli import main
from geomcheck.patch.modernise import modernising_edits
from tests.corpustools import ros_packages

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base"
ROOT = "robots/pr2_base.urdf.xacro"

LEGACY = """<robot name="r" xmlns:xacro="http://playerstage.sourceforge.net/gazebo/xmlschema/#interface">
  <property name="w" value="0.1"/>
  <macro name="leg" params="side">
    <link name="${side}_leg"/>
  </macro>
  <leg side="left"/>
  <gazebo><include><uri>model://sun</uri></include></gazebo>
  <xacro:leg side="right"/>
</robot>
"""


def apply(text: str, edits: list) -> str:
    for edit in sorted(edits, key=lambda e: e.start, reverse=True):
        text = text[: edit.start] + edit.replacement + text[edit.end :]
    return text


def test_bare_instructions_and_macro_calls_get_their_prefix_and_the_namespace_its_uri() -> None:
    fixed = apply(LEGACY, modernising_edits("r.xacro", LEGACY, {"r.xacro": LEGACY}))
    assert fixed.splitlines()[:6] == [
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">',
        '  <xacro:property name="w" value="0.1"/>',
        '  <xacro:macro name="leg" params="side">',
        '    <link name="${side}_leg"/>',
        "  </xacro:macro>",
        '  <xacro:leg side="left"/>',
    ]
    assert "<gazebo><include><uri>model://sun</uri></include></gazebo>" in fixed  # Gazebo's, not xacro's
    assert '<xacro:leg side="right"/>' in fixed and "xacro:xacro:" not in fixed


def test_a_missing_declaration_is_added_to_the_root() -> None:
    text = '<robot name="r">\n  <property name="w" value="1"/>\n</robot>\n'
    fixed = apply(text, modernising_edits("r.xacro", text, {"r.xacro": text}))
    assert fixed.splitlines()[0] == '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'


def expanded_by_xacro(root: Path, package: Path) -> str:
    with ros_packages({"pr2_base_example": package}), contextlib.redirect_stderr(io.StringIO()):
        return str(xacro.process_file(str(root)).toxml())


def test_the_example_is_modernised_safely(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    copy = tmp_path / "pr2_base"
    shutil.copytree(EXAMPLE, copy)
    with pytest.raises(xacro.XacroException):
        expanded_by_xacro(copy / ROOT, copy)  # today's xacro cannot expand the legacy files
    assert main(["check", str(copy / ROOT), "--format", "json", "-o", str(tmp_path / "before.json")]) == 1
    assert main(["fix", str(copy / ROOT)]) == 1
    err = capsys.readouterr().err
    assert "fixed 4 findings" in err
    assert main(["check", str(copy / ROOT), "--format", "json", "-o", str(tmp_path / "after.json")]) == 1
    import json

    before = {d["fingerprint"]: d["code"] for d in json.loads((tmp_path / "before.json").read_text())["diagnostics"]}
    after = {d["fingerprint"]: d["code"] for d in json.loads((tmp_path / "after.json").read_text())["diagnostics"]}
    assert sorted(before[k] for k in before.keys() - after.keys()) == ["GC103"] * 4
    assert after.keys() < before.keys()
    assert expanded_by_xacro(copy / ROOT, copy).count("<link ") == 15
    assert main(["fix", str(copy / ROOT), "--diff"]) == 0  # a second run changes nothing
    assert capsys.readouterr().out == ""
