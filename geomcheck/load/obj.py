"""Wavefront OBJ read with numpy: the triangles trimesh's loader gives, without importing trimesh.

:func:`read_obj` returns, bit for bit, the ``vertices`` (n, 3) float64 and ``faces`` (m, 3)
int64 that :func:`geomcheck.load.meshes.parse_mesh` gets from ``trimesh.load(...,
file_type="obj", process=False, skip_materials=True)`` flattened by ``geometry_only``, or
``None`` for a file it does not reproduce exactly, which the caller then reads with trimesh.

The text's lines and numbers are read by :mod:`geomcheck.load.obj_text`. It follows trimesh's
loader (``trimesh/exchange/obj.py``) step by step, with the same numpy
calls where the result depends on them (number parsing, ``np.unique``, ``argsort``):

- the text: UTF-8, stripped, CRLF made LF, backslash-newline continuations joined;
- ``v`` lines: all numbers read at once, rows of the first line's count when the total
  allows, else every line clipped to the shortest; x y z kept. ``vt`` and ``vn`` lines are
  read too (trimesh raises on what it cannot read) but only whether ``vn`` lines exist matters;
- faces grouped by ``usemtl`` material (``o``, ``g`` and ``s`` lines do not split), one mesh
  per material, meshes concatenated in reverse order of each material's first face (the
  order trimesh fills its scene in);
- a material whose face lines all hold as many integers is read as one array laid out as
  its first line (``v``, ``v/vt``, ``v//vn``, ``v/vt/vn``), and its polygons are split after
  re-indexing: quads as all their first triangles then all their second ones, larger ones
  as fans; a material of mixed lines is read line by line, each line split in place (quads
  ``0 1 2, 2 3 0``, others fans), and is refused unless every reference has one form;
- each mesh keeps the vertices its faces use, in index order, one copy per distinct
  (vertex, texture, normal) index pair when texture or normal indices are given (``v//vn``
  only when the file has ``vn`` lines), ordered as trimesh's ``unmerge_faces`` orders them;
- indices as trimesh reads them: positives made 0-based, negatives counted from the end of
  all the file's vertices (numpy indexing), 0 read as the first vertex.

Lines trimesh does not look for (comments, blank or indented lines, ``mtllib``, ``l``,
``p``, ``vp``, curves, a keyword run into a tab) are passed over as trimesh passes over them.
It refuses (``None``) what it does not model: other encodings, control characters, a line
starting with "f" but not "f " (trimesh's two searches disagree on it), ``usemtl`` anywhere
but at the start of its line, numbers with ``+e``/``-e`` (trimesh edits its text there),
faces of fewer than 3 corners, vertex indices out of range (trimesh raises on them), index
pairs trimesh would compare as raw bytes, an object named like trimesh's scene root, files
beyond the sizes below.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from geomcheck.load.obj_text import (
    DIGIT,
    FACE,
    FORM_V,
    FORM_V_VN,
    FORM_V_VT,
    FORM_V_VT_VN,
    FORM_WIDTH,
    INDEX_CLASSES,
    INDEX_LIMIT,
    INVALID,
    KEYWORDS,
    MATERIAL,
    MAX_MATERIAL_LINES,
    MAX_MATERIALS,
    MAX_OBJ_BYTES,
    NEWLINE,
    NORMAL,
    NORMAL_WIDTHS,
    OBJECT,
    SCENE_ROOT,
    SEPARATOR,
    SIGN,
    SLASH,
    SPACE,
    SPARSE_GROUP,
    STARTERS,
    TEXTURE,
    TEXTURE_WIDTHS,
    UNKNOWN,
    VERTEX,
    Arrays,
    Lines,
    Polygons,
    decoded_text,
    neighbours,
    owner,
    parse_numbers,
    readable,
    split_lines,
    vertex_positions,
)


@dataclass(frozen=True)
class _Faces:
    """The face lines: ``body`` their bytes after "f", each with its newline; ``lines`` (k,)
    their line numbers; ``counts`` (k,) the integers on each ("/" separating); ``values``
    (t,) int64 the integers, positives made 0-based as trimesh makes them; ``first`` (k,)
    the offset of each line's first integer in ``values``; ``normals`` whether the file
    has ``vn`` lines."""

    body: np.ndarray
    lines: np.ndarray
    counts: np.ndarray
    values: np.ndarray
    first: np.ndarray
    normals: bool

    def integers(self, group: np.ndarray) -> np.ndarray:
        """The integers of face lines ``group`` (ascending indices into the face lines), in order."""
        counts = self.counts[group]
        if group[-1] - group[0] + 1 == len(group):  # consecutive lines: one slice
            return self.values[self.first[group[0]] : self.first[group[-1]] + counts[-1]]
        within = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
        return self.values[np.repeat(self.first[group], counts) + within]

    @functools.cached_property
    def forms(self) -> np.ndarray:
        """(k,) the one form (``v``, ``v/vt``, ``v/vt/vn``, ``v//vn``) of every reference on
        each face line, -1 where they differ or an integer is not digits after an optional
        minus (what Python's int, trimesh's reader of mixed lines, reads as numpy does)."""
        previous, current, following = neighbours(INDEX_CLASSES[self.body])
        token_starts = np.flatnonzero((current != SEPARATOR) & (previous == SEPARATOR))
        malformed = (
            (current == INVALID)
            | ((current == SIGN) & (previous != SEPARATOR) & (previous != SLASH))
            | ((current == SIGN) & (following != DIGIT))
            | ((current == SLASH) & (previous != DIGIT) & (previous != SLASH))
            | ((current == SLASH) & (following != DIGIT) & (following != SIGN) & (following != SLASH))
        )
        slashes = np.bincount(owner(np.flatnonzero(current == SLASH), token_starts), minlength=len(token_starts))
        doubled = np.flatnonzero((current == SLASH) & (previous == SLASH))
        adjacent = np.bincount(owner(doubled, token_starts), minlength=len(token_starts))
        token_forms = np.full(len(token_starts), -1, dtype=np.int8)
        token_forms[slashes == 0] = FORM_V
        token_forms[slashes == 1] = FORM_V_VT
        token_forms[(slashes == 2) & (adjacent == 0)] = FORM_V_VT_VN
        token_forms[(slashes == 2) & (adjacent == 1)] = FORM_V_VN
        line_ends = np.flatnonzero(self.body == NEWLINE)
        line_of_token = np.searchsorted(line_ends, token_starts)
        per_line = np.bincount(line_of_token, minlength=len(line_ends))
        forms = np.full(len(line_ends), -1, dtype=np.int8)
        forms[per_line > 0] = token_forms[(np.cumsum(per_line) - per_line)[per_line > 0]]  # first token's
        forms[line_of_token[token_forms != forms[line_of_token]]] = -1
        forms[np.searchsorted(line_ends, np.flatnonzero(malformed))] = -1
        return forms


def _faces(lines: Lines) -> _Faces | None:
    """The face lines' integers, read at once as trimesh reads a material's lines; ``None``
    when numpy cannot read them or one is beyond INDEX_LIMIT."""
    body = lines.body(FACE)
    raw = body.tobytes().replace(b"/", b" ")  # trimesh's "1//2" is two integers
    values = parse_numbers(raw, np.int64)
    spaced = np.frombuffer(raw, dtype=np.uint8)
    separator = spaced <= SPACE  # space, tab, newline: the other controls are refused
    token_starts = ~separator & np.concatenate([[True], separator[:-1]])
    # every line holds its newline: no segment is empty
    counts = np.add.reduceat(token_starts.view(np.uint8), lines.offsets(FACE), dtype=np.int32).astype(np.int64)
    if values is None or len(values) != counts.sum() or ((values >= INDEX_LIMIT) | (values <= -INDEX_LIMIT)).any():
        return None
    np.subtract(values, 1, out=values, where=values > 0)
    first = np.cumsum(counts) - counts
    normals = bool((lines.kinds == NORMAL).any())
    return _Faces(body, np.flatnonzero(lines.kinds == FACE), counts, values, first, normals)


def _in_place_triangles(corners: np.ndarray) -> np.ndarray:
    """Reference indices (t, 3) of the triangles trimesh makes of face lines of mixed corner
    counts (``corners`` (k,)), each line's in place: a quad ``0 1 2, 2 3 0``, others fans
    ``0 i+1 i+2``; references are numbered across lines in order."""
    per_line = corners - 2
    line = np.repeat(np.arange(len(corners)), per_line)
    i = np.arange(int(per_line.sum())) - np.repeat(np.cumsum(per_line) - per_line, per_line)
    local = np.stack([np.zeros_like(i), i + 1, i + 2], axis=1)
    local[(corners[line] == 4) & (i == 1)] = (2, 3, 0)
    first = np.cumsum(corners) - corners
    return local + first[line][:, None]


def _alike_polygons(lines: Lines, faces: _Faces, group: np.ndarray) -> Polygons | None:
    """A material whose face lines all hold as many integers, read as trimesh's
    ``_parse_faces_vectorized`` reads it: one (lines, integers) array laid out as the first
    line's references, texture or normal columns told apart by its slashes."""
    sample = lines.text(int(faces.lines[group[0]]))[1:].strip()  # trimesh's first face line
    references = sample.split()
    columns = int(faces.counts[group[0]])
    per_reference = columns // len(references) if references else 0
    if len(references) < 3 or per_reference * len(references) != columns:
        return None
    array = faces.integers(group).reshape(-1, columns)
    index = np.arange(len(references)) * per_reference
    texture = normal = None
    if per_reference == 2:
        slashes = "".join(reference.strip("/") for reference in references).count("/")
        if slashes == columns:  # v//vn
            normal = array[:, index + 1]
        elif slashes == columns // 2:  # v/vt
            texture = array[:, index + 1]
    elif per_reference == 3:
        texture, normal = array[:, index + 1], array[:, index + 2]
    return array[:, index], _attributes(array[:, index], texture, normal, faces.normals), True


def _mixed_polygons(lines: Lines, faces: _Faces, group: np.ndarray) -> Polygons | None:
    """A material of face lines with different counts, read as trimesh's
    ``_parse_faces_fallback`` reads it: each line split into triangles in place; ``None``
    unless every reference of the material has one form and every line 3 corners or more."""
    forms = faces.forms[group]
    form = int(forms[0])
    if form < 0 or (forms != form).any():
        return None
    width = FORM_WIDTH[form]
    corners = faces.counts[group] // width
    if corners.min() < 3:
        return None  # trimesh skips such lines
    rows = faces.integers(group).reshape(-1, width)[_in_place_triangles(corners)]  # (triangles, 3, integers)
    texture = rows[:, :, 1] if form in (FORM_V_VT, FORM_V_VT_VN) else None
    normal = rows[:, :, 2] if form == FORM_V_VT_VN else rows[:, :, 1] if form == FORM_V_VN else None
    return rows[:, :, 0], _attributes(rows[:, :, 0], texture, normal, faces.normals), False


def _attributes(
    polygons: np.ndarray, texture: np.ndarray | None, normal: np.ndarray | None, normals: bool
) -> list[np.ndarray]:
    """The index arrays trimesh splits vertices by: texture (and normal) indices when given;
    normal indices alone only when the file has ``vn`` lines."""
    if texture is not None:
        return [texture, normal] if normal is not None and len(normal) == len(polygons) else [texture]
    if normal is not None and normal.shape == polygons.shape and normals:
        return [normal]
    return []


def _row_keys(stack: np.ndarray) -> np.ndarray | None:
    """trimesh's ``hashable_rows`` of an integer (n, c) array, c of 2 or 3: each row packed into
    one uint64, columns ``64 // c`` bits apart; ``None`` when a value does not fit (trimesh
    then compares rows as raw bytes, an order not modelled here)."""
    bits = 64 // stack.shape[1]
    threshold = 2 ** (bits - 1) - 1
    if stack.max() >= threshold or stack.min() <= -threshold:
        return None
    keys = np.zeros(len(stack), dtype=np.uint64)
    for offset, column in enumerate((stack.T + (threshold + 1)).astype(np.uint64)):
        np.bitwise_xor(keys, column << np.uint64(offset * bits), out=keys)
    return keys


def _split_vertices(polygons: np.ndarray, attributes: list[np.ndarray]) -> Arrays | None:
    """trimesh's ``unmerge_faces``: ``(polygons re-indexed, vertex index of each new vertex)``,
    one new vertex per distinct (vertex, texture[, normal]) index pair, ordered by packed key
    then by vertex index with numpy's default sort, as trimesh orders them; ``None`` when the
    key does not fit."""
    stack = np.column_stack([polygons.reshape(-1), *(a.reshape(-1) for a in attributes)])
    keys = _row_keys(stack)
    if keys is None:
        return None
    _, unique, inverse = np.unique(keys, return_index=True, return_inverse=True)
    pairs = stack[unique]
    order = pairs[:, 0].argsort()  # trimesh's default kind: which of equal indices comes first is numpy's
    remap = np.zeros(len(order), dtype=np.int64)
    remap[order] = np.arange(len(order))
    return remap[inverse].reshape((-1, polygons.shape[1])), pairs[order][:, 0]


def _used_vertices(polygons: np.ndarray, count: int) -> Arrays:
    """``(polygons re-indexed, indices of the vertices they use)``, vertices in file order, of
    polygons into ``count`` vertices: trimesh's mask over all the vertices, or a sort of the
    polygons' indices when they are few (the same arrays; one file's many materials would
    otherwise cost a pass over all its vertices each)."""
    if polygons.size * SPARSE_GROUP < count:
        absolute = np.where(polygons < 0, polygons + count, polygons).reshape(-1)
        used, inverse = np.unique(absolute, return_inverse=True)
        return inverse.reshape(polygons.shape), used
    mask = np.zeros(count, dtype=bool)
    mask[polygons] = True
    inverse = np.zeros(count, dtype=np.int64)
    inverse[mask] = np.arange(int(mask.sum()))
    return inverse[polygons], np.flatnonzero(mask)


def _polygon_triangles(polygons: np.ndarray) -> np.ndarray:
    """The triangles (t, 3) trimesh's Trimesh makes of polygons (n, k) of one corner count:
    triangles as they are, quads as all ``0 1 2`` then all ``2 3 0``, larger ones as
    consecutive fans ``0 i+1 i+2``."""
    count = polygons.shape[1]
    if count == 3:
        return polygons
    if count == 4:
        return np.vstack((polygons[:, [0, 1, 2]], polygons[:, [2, 3, 0]]))
    i = np.arange(count - 2)
    return polygons[:, np.stack([np.zeros_like(i), i + 1, i + 2], axis=1)].reshape(-1, 3)


def _mesh(vertices: np.ndarray, polygons: Polygons) -> Arrays | None:
    """One material's vertices and triangles as trimesh builds its mesh from ``polygons``
    into the file's ``vertices`` (n, 3); ``None`` for a vertex index out of range (trimesh
    raises) or index pairs whose key does not fit."""
    corners, attributes, alike = polygons
    if corners.min() < -len(vertices) or corners.max() >= len(vertices):
        return None
    split = _split_vertices(corners, attributes) if attributes else _used_vertices(corners, len(vertices))
    if split is None:
        return None
    faces, index = split
    return vertices[index], _polygon_triangles(faces) if alike else faces


def _materials(lines: Lines) -> np.ndarray:
    """Each face line's material (k,), numbered in order of each material's first face: the
    name of the last ``usemtl`` before it, stripped as trimesh strips it, or none."""
    usemtl = np.flatnonzero(lines.kinds == MATERIAL)
    if not len(usemtl):
        return np.zeros(np.count_nonzero(lines.kinds == FACE), dtype=np.int64)
    number: dict[str | None, int] = {}
    named = [number.setdefault(lines.text(int(line))[len("usemtl") :].strip(), len(number)) for line in usemtl]
    unnamed = number.setdefault(None, len(number))
    latest = np.searchsorted(usemtl, np.flatnonzero(lines.kinds == FACE)) - 1  # -1: before any usemtl
    material = np.asarray([*named, unnamed], dtype=np.int64)[latest]
    _, first, inverse = np.unique(material, return_index=True, return_inverse=True)
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first)] = np.arange(len(first))
    return rank[inverse.reshape(-1)]


