"""COLLADA read with lxml and numpy: bit for bit the arrays trimesh (through pycollada) reads,
and the trimesh path for what the reader does not reproduce."""

from __future__ import annotations

import copy
import random
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from geomcheck.load import meshes
from geomcheck.load.collada import read_collada
from geomcheck.load.meshes import parse_mesh, read_with_trimesh

# the corpus's COLLADA files the fast path reads (all of them, measured): a file it stops
# reading is a regression even when trimesh's path still gives the right arrays
CORPUS_FAST_PATH_FILES = 128
MUTATION_SEED = 20261127
MUTATIONS = 300  # altered documents compared with trimesh

NAMESPACE = "http://www.collada.org/2005/11/COLLADASchema"
TRIANGLE = '<input semantic="VERTEX" source="#{g}-vertices" offset="0"/>'

# a box 0.1 x 0.2 x 0.3 (values float32 cannot hold exactly), corner at (0.1, 0.1, 0.1)
BOX = [(x, y, z) for x in (0.1, 0.2) for y in (0.1, 0.3) for z in (0.1, 0.4)]
BOX_NORMALS = [(-1, 0, 0), (1, 0, 0), (0, -1, 0), (0, 1, 0), (0, 0, -1), (0, 0, 1)]
# each side as two triangles: corner indices with the side's normal index
BOX_SIDES = [
    ((0, 1, 3, 2), 0),
    ((4, 6, 7, 5), 1),
    ((0, 4, 5, 1), 2),
    ((2, 3, 7, 6), 3),
    ((0, 2, 6, 4), 4),
    ((1, 5, 7, 3), 5),
]
# a pentagonal prism: two pentagons and five quads
PENTAGON = [(0.0, 0.5), (0.47553, 0.15451), (0.29389, -0.40451), (-0.29389, -0.40451), (-0.47553, 0.15451)]
PRISM = [(x, y, z) for z in (0.0, 0.25) for x, y in PENTAGON]
PRISM_FACES = [(4, 3, 2, 1, 0), (5, 6, 7, 8, 9)] + [(i, (i + 1) % 5, 5 + (i + 1) % 5, 5 + i) for i in range(5)]


def numbers(values: list[tuple[float, ...]]) -> str:
    return " ".join(f"{v:.9g}" for row in values for v in row)


def source(name: str, values: list[tuple[float, ...]], params: str = "XYZ") -> str:
    """A ``<source>`` of float rows, one ``<param>`` per letter of ``params``."""
    count = len(values) * len(params)
    declared = "".join(f'<param name="{p}" type="float"/>' for p in params)
    return (
        f'<source id="{name}"><float_array id="{name}-array" count="{count}">{numbers(values)}</float_array>'
        f'<technique_common><accessor source="#{name}-array" count="{len(values)}" stride="{len(params)}">'
        f"{declared}</accessor></technique_common></source>"
    )


def geometry(name: str, positions: list[tuple[float, ...]], primitives: str, sources: str = "") -> str:
    """A ``<geometry>`` of ``positions`` (through ``<vertices>``), other ``sources`` and ``primitives``."""
    return (
        f'<geometry id="{name}"><mesh>{source(f"{name}-positions", positions)}{sources}'
        f'<vertices id="{name}-vertices"><input semantic="POSITION" source="#{name}-positions"/></vertices>'
        f"{primitives}</mesh></geometry>"
    )


def document(geometries: str, nodes: str, libraries: str = "", asset: str = "") -> bytes:
    """A COLLADA 1.4.1 document: ``libraries`` (effects, materials...), ``geometries``, and a
    default visual scene of ``nodes``."""
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="{NAMESPACE}" version="1.4.1">
  <asset><contributor/>{asset}<up_axis>Z_UP</up_axis></asset>
  {libraries}
  <library_geometries>{geometries}</library_geometries>
  <library_visual_scenes><visual_scene id="scene">{nodes}</visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>""".encode()


def box_triangles(name: str = "box", material: str = "") -> str:
    """The box's twelve triangles with a normal per side (positions at offset 0, normals at 1)."""
    rows = []
    for (a, b, c, d), normal in BOX_SIDES:
        rows += [a, normal, b, normal, c, normal, a, normal, c, normal, d, normal]
    bound = f' material="{material}"' if material else ""
    return (
        f'<triangles count="12"{bound}>{TRIANGLE.format(g=name)}'
        f'<input semantic="NORMAL" source="#{name}-normals" offset="1"/><p>{" ".join(map(str, rows))}</p></triangles>'
    )


