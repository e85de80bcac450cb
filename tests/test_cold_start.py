"""Cold start: the commands that compute nothing import neither the numeric and mesh
libraries, the collision backends nor the service; ``check`` imports what the selected rule
families need. Each command runs in a fresh interpreter and reports ``sys.modules``."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"
HEAVY = ("numpy", "scipy", "trimesh", "coal", "fcl", "networkx", "api", "fastapi", "uvicorn", "sqlalchemy", "celery")

PROBE = """
import contextlib, io, json, sys
from geomcheck.cli import main
with contextlib.redirect_stdout(io.StringIO()):
    try:
        status = main(sys.argv[1:])
    except SystemExit as exit:  # --version
        status = exit.code
print(json.dumps({"status": status, "modules": sorted({name.split(".")[0] for name in sys.modules})}))
"""

PLAIN_URDF = """<robot name="plain">
  <link name="base"><collision><geometry><box size="1 1 1"/></geometry></collision></link>
  <link name="arm"><collision><geometry><cylinder radius="0.1" length="1"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def imported(*argv: str, cwd: Path | None = None) -> tuple[int, set[str]]:
    """Exit status of ``geomcheck argv`` in a new interpreter and the top-level packages it imported."""
    proc = subprocess.run(
        [sys.executable, "-c", PROBE, *argv], capture_output=True, text=True, timeout=300, cwd=cwd, check=False
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.splitlines()[-1])
    return int(out["status"] or 0), set(out["modules"])


@pytest.mark.parametrize("argv", [("--version",), ("rules",), ("rules", "--format", "json"), ("rule", "GC301")])
def test_commands_that_compute_nothing_start_light(argv: tuple[str, ...]) -> None:
    status, modules = imported(*argv)
    assert status == 0
    assert "geomcheck" in modules
    assert modules.isdisjoint(HEAVY), sorted(modules & set(HEAVY))


def test_structure_only_check_needs_no_mesh_or_collision_library(tmp_path: Path) -> None:
    (tmp_path / "plain.urdf").write_text(PLAIN_URDF)
    status, modules = imported("check", "plain.urdf", "--select", "GC1", "--no-cache", cwd=tmp_path)
    assert status == 0
    assert modules.isdisjoint({"scipy", "trimesh", "coal", "fcl", "api", "fastapi"}), modules


def test_check_without_self_collision_rules_imports_no_collision_backend(tmp_path: Path) -> None:
    selected = "GC1,GC2,GC3,GC5"
    status, modules = imported("check", str(EXAMPLE), "--select", selected, "--no-cache", cwd=tmp_path)
    assert status == 1  # the example keeps the real PR2's defects
    # meshes and fits read STL with numpy and hull with qhull; primitives are tessellated, hulls
    # weighed and distances to them measured as trimesh does it, without trimesh
    assert "scipy" in modules and "trimesh" not in modules and "coal" not in modules and "api" not in modules
    status, modules = imported("check", str(EXAMPLE), "--select", "GC4", "--no-cache", cwd=tmp_path)
    assert "coal" in modules


MESH_PROBE = """
import contextlib, io, json, sys
from geomcheck.load.meshes import MeshStore
asked = []
get = MeshStore.get
def counted(self, mesh):
    asked.append(mesh.filename)
    return get(self, mesh)
MeshStore.get = counted
from geomcheck.cli import main
out = io.StringIO()
with contextlib.redirect_stdout(out):
    status = main(sys.argv[1:])
robot = json.loads(out.getvalue())["robot"]
print(json.dumps({"status": status, "modules": sorted({n.split(".")[0] for n in sys.modules}), "asked": asked,
                  "robot": robot}))
"""


def structure_only(root: Path, *argv: str, cwd: Path) -> tuple[int, set[str], list[str], dict[str, int]]:
    """``geomcheck check root --select GC1 --format json`` in a new interpreter: exit status,
    top-level packages imported, meshes asked of the mesh store, the report's ``robot``."""
    command = [sys.executable, "-c", MESH_PROBE, "check", str(root), *argv, "--select", "GC1", "--format", "json"]
    proc = subprocess.run(command, capture_output=True, text=True, timeout=300, cwd=cwd, check=False)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.splitlines()[-1])
    return int(out["status"] or 0), set(out["modules"]), out["asked"], out["robot"]


def test_structure_rules_alone_read_no_mesh_of_the_example(tmp_path: Path) -> None:
    status, modules, asked, robot = structure_only(EXAMPLE, "--no-cache", cwd=tmp_path)
    assert status == 0  # the example's defects are in its geometry, not its structure
    assert "trimesh" not in modules and "coal" not in modules and "scipy" not in modules
    assert asked == []
    assert (robot["links"], robot["meshes_total"], robot["meshes_loaded"]) == (15, 4, 0)


@pytest.mark.corpus
def test_structure_rules_alone_read_no_mesh_of_the_full_pr2(pr2_root: Path, tmp_path: Path) -> None:
    root = pr2_root / "pr2_description" / "robots" / "pr2.urdf.xacro"
    status, modules, asked, robot = structure_only(root, "--search", str(pr2_root), cwd=tmp_path)
    assert status == 1  # GC1xx errors of the 2009 description (undeclared world link, joints without links)
    assert "trimesh" not in modules and "coal" not in modules and "scipy" not in modules
    assert asked == []
    assert (robot["links"], robot["meshes_total"], robot["meshes_loaded"]) == (72, 32, 0)


