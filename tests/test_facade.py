"""geomcheck from Python: check, diff and fix with the options of geomcheck.toml."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import geomcheck
from geomcheck import facade
from geomcheck.errors import UsageError

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pr2_base"
ROOT = "robots/pr2_base.urdf.xacro"


def test_check_returns_the_report_the_cli_writes() -> None:
    report = geomcheck.check(EXAMPLE / ROOT)
    assert isinstance(report, geomcheck.Report)
    assert report.robot.name == "pr2_base_example" and report.robot.links == 15
    assert report.failed and report.counts["error"] >= 1
    assert "GC301" in {d.code for d in report.diagnostics}


def test_options_are_configuration_keys() -> None:
    report = geomcheck.check(EXAMPLE / ROOT, select=["GC1"], fail_on="warning", sweep=False)
    assert {d.code[:3] for d in report.diagnostics} == {"GC1"}
    assert report.fail_on.value == "warning" and report.options["sweep"] is False


def test_a_bad_option_names_the_valid_ones() -> None:
    with pytest.raises(UsageError, match=r"unknown configuration key 'sampels'.*samples"):
        geomcheck.check(EXAMPLE / ROOT, sampels=10)
    with pytest.raises(UsageError, match="fail_on"):
        geomcheck.check(EXAMPLE / ROOT, fail_on="fatal")


def test_diff_and_fix(tmp_path: Path) -> None:
    old, new = tmp_path / "old", tmp_path / "new"
    shutil.copytree(EXAMPLE, old)
    shutil.copytree(EXAMPLE, new)
    laser = new / "urdf" / "laser.urdf.xacro"
    text = laser.read_text()
    assert '<property name="laser_size_x" value="' in text
    laser.write_text(text.replace('<property name="laser_size_x" value="', '<property name="laser_size_x" value="0.2'))
    changed = facade.diff(old / ROOT, new / ROOT, sweep=False)
    assert changed.sections["diff"]["base_exists"] is True
    assert [d.link for d in changed.diagnostics if d.code.startswith("GC3")] == ["base_laser_link"]
    before = laser.read_text()
    safe = facade.fix(new / ROOT, sweep=False)  # the safe fixes: the legacy xacro modernised
    assert "+  <xacro:include filename=" in safe and "<box" not in safe
    patch = facade.fix(new / ROOT, sweep=False, unsafe=True, select=["GC3"])
    assert patch.startswith("--- ") and "urdf/base.urdf.xacro" in patch
    assert laser.read_text() == before  # nothing written without write=True