def box(name: str = "box") -> str:
    return geometry(name, BOX, box_triangles(name), source(f"{name}-normals", BOX_NORMALS))


def trimesh_arrays(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """What parse_mesh read through trimesh before the fast path (unit not applied)."""
    read = read_with_trimesh(data, "dae")
    if read is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.asarray(read[0], dtype=float), np.asarray(read[1], dtype=np.int64)


def same_as_trimesh(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """The fast path's arrays, asserted to be trimesh's bit for bit."""
    fast = read_collada(data)
    assert fast is not None, "the fast path fell back"
    expected = trimesh_arrays(data)
    assert fast[0].dtype == np.float64 and fast[1].dtype == np.int64
    assert np.array_equal(fast[0], expected[0]), "vertices differ from trimesh's"
    assert np.array_equal(fast[1], expected[1]), "faces differ from trimesh's"
    return fast


def test_triangles_with_normals_weld_per_side() -> None:
    data = document(box(), '<node id="n"><instance_geometry url="#box"/></node>')
    vertices, faces = same_as_trimesh(data)
    # each of the 8 corners is on 3 sides, each side with its own normal: 24 vertices
    assert vertices.shape == (24, 3)
    assert faces.shape == (12, 3)
    assert np.array_equal(vertices[0], np.float32([0.1, 0.1, 0.1]).astype(np.float64))


def test_polylist_of_quads_and_pentagons_is_fan_triangulated() -> None:
    counts = " ".join(str(len(face)) for face in PRISM_FACES)
    rows = " ".join(str(i) for face in PRISM_FACES for i in face)
    polylist = f'<polylist count="7">{TRIANGLE.format(g="prism")}<vcount>{counts}</vcount><p>{rows}</p></polylist>'
    data = document(geometry("prism", PRISM, polylist), '<node id="n"><instance_geometry url="#prism"/></node>')
    vertices, faces = same_as_trimesh(data)
    assert vertices.shape == (10, 3)
    assert faces.shape == (2 * 3 + 5 * 2, 3)  # a pentagon makes three triangles, a quad two
    assert faces[:3].tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4]]  # the fan of the first pentagon


def test_polygons_read_as_polylist() -> None:
    polygons = "".join(f"<p>{' '.join(map(str, face))}</p>" for face in PRISM_FACES)
    primitive = f'<polygons count="7">{TRIANGLE.format(g="prism")}{polygons}</polygons>'
    data = document(geometry("prism", PRISM, primitive), '<node id="n"><instance_geometry url="#prism"/></node>')
    vertices, faces = same_as_trimesh(data)
    assert (len(vertices), len(faces)) == (10, 16)


TEXTURED = """
  <library_images><image id="skin"><init_from>skin.png</init_from></image></library_images>
  <library_effects>
    <effect id="painted"><profile_COMMON>
      <newparam sid="skin-surface"><surface type="2D"><init_from>skin</init_from></surface></newparam>
      <newparam sid="skin-sampler"><sampler2D><source>skin-surface</source></sampler2D></newparam>
      <technique sid="common"><phong>
        <emission><color>0 0 0 1</color></emission>
        <diffuse><texture texture="skin-sampler" texcoord="UV"/></diffuse>
        <shininess><float>50</float></shininess>
        <transparency><float>1</float></transparency>
      </phong></technique></profile_COMMON></effect>
    <effect id="plain"><profile_COMMON><technique sid="common"><lambert>
      <diffuse><color>0.8 0.1 0.1 1</color></diffuse></lambert></technique></profile_COMMON></effect>
  </library_effects>
  <library_materials>
    <material id="painted-material"><instance_effect url="#painted"/></material>
    <material id="plain-material"><instance_effect url="#plain"/></material>
  </library_materials>
  <library_lights><light id="lamp"><technique_common><point><color>1 1 1</color>
    <constant_attenuation>1</constant_attenuation></point></technique_common></light></library_lights>
  <library_cameras><camera id="eye"><optics><technique_common><perspective><xfov>50</xfov>
    <znear>0.1</znear><zfar>100</zfar></perspective></technique_common></optics></camera></library_cameras>
"""


