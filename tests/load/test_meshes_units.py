"""Mesh units: a COLLADA file's declared <unit meter> is applied as RViz and Gazebo apply it,
its <up_axis> is not (no ROS consumer applies it); formats without units are read as metres."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.cache import open_store, using_store
from geomcheck.diagnostics import Severity
from geomcheck.load import LoadedMesh, MeshProblem, MeshStore, make_bundle
from geomcheck.load.mesh_units import DeclaredUnitError, collada_unit
from geomcheck.load.meshes import MESH_READER_VERSION, parse_mesh
from geomcheck.model import Mesh
from geomcheck.options import CheckOptions, Selection
from geomcheck.pipeline import run_check

# a tetrahedron 10 x 20 x 40 file units, its corner at the origin
TETRA = [(0, 0, 0), (10, 0, 0), (0, 20, 0), (0, 0, 40)]
TETRA_FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
IDENTITY = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"


def collada(
    unit: str | None = None,
    up_axis: str | None = None,
    matrix: str = IDENTITY,
    unit_attributes: str | None = None,
    vertices: list | np.ndarray = TETRA,
    faces: list | np.ndarray = TETRA_FACES,
) -> bytes:
    """A COLLADA 1.4.1 document holding ``vertices`` and ``faces`` (the tetrahedron), placed
    by ``matrix`` (row-major 4x4), with ``<unit meter=unit>`` and ``<up_axis>`` when given."""
    positions = " ".join(f"{v:g}" for p in vertices for v in p)
    indices = " ".join(str(int(i)) for f in faces for i in f)
    n, m = len(vertices), len(faces)
    asset = "<contributor/>"
    if unit_attributes is not None:
        asset += f"<unit {unit_attributes}/>"
    elif unit is not None:
        asset += f'<unit name="u" meter="{unit}"/>'
    if up_axis is not None:
        asset += f"<up_axis>{up_axis}</up_axis>"
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>{asset}</asset>
  <library_geometries>
    <geometry id="tetra" name="tetra"><mesh>
      <source id="tetra-positions">
        <float_array id="tetra-positions-array" count="{3 * n}">{positions}</float_array>
        <technique_common><accessor source="#tetra-positions-array" count="{n}" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="tetra-vertices"><input semantic="POSITION" source="#tetra-positions"/></vertices>
      <triangles count="{m}"><input semantic="VERTEX" source="#tetra-vertices" offset="0"/><p>{indices}</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene" name="scene">
      <node id="part" name="part"><matrix sid="transform">{matrix}</matrix>
        <instance_geometry url="#tetra"/></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>""".encode()


def bounds(data: bytes) -> np.ndarray:
    arrays = parse_mesh(data, "dae")
    return np.array([arrays["vertices"].min(axis=0), arrays["vertices"].max(axis=0)])


@pytest.mark.parametrize(
    ("unit", "up_axis", "expected"),
    [
        ("0.0254", "Z_UP", [[0, 0, 0], [0.254, 0.508, 1.016]]),  # inches
        ("0.001", "Z_UP", [[0, 0, 0], [0.01, 0.02, 0.04]]),  # millimetres
        # the up axis is not applied: RViz, MoveIt and pinocchio drop assimp's Y-up root
        # transform, Gazebo never reads it; only the unit is
        ("0.001", "Y_UP", [[0, 0, 0], [0.01, 0.02, 0.04]]),
        ("0.01", "X_UP", [[0, 0, 0], [0.1, 0.2, 0.4]]),
        ("1", "Y_UP", [[0, 0, 0], [10, 20, 40]]),
        (None, None, [[0, 0, 0], [10, 20, 40]]),  # no declaration: metres
    ],
)
def test_collada_unit_is_applied_and_up_axis_is_not(unit: str | None, up_axis: str | None, expected: list) -> None:
    assert bounds(collada(unit, up_axis)) == pytest.approx(np.array(expected))
    assert float(parse_mesh(collada(unit, up_axis), "dae")["unit"]) == pytest.approx(float(unit or 1))


def test_unit_scales_the_node_placement_too() -> None:
    # a node moved 100 file units along x: with millimetres, the part sits 0.1 m away (RViz and
    # Gazebo scale the vertices after every node transform)
    moved = "1 0 0 100 0 1 0 0 0 0 1 0 0 0 0 1"
    assert bounds(collada("0.001", "Z_UP", moved)) == pytest.approx(np.array([[0.1, 0, 0], [0.11, 0.02, 0.04]]))


@pytest.mark.parametrize(
    ("attributes", "expected"),
    [
        ('name="inch" meter="0.0254"', 0.0254),
        ('meter=" 1e-3 "', 0.001),  # a number however spelt
        ('name="meter"', 1.0),  # no meter attribute: RViz keeps its default
        ('meter="one"', 1.0),  # not a number: likewise
    ],
)
def test_collada_unit_reads_the_meter_attribute(attributes: str, expected: float) -> None:
    assert collada_unit(collada(unit_attributes=attributes)) == pytest.approx(expected)


