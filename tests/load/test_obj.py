"""Wavefront OBJ read with numpy: bit for bit the triangles trimesh's loader gives through
``geometry_only``, empty arrays where trimesh finds no triangles, ``None`` for what is not
modelled (the caller then reads the file with trimesh)."""

from __future__ import annotations

import io
import random
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.load.meshes import geometry_only
from geomcheck.load.obj import read_obj

# corpus OBJ files the reader reproduces (measured: all 142 of the shared corpus)
CORPUS_ACCEPTED = 142
CORPUS_SECONDS = 20.0  # the corpus comparison's budget, both readers [s]
HOSTILE_FILES = 600  # randomly edited files compared
HOSTILE_ACCEPTED = 170  # of them read_obj reads (measured: 181)

SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
PENTAGON = SQUARE + "v 0.5 1.5 0\n"


def trimesh_arrays(data: bytes) -> tuple[np.ndarray, np.ndarray] | None:
    """What parse_mesh gets from trimesh for ``data``: ``(vertices, faces)``, empty arrays when
    trimesh finds no triangles, ``None`` when trimesh raises."""
    try:
        loaded = trimesh.load(io.BytesIO(data), file_type="obj", process=False, resolver=None, skip_materials=True)
    except (ValueError, IndexError, TypeError):  # what trimesh raises on the malformed files below
        return None
    mesh = geometry_only(loaded)
    if mesh is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


def assert_identical(ours: tuple[np.ndarray, np.ndarray], theirs: tuple[np.ndarray, np.ndarray]) -> None:
    """Same dtypes, shapes and values, vertices compared bit for bit (signed zeros, NaN)."""
    (vertices, faces), (expected_vertices, expected_faces) = ours, theirs
    assert vertices.dtype == np.float64 and faces.dtype == np.int64
    assert vertices.shape == expected_vertices.shape and faces.shape == expected_faces.shape
    assert np.array_equal(vertices.view(np.uint64), expected_vertices.view(np.uint64))
    assert np.array_equal(faces, expected_faces)


def same_as_trimesh(text: str | bytes) -> tuple[np.ndarray, np.ndarray]:
    """The arrays read_obj gives for ``text``, after checking they are trimesh's."""
    data = text.encode() if isinstance(text, str) else text
    ours, theirs = read_obj(data), trimesh_arrays(data)
    assert ours is not None, "refused a file it models"
    assert theirs is not None, "trimesh raised"
    assert_identical(ours, theirs)
    return ours


