"""Property-based fuzzing of the mesh readers through the CLI: truncated binary STL, headers
claiming billions of triangles, NaN and huge vertices, OBJ faces out of range, COLLADA with
broken references, empty and random files.

Every mesh ends as a loaded mesh or a GC2xx finding: exit 0 or 1 with a JSON report, or exit
2 with one line; no traceback, no library warning on stderr (numpy's RuntimeWarnings on
degenerate meshes), never more than 10 s.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import struct
import tempfile
import time
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from geomcheck.cli import main

# Opt-in until the open findings are fixed (docs/robustness.md: a RuntimeWarning escaping the
# mesh code, an example of the description fuzzer that runs for minutes): GEOMCHECK_FUZZ=1.
pytestmark = pytest.mark.skipif(
    os.environ.get("GEOMCHECK_FUZZ") != "1", reason="fuzz tests are opt-in for now: set GEOMCHECK_FUZZ=1"
)

MAX_SECONDS = 10.0
FUZZ = settings(
    max_examples=15,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    database=None,
    phases=[Phase.explicit, Phase.generate],  # no shrinking: a failure is reported as generated, CI stays bounded
)
URDF = """<?xml version="1.0"?>
<robot name="mesh_fuzz">
  <link name="base_link">
    <visual><geometry><mesh filename="{name}"/></geometry></visual>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
</robot>
"""
SPECIAL = [0.0, -0.0, 1.0, -1.0, 1e-30, 1e30, 1e308, -1e308, float("nan"), float("inf"), float("-inf")]
coordinate = st.one_of(st.floats(min_value=-2.0, max_value=2.0), st.sampled_from(SPECIAL))
vertex = st.tuples(coordinate, coordinate, coordinate)


@st.composite
def binary_stl(draw: st.DrawFn) -> tuple[str, bytes]:
    triangles = draw(st.lists(st.tuples(vertex, vertex, vertex), max_size=30))
    claimed = draw(st.one_of(st.just(len(triangles)), st.sampled_from([0, 1, 2**31 - 1, 2**32 - 1, 4_000_000_000])))
    body = b"".join(struct.pack("<12fH", 0, 0, 0, *a, *b, *c, 0) for a, b, c in triangles)
    data = b"\0" * 80 + struct.pack("<I", claimed) + body
    cut = draw(st.one_of(st.none(), st.integers(min_value=0, max_value=len(data))))
    return "part.stl", data if cut is None else data[:cut]


@st.composite
def ascii_stl(draw: st.DrawFn) -> tuple[str, bytes]:
    triangles = draw(st.lists(st.tuples(vertex, vertex, vertex), max_size=20))
    facets = "".join(
        "facet normal 0 0 0\n outer loop\n"
        + "".join(f"  vertex {x!r} {y!r} {z!r}\n" for x, y, z in t)
        + " endloop\nendfacet\n"
        for t in triangles
    )
    text = f"solid fuzz\n{facets}endsolid fuzz\n"
    cut = draw(st.one_of(st.none(), st.integers(min_value=0, max_value=len(text))))
    return "part.stl", (text if cut is None else text[:cut]).encode()


@st.composite
def obj(draw: st.DrawFn) -> tuple[str, bytes]:
    vertices = draw(st.lists(vertex, max_size=20))
    index = st.integers(min_value=-30, max_value=2**31)
    faces = draw(st.lists(st.tuples(index, index, index), max_size=20))
    text = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in vertices) + "".join(f"f {a} {b} {c}\n" for a, b, c in faces)
    return "part.obj", text.encode()


@st.composite
def collada(draw: st.DrawFn) -> tuple[str, bytes]:
    points = draw(st.lists(coordinate, max_size=18))
    count = draw(st.one_of(st.just(len(points)), st.integers(min_value=0, max_value=10**9)))
    source = draw(st.sampled_from(["#pos", "#missing", "", "file:///etc/passwd", "#"]))
    indices = " ".join(str(i) for i in draw(st.lists(st.integers(min_value=-5, max_value=100), max_size=12)))
    geometry = draw(st.sampled_from(["#geom", "#nothing", "other.dae#geom"]))
    text = f"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="{draw(st.sampled_from(["1", "0.001", "0", "-1", "nan", "x"]))}"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="geom"><mesh>
    <source id="pos"><float_array id="arr" count="{count}">{" ".join(repr(p) for p in points)}</float_array>
      <technique_common><accessor source="#arr" count="{count // 3}" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor>
      </technique_common></source>
    <vertices id="verts"><input semantic="POSITION" source="{source}"/></vertices>
    <triangles count="{len(indices.split()) // 3}">
      <input semantic="VERTEX" source="#verts" offset="0"/><p>{indices}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node><instance_geometry url="{geometry}"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""
    return "part.dae", text.encode()


garbage = st.tuples(st.sampled_from(["part.stl", "part.obj", "part.dae", "part.STL"]), st.binary(max_size=300))
meshes = st.one_of(binary_stl(), ascii_stl(), obj(), collada(), garbage, st.just(("part.stl", b"")))


def run_check(folder: Path) -> tuple[int, str, str, float]:
    out, err = io.StringIO(), io.StringIO()
    started = time.monotonic()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning that escapes the library fails the example
        # the mesh, fit and inertia families read the mesh; self-collision adds nothing here
        argv = ["check", str(folder / "robot.urdf"), "--format", "json", "--no-sweep", "--no-untrusted"]
        status = main([*argv, "--select", "GC1,GC2,GC3,GC5"])
    return status, out.getvalue(), err.getvalue(), time.monotonic() - started


@pytest.fixture(scope="module", autouse=True)
def _warm() -> None:
    """One untimed run first: the time limit is about the input, not about importing trimesh."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "part.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        (folder / "robot.urdf").write_text(URDF.format(name="part.obj"), encoding="utf-8")
        run_check(folder)


@FUZZ
@given(mesh=meshes)
def test_fuzzed_meshes_end_in_a_report_or_one_line(mesh: tuple[str, bytes]) -> None:
    name, data = mesh
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / name).write_bytes(data)
        (folder / "robot.urdf").write_text(URDF.format(name=name), encoding="utf-8")
        status, out, err, elapsed = run_check(folder)
    assert elapsed < MAX_SECONDS, f"{elapsed:.1f} s"
    assert "Traceback" not in err and "internal error" not in err, err
    if status == 2:
        assert out == "" and err.count("\n") == 1 and err.startswith("geomcheck: error: "), err
        return
    assert status in (0, 1)
    assert err == "", f"library output leaked to stderr: {err[:300]}"
    report = json.loads(out)
    assert report["robot"]["meshes_total"] == 1
    if report["robot"]["meshes_loaded"] == 0:
        assert any(d["code"].startswith("GC2") for d in report["diagnostics"]), "an unreadable mesh is a GC2xx finding"