def textured_box() -> bytes:
    """The box twice in one geometry: triangles bound to a textured material, triangles whose
    material is not bound, and lines; with every corner of the triangles its own texture
    coordinate, in a node beside a light and a camera."""
    uv = [(i / 36, (i % 7) / 7) for i in range(36)]
    rows = []
    corner = 0
    for (a, b, c, d), normal in BOX_SIDES:
        for index in (a, b, c, a, c, d):
            rows += [index, normal, corner]
            corner += 1
    inputs = (
        f'{TRIANGLE.format(g="box")}<input semantic="NORMAL" source="#box-normals" offset="1"/>'
        '<input semantic="TEXCOORD" source="#box-uv" offset="2" set="0"/>'
    )
    p = " ".join(map(str, rows))
    primitives = (
        f'<triangles count="12" material="painted">{inputs}<p>{p}</p></triangles>'
        f'<triangles count="12" material="unbound">{inputs}<p>{p}</p></triangles>'
        f'<lines count="2">{TRIANGLE.format(g="box")}<p>0 1 1 2</p></lines>'
    )
    sources = source("box-normals", BOX_NORMALS) + source("box-uv", uv, "ST")
    instance = (
        '<instance_geometry url="#box"><bind_material><technique_common>'
        '<instance_material symbol="painted" target="#painted-material">'
        '<bind_vertex_input semantic="UV" input_semantic="TEXCOORD" input_set="0"/></instance_material>'
        "</technique_common></bind_material></instance_geometry>"
    )
    nodes = (
        f'<node id="n"><rotate>0 0 1 30</rotate>{instance}<instance_light url="#lamp"/>'
        '<instance_camera url="#eye"/></node>'
    )
    return document(geometry("box", BOX, primitives, sources), nodes, TEXTURED)


def test_several_primitives_with_texture_coordinates_welded_where_a_material_is_bound() -> None:
    vertices, faces = same_as_trimesh(textured_box())
    assert len(faces) == 24
    # welding on the texture coordinates keeps the 36 corners of the bound triangles apart; the
    # others weld on position and normal alone, 4 corners per side
    assert len(vertices) == 36 + 24
    assert faces.max() == len(vertices) - 1  # the second primitive's faces follow the first's vertices


def mutated(data: bytes, rng: random.Random) -> bytes:
    """``data`` with one to three of its elements removed, repeated, or given another attribute
    value or text."""
    root = etree.fromstring(data)
    for _ in range(rng.randint(1, 3)):
        element = rng.choice([e for e in root.iter() if isinstance(e.tag, str)][1:])
        parent = element.getparent()
        change = rng.randrange(4)
        if change == 0:
            parent.remove(element)
        elif change == 1:
            parent.insert(parent.index(element), copy.deepcopy(element))
        elif change == 2 and element.attrib:
            element.set(rng.choice(sorted(element.attrib)), rng.choice(["", "#", "0", "2", "-1", "#box", "x"]))
        else:
            element.text = rng.choice(["", " ", "0", "1 2", "1e39", "nan", "x", "0 0 1 90", "3 4 5", "0.5 -1"])
    return bytes(etree.tostring(root))