@pytest.mark.parametrize(
    ("text", "vertices", "faces"),
    [
        pytest.param(SQUARE + "f 1 2 3\nf 1 3 4\n", 4, 2, id="triangles"),
        # quads of one material: all first triangles, then all second ones
        pytest.param(SQUARE + "v 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n", 6, 4, id="quads"),
        pytest.param(PENTAGON + "f 1 2 3 5 4\n", 5, 3, id="pentagon-fan"),
        # mixed corner counts: each line split in place, quads 0 1 2, 2 3 0
        pytest.param(PENTAGON + "f 1 2 3\nf 1 2 3 4\nf 1 2 3 5 4\n", 5, 6, id="mixed-polygons"),
        # negative indices count from the end of all vertices, as numpy indexes
        pytest.param(SQUARE + "f -4 -3 -2\nv 5 5 5\nf -1 -2 -3\n", 4, 2, id="negative-indices"),
        pytest.param(SQUARE + "f 0 2 3\n", 3, 1, id="index-zero"),
        pytest.param(
            SQUARE + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\nvn 0 0 1\nvn 0 0 -1\n"
            "f 1/1/1 2/2/1 3/3/1\nf 1/5/2 3/3/2 4/4/2\n",
            6,
            2,
            id="v-vt-vn-splits-vertex",
        ),
        pytest.param(SQUARE + "vt 0 0\nvt 1 1\nf 1/1 2/2 3/1 4/2\n", 4, 2, id="v-vt-quad"),
        pytest.param(SQUARE + "vn 0 0 1\nvn 1 0 0\nf 1//1 2//1 3//1\nf 1//2 3//2 4//2\n", 6, 2, id="v-vn"),
        # without vn lines trimesh ignores the normal indices: no vertex is split
        pytest.param(SQUARE + "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\n", 4, 2, id="v-vn-without-vn-lines"),
        pytest.param(
            SQUARE + "vt 0 0\nvt 1 1\nf 1/1 2/1 3/1\nf 1/2 2/2 3/2 4/2\nf 4/1 3/2 2/1 1/2 2/2\n",
            8,
            6,
            id="v-vt-mixed-polygons",
        ),
        pytest.param(
            "o first\n" + SQUARE + "g part\ns 1\nf 1 2 3\no second\ng other\ns off\nf 1 3 4\n",
            4,
            2,
            id="objects-groups",
        ),
        # materials: one mesh each, concatenated from the last material to appear to the first
        pytest.param(
            SQUARE + "usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\nusemtl red \nf 2 3 4\n", 7, 3, id="materials"
        ),
        pytest.param("o Body\n" + SQUARE + "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n", 6, 2, id="named-materials"),
        pytest.param(
            "# exported\nmtllib robot.mtl\n\n" + SQUARE + "  \n# faces: 2\nl 1 2\nf 1 2 3 \nf 1\t3 4\n# end\n",
            4,
            2,
            id="comments-blank-lines",
        ),
        pytest.param((SQUARE + "f 1 2 3\nf 1 3 4\n").replace("\n", "\r\n"), 4, 2, id="crlf"),
        # lines trimesh does not look for are passed over, a vertex among them too
        pytest.param(
            "\ufeffv 9 9 9\n" + SQUARE + "vp 0.5\n  f 1 2 3\n\tv 7 7 7\ng\no\np 1\ncstype bezier\nv\t8 8 8\nf 1 2 3\n",
            3,
            1,
            id="lines-passed-over",
        ),
        pytest.param(
            "o K\u00f6rper\n" + SQUARE + "usemtl a\u00a0\nf 1 2 3\nusemtl a\nf 1 3 4\n", 4, 2, id="unicode-names"
        ),
        pytest.param(SQUARE + "f 1 2 \\\n3\n# a comment \\\nf 1 3 4\nf 1 3 4\n", 4, 2, id="continuations"),
        pytest.param("v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\nf 1 2 3\n", 3, 1, id="homogeneous-w"),
        pytest.param("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n", 3, 1, id="vertex-colours"),
        # rows of different lengths: trimesh clips every row to the shortest, reading each number alone
        pytest.param("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0.5\nf 1 2 3\n", 3, 1, id="mixed-vertex-rows"),
        pytest.param(
            "v 1.e5 +.5 -0\nv 1E+05 -.5e-3 0.1000000000000000055511151231257827021181583404541015625\n"
            "v 2.2250738585072011e-308 1e400 1e-400\nv 00012.5 -7.7137673941304481 4.\nf 1 2 3\nf 2 3 4\n",
            4,
            2,
            id="numbers",
        ),
        pytest.param(
            "v 1.e5 +.5 -0 1 1\nv 1E+05 -.5e-3 0.1000000000000000055511151231257827021181583404541015625\n"
            "v 2.2250738585072011e-308 1e400 1e-400 0 0 0\nv 00012.5 -7.7137673941304481 4.\nf 1 2 3 4\n",
            4,
            2,
            id="tricky-numbers-mixed-rows",
        ),
    ],
)
def test_read_obj_gives_trimesh_triangles(text: str, vertices: int, faces: int) -> None:
    ours = same_as_trimesh(text)
    assert (len(ours[0]), len(ours[1])) == (vertices, faces)


def test_quads_of_one_material_split_as_trimesh_splits_them() -> None:
    _, faces = same_as_trimesh(SQUARE + "v 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n")
    assert faces.tolist() == [[0, 1, 2], [1, 4, 5], [2, 3, 0], [5, 2, 1]]
    _, mixed = same_as_trimesh(PENTAGON + "f 1 2 3\nf 1 2 3 4\nf 1 2 3 5 4\n")
    assert mixed.tolist() == [[0, 1, 2], [0, 1, 2], [2, 3, 0], [0, 1, 2], [0, 2, 4], [0, 4, 3]]


def test_materials_come_out_last_first() -> None:
    vertices, faces = same_as_trimesh(SQUARE + "usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\nusemtl red\nf 2 3 4\n")
    # blue (first seen second) first, then red's two faces over its own copies of the vertices
    assert vertices[faces[0]].tolist() == [[0, 0, 0], [1, 1, 0], [0, 1, 0]]
    assert len(vertices) == 3 + 4


@pytest.mark.parametrize(
    "text",
    [
        pytest.param("", id="empty-file"),
        pytest.param("# nothing but a comment\n", id="comment-only"),
        pytest.param(SQUARE, id="vertices-only"),
        pytest.param(SQUARE + "vn 0 0 1\n", id="point-cloud-with-normals"),
        pytest.param("f 1 2 3\n", id="faces-without-vertices"),
    ],
)
def test_a_file_without_triangles_gives_empty_arrays(text: str) -> None:
    vertices, faces = same_as_trimesh(text)
    assert vertices.shape == (0, 3) and faces.shape == (0, 3)


