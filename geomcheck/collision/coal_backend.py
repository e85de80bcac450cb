"""The coal backend (the maintained successor of hpp-fcl), the default engine."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import coal
import numpy as np

from geomcheck.collision.base import SEPARATION_MARGIN, CollisionGeometry, MeshArrays, is_exact_hull, points_hull
from geomcheck.collision.support_cache import stored_hull_and_support
from geomcheck.geometry.primitives import cylinder_signed_distance, semi_axes
from geomcheck.geometry.surface import TriangleMesh
from geomcheck.model import Box, Capsule, Cylinder, Sphere


@dataclass(eq=False)
class CoalObject:
    """A coal geometry; ``hull`` is the convex hull of a mesh and ``guard`` a convex polytope
    holding the whole mesh (the hull itself where that is exact), ``None`` for primitives.

    A mesh's BVH (``geometry``) is built from ``mesh`` on first use: a warm check whose
    answers are all cached, or whose guards keep the meshes apart, never builds it."""

    built: Any = None
    hull: Any = None
    guard: Any = None
    mesh: TriangleMesh | None = None

    @property
    def geometry(self) -> Any:
        if self.built is None and self.mesh is not None:
            self.built = _bvh(self.mesh)
        return self.built

    def build(self) -> None:
        """Build what is built on first use (before forking workers, which would each build it)."""
        self.geometry  # noqa: B018

    @property
    def is_mesh(self) -> bool:
        return self.hull is not None


def _transform(m: np.ndarray) -> coal.Transform3s:
    return coal.Transform3s(m[:3, :3], m[:3, 3])


def _bvh(mesh: TriangleMesh) -> coal.BVHModelOBBRSS:
    model = coal.BVHModelOBBRSS()
    model.beginModel(len(mesh.faces), len(mesh.vertices))
    model.addVertices(np.ascontiguousarray(mesh.vertices, dtype=float))
    model.addTriangles(np.ascontiguousarray(mesh.faces, dtype=np.int64))
    model.endModel()
    return model


def _convex(hull: MeshArrays) -> Any:
    """coal's convex object of a hull computed here (its vertices and outward triangles). coal's
    own qhull call is not used: it crashes the process on a nearly flat point set (a 6 cm square
    marker plate given the micrometre thickness that keeps its hull a solid)."""
    points = coal.StdVec_Vec3s()
    for p in np.asarray(hull.vertices, dtype=float):
        points.append(p)
    triangles = coal.StdVec_Triangle()
    for a, b, c in np.asarray(hull.faces, dtype=np.int64).tolist():
        triangles.append(coal.Triangle(a, b, c))
    return coal.Convex(points, triangles)


def sphere_cylinder_signed(ga: Any, pa: coal.Transform3s, gb: Any, pb: coal.Transform3s) -> float | None:
    """The signed distance [m] of a sphere and a cylinder, ``None`` for any other pair.

    coal 3.0's sphere-cylinder routine measures an overlap through the cylinder's side only:
    a 20 mm sphere centred 4 mm from the middle of a 32 mm long, 41 mm radius cylinder gets
    61 mm (radius plus radius) where it leaves through the cap after 32 mm. For a sphere and
    any convex body, the signed distance is the centre's signed distance to the body less the
    radius, exactly."""
    if isinstance(ga, coal.Cylinder) and isinstance(gb, coal.Sphere):
        ga, pa, gb, pb = gb, pb, ga, pa
    if not (isinstance(ga, coal.Sphere) and isinstance(gb, coal.Cylinder)):
        return None
    centre = np.asarray(pb.getRotation()).T @ (np.asarray(pa.getTranslation()) - np.asarray(pb.getTranslation()))
    inside = cylinder_signed_distance(centre[None], float(gb.radius), 2.0 * float(gb.halfLength))
    return float(inside[0]) - float(ga.radius)


def corrected(d: float, ga: Any, pa: coal.Transform3s, gb: Any, pb: coal.Transform3s) -> float:
    """coal's signed distance ``d`` [m] of the pair, with the exact one where coal's is wrong (an
    overlapping sphere and cylinder: :func:`sphere_cylinder_signed`)."""
    exact = sphere_cylinder_signed(ga, pa, gb, pb) if d < 0.0 else None
    return d if exact is None else exact


def _mesh_object(mesh: TriangleMesh) -> CoalObject:
    hull_mesh, support = stored_hull_and_support(mesh)
    hull = _convex(hull_mesh)
    guard = hull if is_exact_hull(mesh) else _convex(points_hull(support))
    return CoalObject(None, hull, guard, mesh)


class CoalBackend:
    name = "coal"

    def __init__(self) -> None:
        self._distance_request = coal.DistanceRequest()
        self._distance_request.enable_signed_distance = True
        self._collision_request = coal.CollisionRequest()
        # with enable_contact off, coal 3.0 misses some deep box-box overlaps (a thin box through a
        # cube: tests/collision/test_collision_backends.py::test_deep_box_overlap_is_a_collision)
        self._collision_request.enable_contact = True
        self._collision_request.num_max_contacts = 1
        # closer than the margin, or overlapping: no contact point or depth needed
        self._guard_request = coal.CollisionRequest()
        self._guard_request.enable_contact = False
        self._guard_request.security_margin = SEPARATION_MARGIN
        # placements of collide's two objects, set in place (cheaper than building two per query)
        self._scratch = (coal.Transform3s(), coal.Transform3s())

    def make(self, geometry: CollisionGeometry) -> CoalObject:
        if isinstance(geometry, Box | Cylinder) and geometry.ellipsoid:  # the ellipsoid, not its box's corners
            return CoalObject(coal.Ellipsoid(*(float(a) for a in semi_axes(geometry))))
        if isinstance(geometry, Box):
            return CoalObject(coal.Box(*(float(s) for s in geometry.size)))
        if isinstance(geometry, Capsule):  # the capsule itself: its enclosing cylinder's rims would touch
            return CoalObject(coal.Capsule(float(geometry.radius), float(geometry.straight_length)))
        if isinstance(geometry, Cylinder):
            return CoalObject(coal.Cylinder(float(geometry.radius), float(geometry.length)))
        if isinstance(geometry, Sphere):
            return CoalObject(coal.Sphere(float(geometry.radius)))
        return _mesh_object(geometry)

    def part(self, obj: CoalObject, mesh: TriangleMesh) -> CoalObject:
        return CoalObject(None, obj.hull, obj.guard, mesh)

    def placement(self, m: np.ndarray) -> coal.Transform3s:
        return _transform(m)

    def _signed(self, ga: Any, pa: coal.Transform3s, gb: Any, pb: coal.Transform3s) -> float:
        result = coal.DistanceResult()  # a reused result would keep the previous minimum
        return corrected(float(coal.distance(ga, pa, gb, pb, self._distance_request, result)), ga, pa, gb, pb)

    def placed_distance(self, a: CoalObject, pa: coal.Transform3s, b: CoalObject, pb: coal.Transform3s) -> float:
        d = self._signed(a.geometry, pa, b.geometry, pb)
        return 0.0 if d <= 0.0 and (a.is_mesh or b.is_mesh) else d

    def placed_hull_distance(self, a: CoalObject, pa: coal.Transform3s, b: CoalObject, pb: coal.Transform3s) -> float:
        return self._signed(a.hull or a.geometry, pa, b.hull or b.geometry, pb)

    def distance(self, a: CoalObject, ta: np.ndarray, b: CoalObject, tb: np.ndarray) -> float:
        return self.placed_distance(a, _transform(ta), b, _transform(tb))

    def hull_distance(self, a: CoalObject, ta: np.ndarray, b: CoalObject, tb: np.ndarray) -> float:
        return self.placed_hull_distance(a, _transform(ta), b, _transform(tb))

    def nearest(
        self, a: CoalObject, ta: np.ndarray, b: CoalObject, tb: np.ndarray, hull: bool
    ) -> tuple[float, np.ndarray, np.ndarray]:
        ga, gb = (a.hull or a.geometry, b.hull or b.geometry) if hull else (a.geometry, b.geometry)
        result = coal.DistanceResult()
        pa, pb = _transform(ta), _transform(tb)
        d = corrected(float(coal.distance(ga, pa, gb, pb, self._distance_request, result)), ga, pa, gb, pb)
        return d, np.array(result.getNearestPoint1()), np.array(result.getNearestPoint2())

    def collide(self, a: CoalObject, ta: np.ndarray, b: CoalObject, tb: np.ndarray) -> tuple[bool, float]:
        pa, pb = self._scratch
        pa.setRotation(ta[:3, :3])
        pa.setTranslation(ta[:3, 3])
        pb.setRotation(tb[:3, :3])
        pb.setTranslation(tb[:3, 3])
        if a.is_mesh or b.is_mesh:
            # the guards hold the meshes: apart by more than the margin, the meshes cannot touch,
            # and the guards' GJK is much cheaper than the meshes' BVH traversal
            result = coal.CollisionResult()
            coal.collide(a.guard or a.geometry, pa, b.guard or b.geometry, pb, self._guard_request, result)
            if not result.isCollision():
                return False, 0.0
        result = coal.CollisionResult()
        coal.collide(a.geometry, pa, b.geometry, pb, self._collision_request, result)
        if not result.isCollision():
            return False, 0.0
        return True, max(0.0, -self.placed_hull_distance(a, pa, b, pb))


__all__ = ["CoalBackend", "CoalObject"]