def test_altered_documents_read_as_trimesh_reads_them_or_are_left_to_it() -> None:
    rng = random.Random(MUTATION_SEED)
    fast_path = 0
    for _ in range(MUTATIONS):
        data = mutated(textured_box(), rng)
        fast = read_collada(data)
        if fast is not None:
            fast_path += 1
            # trimesh raising here would be a file it cannot read that the fast path read
            expected = trimesh_arrays(data)
            assert np.array_equal(fast[0], expected[0], equal_nan=True), data.decode()
            assert np.array_equal(fast[1], expected[1]), data.decode()
    assert fast_path > MUTATIONS // 3  # the others are left to trimesh: 149 of 300 are read here


def test_nested_node_transforms_compose_as_pycollada_and_trimesh_compose_them() -> None:
    inner = (
        '<node id="inner"><scale>1 2 0.5</scale>'
        "<matrix>0 -1 0 0.25 1 0 0 0.5 0 0 1 0.125 0 0 0 1</matrix>"
        '<instance_geometry url="#box"/></node>'
    )
    # rotations by angles whose sines and cosines float32 rounds: the outer instance's rotation is
    # off a rotation by more than 1e-13, which trimesh's scene graph repairs (an SVD)
    outer = (
        '<node id="outer"><translate>0.3 -0.2 1.7</translate><rotate>0 0 1 33</rotate><rotate>1 0 0 12.5</rotate>'
        f'<instance_geometry url="#box"/>{inner}</node>'
    )
    vertices, faces = same_as_trimesh(document(box(), outer))
    assert vertices.shape == (48, 3)
    assert faces.shape == (24, 3)
    untransformed = read_collada(document(box(), '<node id="n"><instance_geometry url="#box"/></node>'))
    assert untransformed is not None
    assert not np.allclose(vertices[:24], untransformed[0])
    assert not np.allclose(vertices[24:], untransformed[0])


def test_a_geometry_instanced_twice_is_placed_twice() -> None:
    nodes = (
        '<node id="left"><translate>-1 0 0</translate><instance_geometry url="#box"/></node>'
        '<node id="right"><rotate>0 1 0 90</rotate><instance_geometry url="#box"/></node>'
    )
    vertices, faces = same_as_trimesh(document(box(), nodes))
    assert vertices.shape == (48, 3)
    assert faces.shape == (24, 3)
    assert np.array_equal(faces[12:], faces[:12] + 24)
    assert np.allclose(vertices[:24, 0], vertices[:24, 0].clip(-0.9, -0.8))  # moved 1 m to -x


def test_declared_unit_is_applied_after_reading_as_before(monkeypatch: pytest.MonkeyPatch) -> None:
    data = document(box(), '<node id="n"><translate>1 2 3</translate><instance_geometry url="#box"/></node>')
    data = data.replace(b"<contributor/>", b'<contributor/><unit name="millimetre" meter="0.001"/>')
    fast = parse_mesh(data, "dae")
    monkeypatch.setattr(meshes, "read_collada", lambda data: None)
    through_trimesh = parse_mesh(data, "dae")
    assert float(fast["unit"]) == 0.001
    assert list(fast) == list(through_trimesh)
    for key in fast:
        assert fast[key].dtype == through_trimesh[key].dtype
        assert np.array_equal(fast[key], through_trimesh[key]), key
    assert fast["vertices"].shape == (24, 3)
    assert np.isclose(fast["vertices"][:, 0].min(), 0.0011)


def test_what_pycollada_drops_is_dropped_alike() -> None:
    # an instance of a missing geometry and a transform of three numbers where four are needed
    nodes = (
        '<node id="a"><rotate>0 0 1</rotate><translate>0 0 1</translate><instance_geometry url="#box"/>'
        '<instance_geometry url="#missing"/><instance_geometry url="box"/></node>'
        '<node id="b"><translate>0 0 2</translate><!-- a comment --><extra/></node>'
    )
    vertices, faces = same_as_trimesh(document(box(), nodes))
    assert (len(vertices), len(faces)) == (24, 12)
    assert np.isclose(vertices[:, 2].min(), 1.1)  # the translation kept, the broken rotation dropped


