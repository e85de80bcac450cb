"""Binary STL read with numpy: the same triangles as trimesh, corners welded, refusals."""

from __future__ import annotations

import struct

import numpy as np
import trimesh

from geomcheck.load.stl import binary_triangle_count, first_indices, read_binary_stl, weld, weld_indices


def test_binary_stl_gives_trimesh_triangles_with_welded_corners() -> None:
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.25)
    data = trimesh.exchange.stl.export_stl(mesh)
    arrays = read_binary_stl(data)
    assert arrays is not None
    vertices, faces = arrays
    assert faces.shape == (1280, 3)
    assert vertices.shape == (642, 3)  # each corner once, not once per triangle (3840)
    expected = mesh.vertices[mesh.faces].astype(np.float32).astype(np.float64)
    assert np.array_equal(vertices[faces], expected)


def test_weld_keeps_first_appearance_order() -> None:
    corners = np.array([[1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, 1], [0, 1, 0]], dtype=np.float32)
    vertices, index = weld(corners)
    assert vertices.tolist() == [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    assert index.tolist() == [0, 1, 0, 2, 1]
    assert first_indices(corners).tolist() == [0, 1, 3]


def test_weld_tells_apart_rows_that_differ_in_one_bit() -> None:
    base = np.float32(0.1)
    close = np.nextafter(base, np.float32(1.0))
    corners = np.array([[base, 0, 0], [close, 0, 0], [base, 0, 0]], dtype=np.float32)
    vertices, index = weld(corners)
    assert len(vertices) == 2
    assert index.tolist() == [0, 1, 0]


def test_ascii_truncated_and_padded_files_are_not_binary() -> None:
    mesh = trimesh.creation.box()
    binary = trimesh.exchange.stl.export_stl(mesh)
    assert binary_triangle_count(binary) == 12
    assert read_binary_stl(trimesh.exchange.stl.export_stl_ascii(mesh).encode()) is None
    assert read_binary_stl(binary[:-10]) is None
    assert read_binary_stl(binary + b"\0") is None
    # a header claiming four billion triangles over a short file is refused before any allocation
    assert read_binary_stl(b"\0" * 80 + struct.pack("<I", 2**32 - 1) + b"\0" * 50) is None
    assert read_binary_stl(b"solid") is None


def test_the_mesh_store_names_its_largest_mesh_for_an_out_of_memory_report(tmp_path) -> None:
    from geomcheck.load import MeshStore, make_bundle
    from geomcheck.model import Mesh

    trimesh.creation.icosphere(subdivisions=2).export(tmp_path / "small.stl")
    trimesh.creation.icosphere(subdivisions=4).export(tmp_path / "large.stl")
    root = tmp_path / "robot.urdf"
    root.write_text('<robot name="r"/>')
    store = MeshStore(make_bundle(root, search=[]))
    assert store.memory_hint() is None
    for name in ("small.stl", "large.stl"):
        store.get(Mesh(name, (1.0, 1.0, 1.0)))
    hint = store.memory_hint()
    assert hint is not None
    assert hint.startswith("the largest mesh is ") and "large.stl: 5,120 triangles, 0.3 MB" in hint


def test_an_obj_that_a_lenient_reader_misreads_is_unreadable_not_a_crash(tmp_path) -> None:
    from geomcheck.load import MeshStore, make_bundle
    from geomcheck.load.meshes import MeshProblem
    from geomcheck.model import Mesh

    (tmp_path / "flat.obj").write_text("v  00 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    root = tmp_path / "robot.urdf"
    root.write_text('<robot name="r"/>')
    problem = MeshStore(make_bundle(root, search=[])).get(Mesh("flat.obj", (1.0, 1.0, 1.0)))
    assert isinstance(problem, MeshProblem)
    assert problem.kind == "unreadable"
    assert problem.message.endswith("flat.obj: vertices of 2 coordinates")


def test_weld_indices_groups_rows_of_any_width_in_order_of_first_appearance() -> None:
    # weld keys of COLLADA corners (position, texture, normal: 8 int64 columns) and of a
    # primitive's rounded vertices (3 columns) are grouped by the same code
    rng = np.random.default_rng(5)
    for width in (3, 5, 8, 11):
        distinct = rng.integers(-(10**12), 10**12, size=(40, width))
        rows = distinct[rng.integers(0, 40, size=300)]
        first, index = weld_indices(rows)
        assert np.array_equal(rows[first][index], rows)
        assert len(first) == len(np.unique(rows, axis=0)) and (np.diff(first) > 0).all()
        assert first[0] == 0 and index[0] == 0


def test_mirrored_float64_rows_get_a_key_each() -> None:
    """A symmetric part's vertices (x, y, z), (-x, -y, z), ... keep distinct hash keys: a
    linear hash let two sign bits cancel and sent the weld to its slow exact sort."""
    from geomcheck.load.stl import _row_hash

    octant = np.random.default_rng(3).uniform(0.01, 0.1, size=(500, 3)).astype(np.float32).astype(np.float64)
    signs = np.array([[sx, sy, sz] for sx in (1, -1) for sy in (1, -1) for sz in (1, -1)], dtype=np.float64)
    rows = (octant[:, None, :] * signs[None]).reshape(-1, 3)
    _, key = _row_hash(rows)
    assert len(np.unique(key)) == len(rows) == 4000
    first, index = weld_indices(np.concatenate([rows, rows[::-1]]))
    assert np.array_equal(first, np.arange(4000)) and np.array_equal(index[4000:], np.arange(4000)[::-1])
