"""The collision-engine interface: one small protocol over coal and python-fcl.

Conventions shared by every backend, so that results do not depend on the engine:

* lengths are [m]; transforms are (4, 4) world-from-object matrices; a cylinder's axis is
  its local z axis, centred on the origin, as in URDF;
* :meth:`CollisionBackend.distance` is the separation distance when the objects are apart.
  When they overlap it is minus the penetration depth for two convex objects (primitives
  and convex hulls) and exactly ``0.0`` when a triangle mesh is involved (mesh distance
  queries only see surfaces: neither engine gives a meaningful depth there);
* :meth:`CollisionBackend.collide` gives ``(in collision, depth >= 0)``; for a pair that
  involves a mesh the depth is that of the meshes' convex hulls (exact for convex meshes,
  an estimate otherwise);
* objects are built once per geometry by :meth:`CollisionBackend.make` and reused for
  every query, also as both arguments of one query.

Meshes are bounding-volume hierarchies (OBBRSS) over their triangles: like MoveIt, a mesh
is a surface, so a mesh lying wholly inside another one is not in contact with it. A mesh is
anything with ``vertices`` (n, 3) [m] and ``faces`` (m, 3) arrays (:class:`MeshArrays`, a
loaded mesh, a trimesh object): the collision layer works on the arrays and imports no
trimesh, whose convex hull :func:`convex_hull` reproduces with qhull and numpy.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    from scipy.spatial import ConvexHull

from geomcheck.geometry.surface import ANALYSIS, TriangleMesh, bounded_hull, enclosing_vertices
from geomcheck.model import Box, Cylinder, Sphere


@dataclass(frozen=True, eq=False)
class MeshArrays:
    """A triangle mesh as arrays: ``vertices`` (n, 3) float64 [m], ``faces`` (m, 3) int64."""

    vertices: np.ndarray
    faces: np.ndarray


CollisionGeometry = Box | Cylinder | Sphere | TriangleMesh

# Two convex sets holding two meshes and apart by more than this cannot have touching meshes:
# the margin absorbs the engines' distance tolerance (GJK, about 1e-6 m) [m]
SEPARATION_MARGIN = 1e-4


class CollisionBackend(Protocol):
    """A collision engine. ``name`` is ``"coal"`` or ``"fcl"``."""

    name: str

    def make(self, geometry: CollisionGeometry) -> Any:
        """The engine's object for a geometry in its own frame (mesh: vertices [m] and triangles)."""
        ...

    def part(self, obj: Any, mesh: TriangleMesh) -> Any:
        """The engine's object for some of the triangles of the mesh object ``obj`` (``mesh``, in
        its frame), keeping ``obj``'s convex hull (it holds the part too); built on first use."""
        ...

    def distance(self, a: Any, ta: np.ndarray, b: Any, tb: np.ndarray) -> float:
        """Separation distance [m] of ``a`` placed at ``ta`` and ``b`` at ``tb`` (4, 4); ``<= 0``
        when they overlap (see the module conventions)."""
        ...

    def collide(self, a: Any, ta: np.ndarray, b: Any, tb: np.ndarray) -> tuple[bool, float]:
        """(in collision, penetration depth [m] >= 0)."""
        ...

    def hull_distance(self, a: Any, ta: np.ndarray, b: Any, tb: np.ndarray) -> float:
        """Signed distance [m] of the convex hulls of ``a`` and ``b`` (primitives are their own
        hull): a lower bound of :meth:`distance` whenever that is positive, and much cheaper
        for meshes."""
        ...

    def nearest(
        self, a: Any, ta: np.ndarray, b: Any, tb: np.ndarray, hull: bool
    ) -> tuple[float, np.ndarray, np.ndarray]:
        """``(signed distance [m], point of a (3,), point of b (3,))``, the points in the frame of
        ``ta``/``tb`` and realising the distance: of the convex hulls when ``hull``, else of the
        objects (:meth:`hull_distance` and :meth:`distance` respectively, without the latter's
        clamping to ``0.0`` for overlapping meshes)."""
        ...

    # Hot loops convert a transform once and reuse it: ``placement`` turns a (4, 4) matrix
    # into the engine's transform; the ``placed_`` queries take those instead of matrices.
    def placement(self, m: np.ndarray) -> Any:
        """The engine's transform for the (4, 4) matrix ``m``."""
        ...

    def placed_distance(self, a: Any, pa: Any, b: Any, pb: Any) -> float:
        """:meth:`distance` with transforms from :meth:`placement`."""
        ...

    def placed_hull_distance(self, a: Any, pa: Any, b: Any, pb: Any) -> float:
        """:meth:`hull_distance` with transforms from :meth:`placement`."""
        ...


def _hull_mesh(points: np.ndarray, hull: ConvexHull) -> MeshArrays:
    """A qhull hull as a mesh of its own vertices, every face wound outwards."""
    index = np.full(len(points), -1, dtype=np.int64)
    index[hull.vertices] = np.arange(len(hull.vertices))
    faces = index[hull.simplices]
    corners = points[hull.simplices]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    inward = np.einsum("ij,ij->i", normals, hull.equations[:, :3]) < 0.0
    faces[inward] = faces[inward][:, ::-1]
    return MeshArrays(np.ascontiguousarray(points[hull.vertices], dtype=np.float64), faces)