def _object_name(lines: Lines) -> str | None:
    """The name trimesh gives its meshes from an ``o`` line: the first ``o`` line's when no
    other statement that starts a face chunk comes before it; else ``None``."""
    starters = np.flatnonzero(np.isin(lines.kinds, STARTERS))
    if not len(starters) or lines.kinds[starters[0]] != OBJECT:
        return None
    return lines.text(int(starters[0]))[len("o") :].strip()


def _occurrences(buf: np.ndarray, word: bytes) -> int:
    """How many times ``word`` occurs in ``buf``, checked at its first byte's positions."""
    at = np.flatnonzero(buf[: len(buf) - len(word) + 1] == word[0])
    match = np.ones(len(at), dtype=bool)
    for i, byte in enumerate(word[1:], start=1):
        match &= buf[at + i] == byte
    return int(np.count_nonzero(match))


def _empty() -> Arrays:
    """No triangles: what parse_mesh makes of an OBJ trimesh reads as a point cloud or an empty scene."""
    return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)


def _concatenated(meshes: list[Arrays]) -> Arrays:
    """The meshes' vertices stacked and their faces offset accordingly, as trimesh concatenates."""
    if len(meshes) == 1:
        return meshes[0]
    offsets = np.cumsum([0] + [len(vertices) for vertices, _ in meshes[:-1]])
    faces = [triangles + offset for (_, triangles), offset in zip(meshes, offsets, strict=True)]
    return np.concatenate([vertices for vertices, _ in meshes]), np.concatenate(faces)


