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
import struct
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, example, given, note
from hypothesis import strategies as st

from geomcheck.cli import main
from tests.load.fuzztools import bounded, fuzz_settings

pytestmark = pytest.mark.long

# data_too_large: a binary STL of 30 triangles with float64 coordinates exceeds hypothesis's
# default buffer at times; such draws are discarded, not failures
FUZZ = fuzz_settings(300, HealthCheck.data_too_large)  # GEOMCHECK_FUZZ_EXAMPLES=5000 for a long campaign
URDF = """<?xml version="1.0"?>
<robot name="mesh_fuzz">
  <link name="base_link">
    <visual><geometry><mesh filename="{name}"{scale}/></geometry></visual>
    <collision><geometry>{collision}</geometry></collision>
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
</robot>
"""
BOX = '<box size="0.2 0.2 0.2"/>'
SCALES = [
    "",
    ' scale="1 1 1"',
    ' scale="0.001 0.001 0.001"',
    ' scale="-1 1 1"',
    ' scale="1 1 0"',
    ' scale="1e5 1e5 1e5"',
]
SCALES += [' scale="1e-30 1e-30 1e-30"', ' scale="0 0 0"']
SPECIAL = [0.0, -0.0, 1.0, -1.0, 1e-30, 1e30, 1e308, -1e308, float("nan"), float("inf"), float("-inf")]
coordinate = st.one_of(st.floats(min_value=-2.0, max_value=2.0), st.sampled_from(SPECIAL))
vertex = st.tuples(coordinate, coordinate, coordinate)
FLOAT32_MAX = 3.4028234663852886e38
# binary STL holds float32: the largest finite one instead of the float64 extremes
coordinate32 = st.one_of(
    st.floats(min_value=-2.0, max_value=2.0, width=32),
    st.sampled_from([v if abs(v) != 1e308 else FLOAT32_MAX * (v / abs(v)) for v in SPECIAL]),
)
vertex32 = st.tuples(coordinate32, coordinate32, coordinate32)


@st.composite
def binary_stl(draw: st.DrawFn) -> tuple[str, bytes]:
    triangles = draw(st.lists(st.tuples(vertex32, vertex32, vertex32), max_size=30))
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


TETRAHEDRON = [(0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.0, 0.0, 0.1)]
TETRAHEDRON_FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


@st.composite
def near_solid(draw: st.DrawFn) -> tuple[str, bytes]:
    """A closed tetrahedron made degenerate: scaled far, corners collapsed or flattened, one
    corner replaced by a special number; written as OBJ or ASCII STL. These reach the
    geometry (hulls, inertia, fit) where the random files above stop at the reader."""
    # half the draws keep a sound solid, moved by up to 5 cm per coordinate: the checks run to the end
    factor = draw(st.one_of(st.just(1.0), st.sampled_from([1e-30, 1e-12, 1e-3, 1e3, 1e5, 1e6, 1e30])))
    jitter = st.floats(min_value=-0.05, max_value=0.05)
    points = [[(c + draw(jitter)) * factor for c in p] for p in TETRAHEDRON]
    change = draw(st.one_of(st.just("none"), st.sampled_from(["collapse", "flatten", "line", "special"])))
    if change == "collapse":
        points = [points[0]] * 4
    elif change == "flatten":
        points = [[x, y, 0.0] for x, y, _ in points]
    elif change == "line":
        points = [[x, 0.0, 0.0] for x, _, _ in points]
    elif change == "special":
        points[draw(st.integers(0, 3))][draw(st.integers(0, 2))] = draw(st.sampled_from(SPECIAL))
    if draw(st.booleans()):
        text = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in points)
        text += "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in TETRAHEDRON_FACES)
        return "part.obj", text.encode()
    facets = "".join(
        "facet normal 0 0 0\n outer loop\n"
        + "".join(f"  vertex {points[i][0]!r} {points[i][1]!r} {points[i][2]!r}\n" for i in face)
        + " endloop\nendfacet\n"
        for face in TETRAHEDRON_FACES
    )
    return "part.stl", f"solid fuzz\n{facets}endsolid fuzz\n".encode()