def test_collada_unit_is_the_first_asset_of_the_document_only() -> None:
    # a <unit> of a nested asset (a node's own) is not the document's: RViz reads <COLLADA><asset><unit>
    data = collada().replace(b"<node id=", b'<asset><unit meter="0.001"/></asset><node id=', 1)
    assert collada_unit(data) == 1.0
    assert collada_unit(b"<other><asset><unit meter='0.001'/></asset></other>") == 1.0
    assert collada_unit(b"not xml at all") == 1.0


@pytest.mark.parametrize("meter", ["0", "-0.001", "inf", "nan"])
def test_a_unit_that_is_no_length_is_refused(meter: str) -> None:
    with pytest.raises(DeclaredUnitError, match="not a positive length"):
        collada_unit(collada(meter))


def write(tmp_path: Path, name: str, data: bytes) -> Path:
    (tmp_path / name).write_bytes(data)
    root = tmp_path / "robot.urdf"
    root.write_text('<robot name="r"/>')
    return root


def test_store_applies_the_unit_before_the_urdf_scale(tmp_path: Path) -> None:
    root = write(tmp_path, "part.dae", collada("0.0254", "Z_UP"))
    store = MeshStore(make_bundle(root, search=[]))
    plain = store.get(Mesh("part.dae"))
    doubled = store.get(Mesh("part.dae", (2.0, 2.0, 2.0)))
    assert isinstance(plain, LoadedMesh) and isinstance(doubled, LoadedMesh)
    assert plain.unit == pytest.approx(0.0254) and doubled.unit == pytest.approx(0.0254)
    assert plain.mesh.extents == pytest.approx((0.254, 0.508, 1.016))
    assert doubled.mesh.extents == pytest.approx((0.508, 1.016, 2.032))
    assert store.files_read == 1


def test_a_unit_that_is_no_length_makes_the_mesh_unreadable(tmp_path: Path) -> None:
    root = write(tmp_path, "part.dae", collada("0"))
    problem = MeshStore(make_bundle(root, search=[])).get(Mesh("part.dae"))
    assert isinstance(problem, MeshProblem)
    assert problem.kind == "unreadable"
    assert 'its <unit meter="0"> is not a positive length' in problem.message


def test_formats_without_units_are_metres(tmp_path: Path) -> None:
    box = trimesh.creation.box(extents=(0.1, 0.2, 0.3))
    for name in ("part.stl", "part.obj", "part.ply", "part.off"):
        box.export(tmp_path / name)
    root = write(tmp_path, "unused.dae", collada())
    store = MeshStore(make_bundle(root, search=[]))
    for name in ("part.stl", "part.obj", "part.ply", "part.off"):
        loaded = store.get(Mesh(name))
        assert isinstance(loaded, LoadedMesh), name
        assert loaded.unit == 1.0
        assert loaded.mesh.extents == pytest.approx((0.1, 0.2, 0.3)), name


