"""The bundled example package examples/pr2_base: its meshes are what the script generates,
it loads as the README's main command loads it, and it shows the findings it was built to show."""

from __future__ import annotations

import importlib.util
import io
import json
from collections import Counter
from contextlib import redirect_stdout
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
import trimesh

from geomcheck.cli import main
from geomcheck.diagnostics import Diagnostic
from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report

REPO = Path(__file__).resolve().parent.parent
PACKAGE = REPO / "examples" / "pr2_base"
ROOT_FILE = PACKAGE / "robots" / "pr2_base.urdf.xacro"
MAIN_COMMAND = "geomcheck check examples/pr2_base/robots/pr2_base.urdf.xacro"
CASTERS = ("fl", "fr", "bl", "br")
WHEELS = [f"{c}_caster_{s}_wheel_link" for c in CASTERS for s in "lr"]
HUBS = [f"{c}_caster_rotation_link" for c in CASTERS]
LEGACY_FILES = ["robots/pr2_base.urdf.xacro", "urdf/base.urdf.xacro", "urdf/common.xacro", "urdf/laser.urdf.xacro"]


def load_mesh_script() -> ModuleType:
    spec = importlib.util.spec_from_file_location("make_example_meshes", REPO / "scripts" / "make_example_meshes.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def report() -> Report:
    return run_check(make_bundle(ROOT_FILE), CheckOptions())


def subjects(report: Report, code: str) -> list[str]:
    """The links ``code``'s findings are about, those a grouped finding stands for included."""
    return sorted(name for d in report.diagnostics if d.code == code for name in (str(d.link), *d.data.get("also", ())))


def subjects_of(d: Diagnostic) -> list[str]:
    return [str(d.link), *d.data.get("also", ())]


def test_meshes_are_what_the_script_generates(tmp_path: Path) -> None:
    written = load_mesh_script().write_meshes(tmp_path)
    committed = sorted(p.name for p in (PACKAGE / "meshes").iterdir())
    assert sorted(written) == committed == ["base.stl", "caster.stl", "laser.stl", "wheel.stl"]
    for name, path in written.items():
        assert path.read_bytes() == (PACKAGE / "meshes" / name).read_bytes(), name


def test_mesh_dimensions_follow_the_pr2() -> None:
    def extents(name: str) -> list[float]:
        mesh = trimesh.load(PACKAGE / "meshes" / name, force="mesh")
        assert mesh.is_watertight, name
        return np.round(mesh.extents, 4).tolist()

    assert extents("base.stl") == [0.66, 0.66, 0.9]
    assert extents("wheel.stl") == [0.158, 0.034, 0.158]  # uncompressed radius 0.079 m, axis y
    assert extents("caster.stl") == [0.187, 0.15, 0.193]
    assert max(extents("laser.stl")) < 0.06


def test_package_is_found_from_the_root_file() -> None:
    bundle = make_bundle(ROOT_FILE)
    assert bundle.packages["pr2_base_example"] == PACKAGE
    assert MAIN_COMMAND in (REPO / "README.md").read_text()


def test_robot_shape(report: Report) -> None:
    robot = report.robot
    # base_footprint + base + laser + 4 casters + 8 wheels
    assert (robot.name, robot.links, robot.joints) == ("pr2_base_example", 15, 14)
    assert (robot.meshes_total, robot.meshes_loaded) == (4, 4)
    assert report.skipped == ()
    assert [e["link"] for e in report.sections["inertia"]] == [
        "base_link",
        "base_laser_link",
        *[
            link
            for c in CASTERS
            for link in (f"{c}_caster_rotation_link", f"{c}_caster_l_wheel_link", f"{c}_caster_r_wheel_link")
        ],
    ]


def test_expected_findings(report: Report) -> None:
    counts = Counter(d.code for d in report.diagnostics)
    # one legacy-syntax warning per xacro file
    legacy = sorted(
        str(d.location.file).split("pr2_base/")[-1] for d in report.diagnostics if d.code == "GC103" and d.location
    )
    assert legacy == LEGACY_FILES
    # the PR2's thin collision slabs: 0.04 m on a 0.90 m base, 0.013 m on a 0.193 m caster housing
    assert subjects(report, "GC301") == sorted(["base_link", *HUBS])
    # the caster macro's one box is one finding naming the other three casters
    (hubs,) = [d for d in report.diagnostics if d.code == "GC301" and d.link in HUBS]
    assert [hubs.link, *hubs.data["also"]] == sorted(HUBS)
    assert hubs.message.endswith("(also in br_caster_rotation_link, fl_caster_rotation_link, fr_caster_rotation_link)")
    # the PR2 wheel tensor (its caster hub's) and the PR2 laser's 1 g with 1e-4 kg m^2
    assert subjects(report, "GC505") == sorted(["base_laser_link", *WHEELS])
    assert subjects(report, "GC507") == sorted(WHEELS)
    assert set(counts) - {"GC103", "GC301", "GC505", "GC507"} <= {c for c in counts if c.startswith("GC4")}
    assert not [d for d in report.diagnostics if d.code.startswith("GC4") and d.severity.value == "error"]
    # the wheel's collision cylinder lies along the wheel's axis: no axis or offset finding
    assert not [d for d in report.diagnostics if d.link in WHEELS and d.code.startswith("GC3")]
    assert report.failed


def test_wheel_finding_points_at_the_macro(report: Report) -> None:
    d = next(d for d in report.diagnostics if d.code == "GC505" and "fl_caster_l_wheel_link" in subjects_of(d))
    assert d.location is not None and d.location.file.endswith("examples/pr2_base/urdf/base.urdf.xacro")
    lines = (PACKAGE / "urdf" / "base.urdf.xacro").read_text().splitlines()
    assert d.location.line is not None and lines[d.location.line - 1].strip() == "<inertial>"
    assert "0.44036" in lines[d.location.line]
    assert "radius of gyration of 0.186 m about the link y axis" in d.message


def test_main_command_from_the_repo_root(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)
    outputs = []
    for _ in range(2):
        out = io.StringIO()
        with redirect_stdout(out):
            status = main(["check", "examples/pr2_base/robots/pr2_base.urdf.xacro", "--format", "json"])
        assert status == 1
        outputs.append(out.getvalue())
    assert outputs[0] == outputs[1]  # same input, same bytes
    data = json.loads(outputs[0])
    assert data["robot"]["source"] == "examples/pr2_base/robots/pr2_base.urdf.xacro"
    assert data["verdict"] == "fail"