garbage = st.tuples(st.sampled_from(["part.stl", "part.obj", "part.dae", "part.STL"]), st.binary(max_size=300))
meshes = st.one_of(
    binary_stl(), ascii_stl(), obj(), collada(), near_solid(), near_solid(), garbage, st.just(("part.stl", b""))
)


def run_check(folder: Path) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        # the mesh, fit and inertia families read the mesh; self-collision adds nothing here
        argv = ["check", str(folder / "robot.urdf"), "--format", "json", "--no-sweep", "--no-untrusted"]
        status = main([*argv, "--select", "GC1,GC2,GC3,GC5"])
    return status, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module", autouse=True)
def _warm() -> None:
    """One untimed run first: the time limit is about the input, not about importing trimesh."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "part.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        (folder / "robot.urdf").write_text(URDF.format(name="part.obj", scale="", collision=BOX), encoding="utf-8")
        run_check(folder)


# what the fuzzer found, replayed first on every run (docs/robustness.md)
HUGE_STL = (
    b"solid fuzz\nfacet normal 0 0 0\n outer loop\n  vertex -0.8537755732687253 1e+30 1e+308\n"
    b"  vertex -1e+308 0.0 -0.26536340339172915\n  vertex 1e-30 0.0 1e+30\n endloop\nendfacet\nendsolid fuzz\n"
)
TINY_OBJ = (
    b"v 2.5259432393004743e-171 -3.0331857729269375e-153 0.0\nv 1.3964054163829025e-13 -3.782876107845237e-15 0.0\n"
    b"v 1.4602941447863045e-89 8.064973809944341e-14 0.0\nv -2.949903194376242e-14 9.999999999999999e-19 0.0\n"
    b"f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
)
INF_STL = b"\0" * 80 + struct.pack("<I", 1) + struct.pack("<12fH", 0, 0, 0, 0, 0, 0, float("inf"), 0, 0, 0, 1, 0, 0)


@FUZZ
@example(mesh=("part.stl", HUGE_STL), scale="", mesh_collision=False)  # overflow in the vertex welding
@example(mesh=("part.stl", INF_STL), scale=' scale="0 0 0"', mesh_collision=True)  # inf * 0 in the scaling
@example(mesh=("part.obj", TINY_OBJ), scale=' scale="0.001 0.001 0.001"', mesh_collision=True)  # overflow in a ratio
@given(mesh=meshes, scale=st.one_of(st.just(""), st.sampled_from(SCALES)), mesh_collision=st.booleans())
def test_fuzzed_meshes_end_in_a_report_or_one_line(mesh: tuple[str, bytes], scale: str, mesh_collision: bool) -> None:
    name, data = mesh
    collision = f'<mesh filename="{name}"{scale}/>' if mesh_collision else BOX
    note(f"{name}{scale} (collision: {mesh_collision}): {data!r}")  # printed with a failure: the input to reproduce
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / name).write_bytes(data)
        (folder / "robot.urdf").write_text(URDF.format(name=name, scale=scale, collision=collision), encoding="utf-8")
        with bounded():  # time, peak memory, and no warning escaping the library
            status, out, err = run_check(folder)
    assert "Traceback" not in err and "internal error" not in err, err
    event(f"exit {status}")  # the outcomes' spread, shown by --hypothesis-show-statistics
    if status == 2:
        assert out == "" and err.count("\n") == 1 and err.startswith("geomcheck: error: "), err
        return
    assert status in (0, 1)
    assert err == "", f"library output leaked to stderr: {err[:300]}"
    report = json.loads(out)
    assert report["robot"]["meshes_total"] == 1
    event(f"mesh codes {sorted({d['code'] for d in report['diagnostics'] if d['code'].startswith('GC2')})}")
    if report["robot"]["meshes_loaded"] == 0:
        assert any(d["code"].startswith("GC2") for d in report["diagnostics"]), "an unreadable mesh is a GC2xx finding"