MESH_URDF = """<robot name="meshes">
  <link name="base">
    <visual><geometry><mesh filename="meshes/base.obj"/></geometry></visual>
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <visual><origin xyz="0 0 0.3"/><geometry><mesh filename="meshes/arm.stl" scale="0.001 0.001 0.001"/></geometry>
    </visual>
    <collision><origin xyz="0 0 0.3"/><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_a_warm_check_of_meshes_and_fits_imports_no_trimesh(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Neither run of the mesh, fit and view rules imports trimesh (OBJ and STL are read with
    numpy), and every mesh's triangles, hull and fit come from the cache the first run filled:
    the second run reads them as arrays and imports no scipy either."""
    import trimesh

    (tmp_path / "meshes").mkdir()
    trimesh.creation.box(extents=(0.2, 0.2, 0.1)).export(tmp_path / "meshes" / "base.obj")
    trimesh.creation.cylinder(radius=50.0, height=400.0).export(tmp_path / "meshes" / "arm.stl")
    (tmp_path / "robot.urdf").write_text(MESH_URDF)
    monkeypatch.setenv("GEOMCHECK_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("GEOMCHECK_UNTRUSTED", "0")  # checked in this interpreter, not in a worker
    argv = ("check", "robot.urdf", "--select", "GC2,GC3", "--format", "json", "-o", "report.json")
    cold_status, cold = imported(*argv, cwd=tmp_path)
    cold_report = json.loads((tmp_path / "report.json").read_text())
    # a file no check reads, added to the root file's folder: the whole report is checked again
    # (geomcheck.check_cache), each stage from its own cache
    (tmp_path / "notes.txt").write_text("not read")
    warm_status, warm = imported(*argv, cwd=tmp_path)
    warm_report = json.loads((tmp_path / "report.json").read_text())
    # the OBJ read, the primitives tessellated and the hulls made as trimesh does it, without it
    assert "trimesh" not in cold and "scipy" in cold and "scipy" not in warm
    assert "trimesh" not in warm and "networkx" not in warm and "coal" not in warm
    assert warm_status == cold_status
    assert warm_report["robot"]["meshes_loaded"] == 2
    fitted = [entry["link"] for entry in warm_report["sections"]["links"] if entry["union"] is not None]
    assert fitted == ["base", "arm"] and set(warm_report["sections"]) == {"links", "views", "scene"}
    for report in (cold_report, warm_report):
        report.pop("created")
    assert warm_report == cold_report


MATRIX_URDF = """<robot name="matrix">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="arm">
    <collision><origin xyz="0 0 0.3"/><geometry><mesh filename="meshes/arm.stl" scale="0.001 0.001 0.001"/></geometry>
    </collision>
  </link>
  <link name="hand"><collision><geometry><mesh filename="meshes/hand.stl"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="arm"/><child link="hand"/><origin xyz="0 0 0.6"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>
"""


def test_matrix_of_meshes_imports_no_trimesh(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The collision scene, its convex hulls and the engines work on the meshes' arrays: a
    cold ``matrix`` run over binary STL meshes never imports trimesh (nor networkx)."""
    import trimesh

    (tmp_path / "meshes").mkdir()
    trimesh.creation.cylinder(radius=50.0, height=400.0).export(tmp_path / "meshes" / "arm.stl")
    trimesh.creation.icosphere(subdivisions=2, radius=0.08).export(tmp_path / "meshes" / "hand.stl")
    (tmp_path / "robot.urdf").write_text(MATRIX_URDF)
    monkeypatch.setenv("GEOMCHECK_UNTRUSTED", "0")  # run in this interpreter, not in a worker
    argv = ("matrix", "robot.urdf", "--samples", "200", "--srdf-out", "robot.srdf", "--no-cache")
    status, modules = imported(*argv, cwd=tmp_path)
    assert status == 0
    assert "coal" in modules  # the scene was built and queried
    assert "trimesh" not in modules and "networkx" not in modules, sorted(modules & {"trimesh", "networkx"})
    srdf = (tmp_path / "robot.srdf").read_text()
    assert 'link1="arm" link2="hand"' in srdf or 'link1="hand" link2="arm"' in srdf


DRAWN_PROBE = PROBE.replace(
    '{name.split(".")[0] for name in sys.modules}',
    '{name for name in sys.modules if name.startswith("geomcheck.checks")}',
)


@pytest.mark.parametrize(("fmt", "drawn"), [("github", False), ("full", False), ("sarif", False), ("json", True)])
def test_only_an_output_that_shows_drawings_draws_them(fmt: str, drawn: bool, tmp_path: Path) -> None:
    """A CI gate's formats and the terminal show no view: the drawing families (views, 3D
    scene) are not even imported; the JSON report carries them to a later HTML render."""
    (tmp_path / "plain.urdf").write_text(PLAIN_URDF)
    proc = subprocess.run(
        [sys.executable, "-c", DRAWN_PROBE, "check", "plain.urdf", "--no-cache", "--format", fmt, "-o", "out"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    modules = set(json.loads(proc.stdout.splitlines()[-1])["modules"])
    assert "geomcheck.checks.fit" in modules and "geomcheck.checks.selfcollision" in modules
    assert (
        {"geomcheck.checks.views", "geomcheck.checks.scene"} <= modules
        if drawn
        else not modules
        & {
            "geomcheck.checks.views",
            "geomcheck.checks.scene",
        }
    )
    if drawn:
        assert {"views", "scene"} <= set(json.loads((tmp_path / "out").read_text())["sections"])