def test_a_scene_without_triangles_reads_empty() -> None:
    vertices, faces = same_as_trimesh(document(box(), '<node id="empty"><translate>1 0 0</translate></node>'))
    assert vertices.shape == (0, 3) and faces.shape == (0, 3)
    arrays = parse_mesh(document(box(), ""), "dae")
    assert arrays["vertices"].shape == (0, 3) and arrays["faces"].shape == (0, 3)


UNSUPPORTED = {
    "triangle strips": (
        geometry("strip", BOX[:4], f'<tristrips count="2">{TRIANGLE.format(g="strip")}<p>0 1 2 3</p></tristrips>'),
        '<node id="n"><instance_geometry url="#strip"/></node>',
    ),
    "lookat": (box(), '<node id="n"><lookat>2 0 1 0 0 0 0 0 1</lookat><instance_geometry url="#box"/></node>'),
    "a node instanced by reference": (
        box(),
        '<node id="n"><instance_geometry url="#box"/></node><node id="m"><instance_node url="#n"/></node>',
    ),
    "a comment inside a mesh": (
        box().replace("<vertices", "<!-- exported --><vertices"),
        '<node id="n"><instance_geometry url="#box"/></node>',
    ),
    "an index past its source": (
        box().replace("<p>0 0 1 0", "<p>9 0 1 0"),
        '<node id="n"><instance_geometry url="#box"/></node>',
    ),
}


@pytest.mark.parametrize("case", sorted(UNSUPPORTED))
def test_what_the_reader_does_not_reproduce_is_read_through_trimesh(case: str) -> None:
    geometries, nodes = UNSUPPORTED[case]
    data = document(geometries, nodes)
    assert read_collada(data) is None
    arrays = parse_mesh(data, "dae")
    expected = trimesh_arrays(data)
    assert np.array_equal(arrays["vertices"], expected[0]) and np.array_equal(arrays["faces"], expected[1])
    if case == "lookat":  # trimesh reads the rest of the file
        assert arrays["faces"].shape == (12, 3)


def test_a_document_without_default_scene_is_left_to_trimesh() -> None:
    data = document(box(), "").replace(b'<scene><instance_visual_scene url="#scene"/></scene>', b"")
    assert read_collada(data) is None
    with pytest.raises(AttributeError):  # trimesh fails on it, as before
        parse_mesh(data, "dae")


def test_hostile_documents_are_not_read_by_the_fast_path() -> None:
    bomb = b'<?xml version="1.0"?><!DOCTYPE COLLADA [<!ENTITY a "aaaaaaaa">]><COLLADA xmlns="' + NAMESPACE.encode()
    assert read_collada(bomb + b'">&a;</COLLADA>') is None
    deep = document(box(), "<node>" * 300 + '<instance_geometry url="#box"/>' + "</node>" * 300)
    assert read_collada(deep) is None
    # a zip archive's end record where zipfile looks for one: pycollada would try the file as an archive
    assert read_collada(document(box(), "") + b"<!-- PK\x05\x06 -->") is None
    assert read_collada(b"<COLLADA><scene/></COLLADA>") is None  # no namespace: pycollada finds nothing


def test_every_corpus_collada_file_reads_as_trimesh_reads_it(corpus: Path) -> None:
    files = sorted(path for path in corpus.rglob("*") if path.suffix.lower() == ".dae" and path.is_file())
    assert files, f"no COLLADA file under {corpus}"
    fast_path = 0
    for path in files:
        data = path.read_bytes()
        fast = read_collada(data)
        expected = trimesh_arrays(data)
        if fast is not None:
            fast_path += 1
            assert np.array_equal(fast[0], expected[0]) and np.array_equal(fast[1], expected[1]), path
            assert fast[0].dtype == expected[0].dtype and fast[1].dtype == expected[1].dtype, path
    assert fast_path >= CORPUS_FAST_PATH_FILES, f"{fast_path} of {len(files)} files took the fast path"
