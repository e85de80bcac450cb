"""Triangle meshes of primitives (box, cylinder, icosphere) with numpy alone.

They are the meshes ``trimesh.creation`` makes (``box``, ``cylinder``, ``icosphere``;
trimesh 4.x and 5.x), value for value and in the same order: every fit, bound and picture
made from a primitive's mesh was made from trimesh's, and a cold check must not pay about
0.4 s to import trimesh for twenty triangles. Each function repeats trimesh's arithmetic
operation for operation (the same numpy calls on the same arrays), so the floats are equal,
not merely close; ``tests/geometry/test_tessellation.py`` holds them to trimesh's over sizes
from nanometres to tens of metres.
"""

from __future__ import annotations

import numpy as np

from geomcheck.load.stl import weld_indices

# trimesh's reference cube (``creation._data["box"]``): the unit cube's corners and faces
_BOX_VERTICES = (
    (0.0, 0.0, 0.0),
    (0.0, 0.0, 1.0),
    (0.0, 1.0, 0.0),
    (0.0, 1.0, 1.0),
    (1.0, 0.0, 0.0),
    (1.0, 0.0, 1.0),
    (1.0, 1.0, 0.0),
    (1.0, 1.0, 1.0),
)
_BOX_FACES = (
    (1, 3, 0),
    (4, 1, 0),
    (0, 3, 2),
    (2, 4, 0),
    (1, 7, 3),
    (5, 1, 4),
    (5, 7, 1),
    (3, 7, 2),
    (6, 4, 2),
    (2, 7, 6),
    (6, 5, 4),
    (7, 5, 6),
)
# trimesh's reference icosahedron (``creation._data["icosahedron"]``): unit circumradius
_ICO_A = 0.5257311121191336
_ICO_B = 0.85065080835204
_ICOSAHEDRON_VERTICES = (
    (-_ICO_A, _ICO_B, 0.0),
    (_ICO_A, _ICO_B, 0.0),
    (-_ICO_A, -_ICO_B, 0.0),
    (_ICO_A, -_ICO_B, 0.0),
    (0.0, -_ICO_A, _ICO_B),
    (0.0, _ICO_A, _ICO_B),
    (0.0, -_ICO_A, -_ICO_B),
    (0.0, _ICO_A, -_ICO_B),
    (_ICO_B, 0.0, -_ICO_A),
    (_ICO_B, 0.0, _ICO_A),
    (-_ICO_B, 0.0, -_ICO_A),
    (-_ICO_B, 0.0, _ICO_A),
)
_ICOSAHEDRON_FACES = (
    (0, 11, 5),
    (0, 5, 1),
    (0, 1, 7),
    (0, 7, 10),
    (0, 10, 11),
    (1, 5, 9),
    (5, 11, 4),
    (11, 10, 2),
    (10, 7, 6),
    (7, 1, 8),
    (3, 9, 4),
    (3, 4, 2),
    (3, 2, 6),
    (3, 6, 8),
    (3, 8, 9),
    (4, 9, 5),
    (2, 4, 11),
    (6, 2, 10),
    (8, 6, 7),
    (9, 8, 1),
)
MERGE_M = 1e-8  # trimesh's ``tol.merge``: smaller triangle areas are dropped, closer vertices welded [m^2, m]
MERGE_DIGITS = 8  # decimal digits of MERGE_M: vertices are welded on coordinates rounded to these [count]

Mesh = tuple[np.ndarray, np.ndarray]  # vertices (n, 3) float64 [m], faces (m, 3) int64


def box(size: tuple[float, float, float]) -> Mesh:
    """``trimesh.creation.box(extents=size)``: a box of edge lengths ``size`` [m] centred on
    the origin, 8 vertices and 12 faces."""
    vertices = np.array(_BOX_VERTICES, order="C", dtype=np.float64)
    vertices -= 0.5
    vertices *= np.asarray(size, dtype=np.float64)
    return vertices, np.array(_BOX_FACES, order="C", dtype=np.int64)


def _triangle_areas(triangles: np.ndarray) -> np.ndarray:
    """``trimesh.triangles.area(triangles)`` per triangle (m, 3, 3) [m^2]."""
    vectors = triangles[:, 1:, :] - triangles[:, :2, :]
    crosses = np.cross(vectors[:, 0], vectors[:, 1])
    return np.sqrt((crosses**2).sum(axis=1)) / 2.0


