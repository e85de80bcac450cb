"""trimesh's convex hull of a point set and its mass properties, with qhull and numpy.

:func:`trimesh_hull` gives the vertices and faces ``trimesh.convex.convex_hull`` gives (trimesh
4.x and 5.x), bit for bit, without importing trimesh: a link's hull is the collision engine's
convex object and the body whose mass properties the inertia rules compare, and a cold check
must not pay about 0.4 s to import trimesh for it. :func:`solid_properties` and
:func:`solid` repeat ``Trimesh.mass_properties`` and ``Trimesh.is_volume`` on those arrays,
operation for operation. The rare hull trimesh's processing would change beyond what is
reproduced here (welded vertices, rewound or inverted faces) is trimesh's own, imported then.
"""

from __future__ import annotations

import numpy as np

HullMesh = tuple[np.ndarray, np.ndarray]  # vertices (n, 3) float64 [m], faces (m, 3) int64

# trimesh's convex hull (trimesh.convex.convex_hull, trimesh 4.x/5.x), reproduced below: its
# qhull options, zero-area threshold (util.TOL_ZERO) and vertex merging digits (tol.merge)
TRIMESH_QHULL_OPTIONS = "Qt QbB Pp"
TRIMESH_TOL_ZERO = 1e-13
TRIMESH_MERGE_DIGITS = 8
# a watertight hull whose volume is below this share of its bounding box's may be one trimesh
# turns inside out (its volume's sign is then round-off): that rare hull is left to trimesh
INVERSION_MARGIN = 1e-6


def _trimeshs_own_hull(points: np.ndarray) -> HullMesh:
    """``trimesh.convex.convex_hull(points)`` as arrays (imports trimesh): the rare hulls
    :func:`trimesh_hull` does not reproduce itself."""
    import trimesh

    hull = trimesh.convex.convex_hull(points)
    return np.asarray(hull.vertices, dtype=np.float64), np.asarray(hull.faces, dtype=np.int64)


def trimesh_hull(points: np.ndarray) -> HullMesh:
    """The vertices and faces ``trimesh.convex.convex_hull(points)`` gives, bit for bit: qhull
    with trimesh's options (joggled on failure), zero-area faces dropped, every face wound away
    from the area-weighted centroid, the vertices no face uses dropped. Where trimesh would go on
    to change that mesh otherwise (merge vertices equal to 1e-8 m, rewind faces over the
    adjacency graph, invert a flat hull or one of negative volume) the hull is trimesh's own
    (:func:`_trimeshs_own_hull`).
    Raises :class:`QhullError` (or ``ValueError``) like trimesh when qhull fails."""
    from scipy.spatial import ConvexHull, QhullError  # scipy is imported when a hull is first needed

    try:
        hull = ConvexHull(points, qhull_options=TRIMESH_QHULL_OPTIONS)
    except QhullError:
        hull = ConvexHull(points, qhull_options="QJ")
    vid = np.sort(hull.vertices)
    mask = np.zeros(len(hull.points), dtype=np.int64)
    mask[vid] = np.arange(len(vid))
    faces = mask[hull.simplices].copy()
    vertices = hull.points[vid].copy()
    # trimesh.triangles.cross and util.unitize(check_valid=True), operation for operation
    corners = vertices[faces]
    edges = corners[:, 1:, :] - corners[:, :2, :]
    crosses = np.cross(edges[:, 0], edges[:, 1])
    norm = np.sqrt(np.dot(crosses * crosses, [1.0] * 3))
    valid = norm > TRIMESH_TOL_ZERO
    norm[valid] **= -1
    normals = (crosses * norm.reshape((-1, 1)))[valid]
    faces = faces[valid]
    crosses = crosses[valid]
    areas = np.sqrt((crosses**2).sum(axis=1)) / 2.0
    centres = vertices[faces].mean(axis=1)
    try:
        centroid = np.average(centres, weights=areas, axis=0)
    except ZeroDivisionError:
        centroid = vertices.mean(axis=0) if len(vertices) else np.zeros(3)
    backwards = np.dot(normals * (centres - centroid), [1.0] * 3) < 0.0
    faces[backwards] = np.fliplr(faces[backwards])
    if len(faces) < 4:
        return vertices, faces  # no solid: not used as a hull
    processed = _processed(vertices, faces)
    return _trimeshs_own_hull(points) if processed is None else processed


def _processed(vertices: np.ndarray, faces: np.ndarray) -> HullMesh | None:
    """The hull mesh as trimesh's processing leaves it (``Trimesh(process=True)`` drops the
    vertices no face uses, then ``fix_normals(multibody=False)``), or ``None`` where that would
    merge vertices, rewind faces over the adjacency graph or invert the mesh."""
    referenced = np.zeros(len(vertices), dtype=bool)
    referenced[faces] = True
    keys = (vertices[referenced] * 10.0**TRIMESH_MERGE_DIGITS).round().astype(np.int64)
    if len(np.unique(keys, axis=0)) != len(keys):
        return None  # merge_vertices would merge vertices
    if not referenced.all():
        index = np.zeros(len(vertices), dtype=np.int64)
        index[referenced] = np.arange(len(keys))
        vertices, faces = vertices[referenced], index[faces.reshape(-1)].reshape((-1, 3))
    directed = _edges(faces)
    _, group, counts = np.unique(np.sort(directed, axis=1), axis=0, return_inverse=True, return_counts=True)
    forward = np.bincount(group.reshape(-1), weights=directed[:, 0] < directed[:, 1], minlength=len(counts))
    if np.any((counts == 2) & (forward != 1)):
        return None  # fix_winding would rewind faces
    if np.all(counts == 2):  # watertight: fix_inversion inverts a hull of negative volume
        volume = signed_volume(vertices, faces)
        if volume <= INVERSION_MARGIN * float(np.prod(np.ptp(vertices, axis=0))):
            return None
    return vertices, faces