def read_obj(data: bytes) -> Arrays | None:
    """``(vertices (n, 3) float64 [file units], faces (m, 3) int64)`` of an OBJ file's bytes,
    bit for bit what trimesh loads and ``geometry_only`` flattens; empty arrays (both
    ``(0, 3)``) for a file with no face or no vertex line, as ``parse_mesh`` returns for it;
    ``None`` for a file outside what is modelled here (see the module documentation): read
    it with trimesh."""
    lines = _modelled_lines(data)
    if lines is None:
        return None
    # trimesh reads all three kinds of vertex lines and raises on what it cannot read
    counts = np.bincount(lines.kinds, minlength=UNKNOWN)
    for kind, widths in ((TEXTURE, TEXTURE_WIDTHS), (NORMAL, NORMAL_WIDTHS)):
        if counts[kind] and not readable(lines.body(kind), int(counts[kind]), widths):
            return None
    vertices = vertex_positions(lines.body(VERTEX), int(counts[VERTEX])) if counts[VERTEX] else None
    if counts[VERTEX] and vertices is None:
        return None
    if vertices is None or not counts[FACE]:
        return _empty()
    faces = _faces(lines)
    if faces is None:
        return None
    meshes = _material_meshes(lines, faces, vertices)
    return None if meshes is None else _concatenated(meshes)