@pytest.mark.parametrize(
    "data",
    [
        pytest.param("# caf\xe9\n".encode("latin-1") + (SQUARE + "f 1 2 3\n").encode(), id="not-utf-8"),
        pytest.param((SQUARE + "f 1 2 3\n").replace("\n", "\r").encode(), id="cr-line-ends"),
        pytest.param((SQUARE + "f 1 2 3\nfo 1 2 3\n").encode(), id="face-keyword-run-on"),
        pytest.param((SQUARE + " usemtl red\nf 1 2 3\n").encode(), id="indented-usemtl"),
        pytest.param((SQUARE + "f\t1 2 3\n").encode(), id="face-keyword-with-tab"),
        pytest.param((SQUARE + "# usemtl red\nf 1 2 3\n").encode(), id="usemtl-in-a-comment"),
        pytest.param(("o world\n" + SQUARE + "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n").encode(), id="scene-root-name"),
        pytest.param((SQUARE + "f 1 2\nf 1 2 3\n").encode(), id="two-corners"),
        pytest.param((SQUARE + "f 1/1 2/1 3/1\nf 1 2 3 4\n").encode(), id="mixed-forms-mixed-counts"),
        pytest.param((SQUARE + "vt 0 0\nf 1/1/2000000 2/1/1 3/1/1\n").encode(), id="index-key-too-wide"),
        # trimesh reads rows of two numbers, which parse_mesh then refuses
        pytest.param(b"v 1 2 3\nv 1 2\nv 3 4 5\nf 1 2 3\n", id="vertex-of-two-numbers"),
    ],
)
def test_what_is_not_modelled_is_refused(data: bytes) -> None:
    assert read_obj(data) is None


@pytest.mark.parametrize(
    "text",
    [
        pytest.param(SQUARE + "f 1 2 5\n", id="index-out-of-range"),
        pytest.param(SQUARE + "f -5 1 2\n", id="negative-index-out-of-range"),
        pytest.param(SQUARE + "f 1 2 3 # a comment\n", id="comment-after-face"),
        pytest.param(SQUARE + "v 1 2 3 # a comment\nf 1 2 3\n", id="comment-after-vertex"),
        pytest.param(SQUARE + "vn 0 0 x\nf 1 2 3\n", id="unreadable-normal"),
        pytest.param(SQUARE + "f 1 2 99999999999999999999\n", id="index-overflowing-int64"),
    ],
)
def test_files_trimesh_rejects_are_refused(text: str) -> None:
    data = text.encode()
    assert read_obj(data) is None
    assert trimesh_arrays(data) is None


def test_hostile_bytes_give_trimesh_triangles_or_a_refusal() -> None:
    """A valid file with one byte changed or deleted: never an exception, never other triangles than trimesh's."""
    base = (
        SQUARE + "vt 0 0\nvt 1 1\nvn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/1/1\nusemtl b\nf 1/2/1 3/1/1 4/2/1\n"
    ).encode()
    alphabet = b"0123456789 -+./\n\te#fvtnusml\r\\\x00\xff"
    rng = random.Random(20260101)
    accepted = 0
    for _ in range(HOSTILE_FILES):
        data = bytearray(base)
        position = rng.randrange(len(data))
        if rng.random() < 0.5:
            data[position] = rng.choice(alphabet)
        else:
            del data[position]
        ours = read_obj(bytes(data))
        if ours is not None:
            theirs = trimesh_arrays(bytes(data))
            assert theirs is not None, bytes(data)
            assert_identical(ours, theirs)
            accepted += 1
    assert accepted >= HOSTILE_ACCEPTED  # many edits leave the file readable: the comparison means something


def test_reading_an_obj_does_not_import_trimesh() -> None:
    probe = (
        "import sys\nfrom geomcheck.load.obj import read_obj\n"
        f"assert read_obj({(SQUARE + 'f 1 2 3 4').encode()!r})[1].shape == (2, 3)\n"
        "assert 'trimesh' not in sys.modules\n"
    )
    proc = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=False)
    assert proc.returncode == 0, proc.stderr


@pytest.mark.corpus
def test_corpus_obj_files_read_as_trimesh_reads_them(corpus: Path) -> None:
    files = sorted(path for path in corpus.rglob("*") if path.suffix.lower() == ".obj" and path.is_file())
    assert len(files) >= CORPUS_ACCEPTED
    started = time.perf_counter()
    accepted = []
    for path in files:
        data = path.read_bytes()
        ours = read_obj(data)
        theirs = trimesh_arrays(data)
        if ours is None:
            continue
        assert theirs is not None, path
        assert_identical(ours, theirs)
        accepted.append(path)
    assert len(accepted) >= CORPUS_ACCEPTED, sorted(set(files) - set(accepted))
    assert time.perf_counter() - started < CORPUS_SECONDS