def test_the_mesh_load_cache_is_keyed_by_the_reader(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    root = write(tmp_path, "part.dae", collada("0.001"))

    def entries() -> int:
        return sum(1 for p in (tmp_path / "cache").rglob("*") if p.is_file() and "mesh-load" in p.parts)

    store = open_store(tmp_path / "cache")
    with using_store(store):
        first = MeshStore(make_bundle(root, search=[])).get(Mesh("part.dae"))
        again = MeshStore(make_bundle(root, search=[])).get(Mesh("part.dae"))
        assert entries() == 1
        monkeypatch.setattr("geomcheck.load.meshes.MESH_READER_VERSION", MESH_READER_VERSION + 1)
        other = MeshStore(make_bundle(root, search=[])).get(Mesh("part.dae"))
        assert entries() == 2  # another reader never takes the triangles an older one stored
    for loaded in (first, again, other):
        assert isinstance(loaded, LoadedMesh)
        assert loaded.mesh.extents == pytest.approx((0.01, 0.02, 0.04))


LEG_URDF = """<robot name="r">
  <link name="base"><collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision></link>
  <link name="leg">
    <visual><geometry><mesh filename="leg.dae"/></geometry></visual>
    <collision><geometry>COLLISION</geometry></collision>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="leg"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


def leg_report(tmp_path: Path, collision: str) -> list:
    """GC2 findings of a 0.3 m leg exported in inches (a box 12 file units long, declared
    <unit meter="0.0254">) as the visual, with ``collision`` as its collision geometry."""
    part = trimesh.creation.box(extents=(2.0, 2.0, 12.0))
    (tmp_path / "leg.dae").write_bytes(collada("0.0254", "Z_UP", vertices=part.vertices, faces=part.faces))
    (tmp_path / "robot.urdf").write_text(LEG_URDF.replace("COLLISION", collision))
    selection = Selection(select=("GC2",))
    return list(
        run_check(make_bundle(tmp_path / "robot.urdf", search=[]), CheckOptions(selection=selection)).diagnostics
    )


def test_a_collada_link_in_inches_is_judged_at_its_declared_size(tmp_path: Path) -> None:
    # no size finding, where reading the file units as metres found a mesh of 12 m (GC205, 39.37x);
    # the declared unit itself is information on a visual: RViz and Gazebo draw it at 0.3 m
    [d] = leg_report(tmp_path, '<box size="0.05 0.05 0.3"/>')
    assert (d.code, d.severity, d.link, d.about) == ("GC209", Severity.INFO, "leg", "visual[0]")
    assert d.data["size"] == pytest.approx(0.3048) and d.data["size_unapplied"] == pytest.approx(12.0)
    leg = MeshStore(make_bundle(tmp_path / "robot.urdf", search=[])).get(Mesh("leg.dae"))
    assert isinstance(leg, LoadedMesh)
    assert leg.mesh.extents == pytest.approx((0.0508, 0.0508, 0.3048))


def test_a_collision_mesh_in_a_declared_unit_is_an_error(tmp_path: Path) -> None:
    # MoveIt and pinocchio drop assimp's root transform, and the unit with it: they collide a 12 m leg
    found = {d.about: d for d in leg_report(tmp_path, '<mesh filename="leg.dae"/>')}
    assert sorted(found) == ["collision[0]", "visual[0]"]
    d = found["collision[0]"]
    assert (d.code, d.severity) == ("GC209", Severity.ERROR)
    assert d.message == (
        'collision[0] mesh leg.dae declares <unit meter="0.0254">: RViz and Gazebo apply it (0.305 m across), '
        "MoveIt and pinocchio do not (12 m across)"
    )
    assert d.data["suggested_scale"] == "0.0254 0.0254 0.0254"
    assert found["visual[0]"].severity == Severity.INFO


def test_a_size_finding_names_the_declared_unit_it_applied(tmp_path: Path) -> None:
    # a tetrahedron 40 file units tall declared in kilometres: 40 km, whatever the scale
    (tmp_path / "part.dae").write_bytes(collada("1000", "Z_UP"))
    (tmp_path / "robot.urdf").write_text(
        '<robot name="r"><link name="body"><visual><geometry><mesh filename="part.dae"/></geometry></visual></link>'
        "</robot>"
    )
    report = run_check(
        make_bundle(tmp_path / "robot.urdf", search=[]), CheckOptions(selection=Selection(select=("GC2",)))
    )
    [d] = [d for d in report.diagnostics if d.code != "GC209"]
    assert d.code == "GC206" and d.data["size"] == pytest.approx(40000.0)
    assert d.message.endswith('; its declared <unit meter="1000"> is applied, as RViz and Gazebo apply it')


def test_a_part_exported_as_many_files_in_one_unit_is_one_finding(tmp_path: Path) -> None:
    """A link drawn by 18 COLLADA files in millimetres: one GC209 naming the other 17, as
    repeats of a macro are one finding; another link's, or the collision meshes', stay apart."""
    part = trimesh.creation.box(extents=(20.0, 20.0, 120.0))
    visuals = ""
    for index in range(18):
        (tmp_path / f"shell{index}.dae").write_bytes(collada("0.001", "Z_UP", vertices=part.vertices, faces=part.faces))
        visuals += f'<visual><geometry><mesh filename="shell{index}.dae"/></geometry></visual>'
    (tmp_path / "robot.urdf").write_text(
        '<robot name="r"><link name="body">'
        f'{visuals}<collision><geometry><mesh filename="shell0.dae"/></geometry></collision></link>'
        '<link name="arm"><visual><geometry><mesh filename="shell1.dae"/></geometry></visual></link>'
        '<joint name="j" type="fixed"><parent link="body"/><child link="arm"/></joint></robot>'
    )
    report = run_check(
        make_bundle(tmp_path / "robot.urdf", search=[]), CheckOptions(selection=Selection(select=("GC209",)))
    )
    found = sorted(((d.link, d.about, d.severity) for d in report.diagnostics), key=lambda f: (f[0], f[1]))
    assert found == [
        ("arm", "visual[0]", Severity.INFO),
        ("body", "collision[0]", Severity.ERROR),
        ("body", "visual[0]", Severity.INFO),
    ]
    [grouped] = [d for d in report.diagnostics if d.link == "body" and d.about == "visual[0]"]
    assert grouped.data["meshes"] == [f"shell{i}.dae" for i in range(1, 18)]
    assert grouped.message.endswith(
        "(also 17 more visual meshes: shell1.dae, shell2.dae, shell3.dae, shell4.dae, shell5.dae and 12 more files)"
    )