def _modelled_lines(data: bytes) -> Lines | None:
    """The lines of an OBJ file's bytes, ``None`` when its text or its materials are outside
    what is modelled here."""
    buf = decoded_text(data) if len(data) <= MAX_OBJ_BYTES else None
    lines = None if buf is None else split_lines(buf)
    if lines is None:
        return None
    materials = int(np.count_nonzero(lines.kinds == MATERIAL))
    # trimesh splits face chunks at every "usemtl ", also one inside a comment or a name
    if materials > MAX_MATERIAL_LINES or _occurrences(lines.buf, KEYWORDS[MATERIAL]) != materials:
        return None
    return lines


def _material_meshes(lines: Lines, faces: _Faces, vertices: np.ndarray) -> list[Arrays] | None:
    """The mesh of each material's faces, in trimesh's order; ``None`` when one is outside what
    is modelled here."""
    material = _materials(lines)
    count = int(material.max()) + 1
    if count > MAX_MATERIALS or (count > 1 and (_object_name(lines) or "").startswith(SCENE_ROOT)):
        return None
    order = np.argsort(material, kind="stable")
    bounds = np.searchsorted(material[order], np.arange(count + 1))
    meshes = []
    for index in range(count - 1, -1, -1):  # trimesh pops its material chunks from the last
        group = order[bounds[index] : bounds[index + 1]]
        alike = bool((faces.counts[group] == faces.counts[group[0]]).all())
        polygons = (_alike_polygons if alike else _mixed_polygons)(lines, faces, group)
        mesh = None if polygons is None else _mesh(vertices, polygons)
        if mesh is None:
            return None
        meshes.append(mesh)
    return meshes


__all__ = ["read_obj"]
