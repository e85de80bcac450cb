"""The collision-engine interface: one small protocol over coal and python-fcl.

Conventions shared by every backend, so that results do not depend on the engine:

* lengths are [m]; transforms are (4, 4) world-from-object matrices; a cylinder's axis is
  its local z axis, centred on the origin, as in URDF; a capsule is collided as the capsule
  (along z, hemispherical ends), while its support points and bounds are those of the
  cylinder enclosing it, which stay lower bounds of its distances; an ellipsoid (a box or a
  cylinder marked ``ellipsoid``) likewise collides as itself and is bounded by its box or cylinder;
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

from geomcheck.geometry.hull_mesh import signed_volume, trimesh_hull
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
    return _hull_mesh(found[0], found[1]) if found is not None else solid_hull(vertices)


def hull_and_support(mesh: TriangleMesh) -> tuple[MeshArrays, np.ndarray]:
    """:func:`convex_hull` and :func:`support_points` of ``mesh`` together: a fine mesh's
    bounded hull, the expensive part of both, is computed once."""
    vertices = np.asarray(mesh.vertices, dtype=float)
    found = bounded_hull(vertices) if not is_exact_hull(mesh) else None
    if found is not None:
        return _hull_mesh(found[0], found[1]), enclosing_vertices(*found)
    exact = solid_hull(vertices)
    return exact, np.asarray(exact.vertices, dtype=float)


def points_hull(points: np.ndarray) -> MeshArrays:
    """The hull of ``points`` (n, 3) [m] with every extreme point a vertex (qhull's defaults, no
    merging of nearly coplanar facets: a guard built on it holds every point), or
    :func:`solid_hull`'s where qhull refuses them (flat input)."""
    from scipy.spatial import ConvexHull, QhullError

    pts = np.asarray(points, dtype=float)
    try:
        return _hull_mesh(pts, ConvexHull(pts))
    except (QhullError, ValueError):
        return solid_hull(pts)


def solid_hull(vertices: np.ndarray) -> MeshArrays:
    """The exact hull of ``vertices`` (n, 3) [m], given a tiny thickness where it is flat, its
    faces wound outwards."""
    try:
        exact = MeshArrays(*trimesh_hull(vertices))
        # four coplanar points come back as a flat "hull" of four faces
        if len(exact.faces) >= 4 and abs(signed_volume(exact.vertices, exact.faces)) > 0.0:
            return exact
    except Exception:  # qhull fails on flat or collinear input
        pass
    jitter = np.array([[0, 0, 0], [1e-6, 0, 0], [0, 1e-6, 0], [0, 0, 1e-6]], dtype=float)
    return MeshArrays(*trimesh_hull(np.concatenate([vertices + j for j in jitter])))


__all__ = [
    "SEPARATION_MARGIN",
    "CollisionBackend",
    "CollisionGeometry",
    "MeshArrays",
    "convex_hull",
    "hull_and_support",
    "is_exact_hull",
    "points_hull",
    "solid_hull",
    "support_points",
]