def signed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """The volume [m^3] a closed surface ``vertices`` (n, 3) [m], ``faces`` (m, 3) encloses,
    negative when its faces are wound inwards, 0 for a flat one (divergence theorem)."""
    corners = np.asarray(vertices, dtype=float)[faces]
    return float(np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum()) / 6.0


def _edges(faces: np.ndarray) -> np.ndarray:
    """The directed edges (3 m, 2) of ``faces`` (m, 3), in trimesh's order."""
    return faces[:, [0, 1, 1, 2, 2, 0]].reshape((-1, 2))


def solid(vertices: np.ndarray, faces: np.ndarray) -> tuple[float, np.ndarray, np.ndarray] | None:
    """:func:`solid_properties` of ``vertices`` (n, 3) [m] and ``faces`` (m, 3) when they are
    what ``Trimesh.is_volume`` accepts (every edge shared by exactly two faces, which run it in
    opposite directions, and a finite centre of mass of a positive volume), else ``None``."""
    if len(vertices) == 0 or len(faces) == 0:
        return None
    directed = _edges(faces)
    _, group, counts = np.unique(np.sort(directed, axis=1), axis=0, return_inverse=True, return_counts=True)
    group = group.reshape(-1)
    if not np.all(counts == 2):
        return None
    # each pair: the first edge's end is the second edge's start
    order = np.argsort(group, kind="stable")
    pairs = directed[order].reshape((-1, 4))
    if not np.array_equal(pairs[:, 1], pairs[:, 2]):
        return None
    properties = solid_properties(vertices, faces)
    volume, centre, _ = properties
    return properties if bool(np.isfinite(centre).all() and volume > 0.0) else None


def is_solid(vertices: np.ndarray, faces: np.ndarray) -> bool:
    """``Trimesh.is_volume`` of ``vertices`` (n, 3) [m] and ``faces`` (m, 3) (:func:`solid`)."""
    return solid(vertices, faces) is not None


def solid_properties(vertices: np.ndarray, faces: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """``trimesh.triangles.mass_properties`` of the closed surface ``vertices`` (n, 3) [m],
    ``faces`` (m, 3) at unit density: the volume [m^3], the centre of mass (3,) [m] and the
    inertia tensor (3, 3) [kg m^2 at 1 kg/m^3] about it. The integrals are Tonon's (2004),
    each sum taken in trimesh's order so the values are its values."""
    triangles = np.asarray(vertices, dtype=np.float64)[faces]
    vectors = triangles[:, 1:, :] - triangles[:, :2, :]
    crosses = np.cross(vectors[:, 0], vectors[:, 1])
    p0, p1, p2 = triangles[:, 0, :], triangles[:, 1, :], triangles[:, 2, :]
    f1 = p0 + p1 + p2
    f2 = p0**2 + p1**2 + p0 * p1 + p2 * f1
    f3 = (p0**3) + (p0**2) * (p1) + (p0) * (p1**2) + (p1**3) + (p2 * f2)
    g0 = f2 + (p0 + f1) * p0
    g1 = f2 + (p1 + f1) * p1
    g2 = f2 + (p2 + f1) * p2
    integral = np.zeros((10, len(f1)))
    integral[0] = crosses[:, 0] * f1[:, 0]
    integral[1:4] = (crosses * f2).T
    integral[4:7] = (crosses * f3).T
    for i in range(3):
        j = np.mod(i + 1, 3)
        integral[i + 7] = crosses[:, i] * ((p0[:, j] * g0[:, i]) + (p1[:, j] * g1[:, i]) + (p2[:, j] * g2[:, i]))
    integrated = integral.sum(axis=1) / np.array([6, 24, 24, 24, 60, 60, 60, 120, 120, 120], dtype=np.float64)
    volume = integrated[0]
    with np.errstate(invalid="ignore", divide="ignore"):  # a flat surface's centre is 0/0: not finite
        centre = integrated[1:4] / volume
    inertia = np.zeros((3, 3))
    inertia[0, 0] = integrated[5] + integrated[6] - (volume * (centre[[1, 2]] ** 2).sum())
    inertia[1, 1] = integrated[4] + integrated[6] - (volume * (centre[[0, 2]] ** 2).sum())
    inertia[2, 2] = integrated[4] + integrated[5] - (volume * (centre[[0, 1]] ** 2).sum())
    inertia[0, 1] = -(integrated[7] - (volume * np.prod(centre[[0, 1]])))
    inertia[1, 2] = -(integrated[8] - (volume * np.prod(centre[[1, 2]])))
    inertia[0, 2] = -(integrated[9] - (volume * np.prod(centre[[0, 2]])))
    inertia[2, 0] = inertia[0, 2]
    inertia[2, 1] = inertia[1, 2]
    inertia[1, 0] = inertia[0, 1]
    return float(volume), centre, inertia * 1.0
