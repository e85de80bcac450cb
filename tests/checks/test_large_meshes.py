"""Large meshes are checked in bounded memory, and the fit says how precise it is."""

from __future__ import annotations

import json
import resource
import subprocess
import sys
from pathlib import Path

import trimesh

GIB = 1024**3


def write_sphere_link(folder: Path, subdivisions: int) -> Path:
    """A one-link robot whose visual is an icosphere STL of radius 0.1 m in a 0.15 m box."""
    trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.1).export(folder / "ball.stl")
    urdf = folder / "ball.urdf"
    urdf.write_text(
        '<robot name="ball"><link name="ball">'
        '<visual><geometry><mesh filename="ball.stl"/></geometry></visual>'
        '<collision><geometry><box size="0.15 0.15 0.15"/></geometry></collision>'
        "</link></robot>\n"
    )
    return urdf


def limit_address_space() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (GIB, GIB))


def test_a_mesh_of_300k_triangles_is_checked_within_1_gib(tmp_path: Path) -> None:
    urdf = write_sphere_link(tmp_path, 7)  # 327,680 triangles, every vertex on the hull
    out = tmp_path / "report.json"
    proc = subprocess.run(
        [sys.executable, "-m", "geomcheck", "check", str(urdf), "--format", "json", "-o", str(out), "--no-config"],
        capture_output=True,
        text=True,
        preexec_fn=limit_address_space,
        env={"PATH": "/usr/bin:/bin", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"},
        timeout=300,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]  # a warning: exit 0
    report = json.loads(out.read_text())
    (link,) = report["sections"]["links"]
    assert link["visual_meshes"][0]["loaded"] is True
    precision = link["precision"]
    assert precision["surface_samples"] == 2000
    assert 0.0 < precision["hull_tolerance_mm"] <= 0.2  # 5e-4 of the 0.35 m diagonal
    fit = link["collisions"][0]["fit"]
    assert abs(fit["protrusion_max_mm"] - 25.0) <= 0.2  # radius 100 mm against a half-width of 75 mm
    assert fit["suggested"]["type"] == "box"
    assert all(abs(v - 0.2) < 0.001 for v in fit["suggested"]["geometry"]["size"])
    assert [(d["code"], d["link"]) for d in report["diagnostics"]] == [("GC301", "ball")]