# trimesh's convex hull (trimesh.convex.convex_hull, trimesh 4.x/5.x), reproduced below: its
# qhull options, zero-area threshold (util.TOL_ZERO) and vertex merging digits (tol.merge)
TRIMESH_QHULL_OPTIONS = "Qt QbB Pp"
TRIMESH_TOL_ZERO = 1e-13
TRIMESH_MERGE_DIGITS = 8
# a watertight hull whose volume is below this share of its bounding box's may be one trimesh
# turns inside out (its volume's sign is then round-off): that rare hull is left to trimesh
INVERSION_MARGIN = 1e-6


def _trimesh_hull(points: np.ndarray) -> MeshArrays:
    """``trimesh.convex.convex_hull(points)`` as arrays (imports trimesh): the rare hulls
    :func:`_qhull_hull` does not reproduce itself."""
    import trimesh

    hull = trimesh.convex.convex_hull(points)
    return MeshArrays(np.asarray(hull.vertices, dtype=np.float64), np.asarray(hull.faces, dtype=np.int64))


def _qhull_hull(points: np.ndarray) -> MeshArrays:
    """The vertices and faces ``trimesh.convex.convex_hull(points)`` gives, bit for bit: qhull
    with trimesh's options (joggled on failure), zero-area faces dropped, every face wound away
    from the area-weighted centroid, the vertices no face uses dropped. Where trimesh would go on
    to change that mesh otherwise (merge vertices equal to 1e-8 m, rewind faces over the
    adjacency graph, invert a flat hull or one of negative volume) the hull is trimesh's own
    (:func:`_trimesh_hull`).
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
        return MeshArrays(vertices, faces)  # no solid: not used as a hull (see convex_hull)
    processed = _processed(vertices, faces)
    return _trimesh_hull(points) if processed is None else processed


def _processed(vertices: np.ndarray, faces: np.ndarray) -> MeshArrays | None:
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
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape((-1, 2))
    _, group, counts = np.unique(np.sort(directed, axis=1), axis=0, return_inverse=True, return_counts=True)
    forward = np.bincount(group.reshape(-1), weights=directed[:, 0] < directed[:, 1], minlength=len(counts))
    if np.any((counts == 2) & (forward != 1)):
        return None  # fix_winding would rewind faces
    if np.all(counts == 2):  # watertight: fix_inversion inverts a hull of negative volume
        corners = vertices[faces]
        volume = float(np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum()) / 6.0
        if volume <= INVERSION_MARGIN * float(np.prod(np.ptp(vertices, axis=0))):
            return None
    return MeshArrays(vertices, faces)


def is_exact_hull(mesh: TriangleMesh) -> bool:
    """Whether :func:`convex_hull` of ``mesh`` is exact (holds every vertex), so that it equals
    the hull of :func:`support_points`; else it is a bounded hull and may leave vertices out."""
    return len(mesh.vertices) <= ANALYSIS.hull_exact_points


def support_points(mesh: TriangleMesh) -> np.ndarray:
    """Points (k, 3) [m] whose convex hull holds every vertex of ``mesh``: its hull's vertices,
    or for a mesh too fine for an exact hull (``AnalysisThresholds.hull_exact_points``) those
    of its bounded hull pushed out by the hull's tolerance. Bounds built on them stay sound."""
    return hull_and_support(mesh)[1]


def convex_hull(mesh: TriangleMesh) -> MeshArrays:
    """The convex hull of a mesh's vertices, the vertices and faces of trimesh's ``convex_hull``;
    a degenerate (flat) mesh gets a tiny thickness so the hull stays a solid (the hull is only
    used for bounds and depth estimates). A mesh too fine for an exact hull gets its bounded
    hull, of a size set by its tolerance."""
    vertices = np.asarray(mesh.vertices, dtype=float)
    found = bounded_hull(vertices) if not is_exact_hull(mesh) else None
    return _hull_mesh(found[0], found[1]) if found is not None else _solid_hull(vertices)


def hull_and_support(mesh: TriangleMesh) -> tuple[MeshArrays, np.ndarray]:
    """:func:`convex_hull` and :func:`support_points` of ``mesh`` together: a fine mesh's
    bounded hull, the expensive part of both, is computed once."""
    vertices = np.asarray(mesh.vertices, dtype=float)
    found = bounded_hull(vertices) if not is_exact_hull(mesh) else None
    if found is not None:
        return _hull_mesh(found[0], found[1]), enclosing_vertices(*found)
    exact = _solid_hull(vertices)
    return exact, np.asarray(exact.vertices, dtype=float)


def _solid_hull(vertices: np.ndarray) -> MeshArrays:
    """The exact hull of ``vertices`` (n, 3) [m], given a tiny thickness where it is flat."""
    try:
        exact = _qhull_hull(vertices)
        if len(exact.faces) >= 4:
            return exact
    except Exception:  # qhull fails on flat or collinear input
        pass
    jitter = np.array([[0, 0, 0], [1e-6, 0, 0], [0, 1e-6, 0], [0, 0, 1e-6]], dtype=float)
    return _qhull_hull(np.concatenate([vertices + j for j in jitter]))


__all__ = [
    "SEPARATION_MARGIN",
    "CollisionBackend",
    "CollisionGeometry",
    "MeshArrays",
    "convex_hull",
    "hull_and_support",
    "is_exact_hull",
    "support_points",
]
