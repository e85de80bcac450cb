"""Fingerprints of file-level findings do not depend on the folder geomcheck runs in."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check

LEGACY = """<?xml version="1.0"?>
<robot name="r">
  <property name="w" value="0.1"/>
  <link name="base"><visual><geometry><box size="${w} 1 1"/></geometry></visual>
    <collision><geometry><box size="${w} 1 1"/></geometry></collision></link>
  <orgin/>
  <orgin/>
</robot>
"""


def write_package(root: Path) -> Path:
    pkg = root / "demo"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>demo</name></package>")
    robot = pkg / "urdf" / "r.urdf.xacro"
    robot.write_text(LEGACY)
    return robot


def fingerprints(robot: Path, display_root: Path) -> dict[str, list[str]]:
    report = run_check(make_bundle(robot, display_root=display_root), CheckOptions(sweep=False))
    out: dict[str, list[str]] = {}
    for d in report.diagnostics:
        out.setdefault(d.code, []).append(d.fingerprint)
    return out


def test_identity_is_package_relative(tmp_path: Path) -> None:
    robot = write_package(tmp_path)
    bundle = make_bundle(robot, display_root=tmp_path)
    assert bundle.identity("demo/urdf/r.urdf.xacro") == "package://demo/urdf/r.urdf.xacro"


@pytest.mark.parametrize("legacy_code", ["GC103"])
def test_file_findings_keep_fingerprints_across_folders_and_copies(tmp_path: Path, legacy_code: str) -> None:
    first = write_package(tmp_path / "a")
    second = write_package(tmp_path / "b" / "checkout")
    one = fingerprints(first, tmp_path)
    two = fingerprints(second, second.parent)
    assert legacy_code in one
    assert one == two