def _weld(vertices: np.ndarray, faces: np.ndarray) -> Mesh:
    """What the ``Trimesh`` constructor's processing does to finite vertices: the vertices no
    face uses are dropped (unless there is no face: a primitive so small that every triangle
    fell below :data:`MERGE_M` keeps them all), and those equal once rounded to
    :data:`MERGE_DIGITS` decimals are welded into their first occurrence."""
    referenced = np.zeros(len(vertices), dtype=bool) if len(faces) else np.ones(len(vertices), dtype=bool)
    referenced[faces] = True
    rounded = (vertices * (10**MERGE_DIGITS)).round().astype(np.int64)
    first, position = weld_indices(rounded[referenced])  # trimesh's unique_rows(keep_order=True)
    inverse = np.zeros(len(vertices), dtype=np.int64)
    inverse[referenced] = position
    keep = np.nonzero(referenced)[0][first]
    return vertices[keep], inverse[faces.reshape(-1)].reshape((-1, 3))


def cylinder(radius: float, length: float, sections: int) -> Mesh:
    """``trimesh.creation.cylinder(radius, height=length, sections=sections)``: a cylinder of
    ``radius`` and ``length`` [m] along z, centred on the origin, its profile revolved in
    ``sections`` wedges and welded as trimesh's constructor welds it."""
    half = abs(float(length)) / 2.0
    profile = np.asarray([[0, -half], [radius, -half], [radius, half], [0, half]], dtype=np.float64)
    theta = np.linspace(0, np.pi * 2.0, sections + 1)
    points = np.column_stack((np.cos(theta), np.sin(theta)))
    per = len(profile)
    vertices = np.column_stack(
        (
            np.tile(points, (1, per)).reshape((-1, 2)) * np.tile(profile[:, 0], len(points)).reshape((-1, 1)),
            np.tile(profile[:, 1], len(points)),
        )
    )
    vertices = vertices[:-per]  # a whole turn: the last ring is the first
    quad = np.array([0, per, 1, 1, per, per + 1])
    single = np.tile(quad, per - 1).reshape((-1, 3))
    single += np.tile(np.arange(per - 1), (2, 1)).T.reshape((-1, 1))
    single = single[_triangle_areas(vertices[single]) > MERGE_M]
    offset = np.tile(np.arange(sections) * per, (len(single), 1)).T.reshape((-1, 1))
    stacked = np.tile(single.ravel(), sections).reshape((-1, 3))
    faces = (stacked + offset) % len(vertices)
    return _weld(vertices, faces)


def _subdivide(vertices: np.ndarray, faces: np.ndarray) -> Mesh:
    """``trimesh.remesh.subdivide``: every triangle cut into four at its edges' midpoints,
    the midpoints appended in trimesh's order of the edges (sorted by their larger, then
    their smaller vertex index)."""
    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape((-1, 2)), axis=1)
    # trimesh packs an edge (a, b) into one integer, b in the high bits, and sorts those
    _, unique, inverse = np.unique(
        edges[:, 1].astype(np.int64) << 32 | edges[:, 0].astype(np.int64), return_index=True, return_inverse=True
    )
    mid = vertices[edges[unique]].mean(axis=1)
    mid_idx = inverse.reshape((-1, 3)) + len(vertices)
    f = np.column_stack(
        [
            faces[:, 0],
            mid_idx[:, 0],
            mid_idx[:, 2],
            mid_idx[:, 0],
            faces[:, 1],
            mid_idx[:, 1],
            mid_idx[:, 2],
            mid_idx[:, 1],
            faces[:, 2],
            mid_idx[:, 0],
            mid_idx[:, 1],
            mid_idx[:, 2],
        ]
    ).reshape((-1, 3))
    return np.vstack((vertices, mid)), f


def _to_radius(vertices: np.ndarray, radius: float) -> np.ndarray:
    """Every vertex moved along its direction from the origin to ``radius`` [m], as trimesh does it."""
    scalar = np.sqrt(np.dot(vertices**2, [1, 1, 1]))
    unit = vertices / scalar.reshape((-1, 1))
    return vertices + unit * (radius - scalar).reshape((-1, 1))


def icosphere(subdivisions: int, radius: float) -> Mesh:
    """``trimesh.creation.icosphere(subdivisions, radius)``: an icosahedron subdivided
    ``subdivisions`` times, its vertices pushed out to ``radius`` [m] after each step."""
    radius = float(radius)
    vertices = np.array(_ICOSAHEDRON_VERTICES, dtype=np.float64)
    faces = np.array(_ICOSAHEDRON_FACES, dtype=np.int64)
    for _ in range(int(subdivisions)):
        vertices, faces = _subdivide(vertices, faces)
        vertices = _to_radius(vertices, radius)
    if subdivisions <= 0:
        vertices = _to_radius(vertices, radius)
    return vertices, faces
