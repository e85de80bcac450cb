"""The python-fcl backend (FCL as MoveIt uses it), selected with ``--backend fcl``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import fcl
import numpy as np

from geomcheck.collision.base import CollisionGeometry, convex_hull
from geomcheck.geometry.primitives import semi_axes
from geomcheck.geometry.surface import TriangleMesh
from geomcheck.model import Box, Capsule, Cylinder, Sphere


@dataclass(frozen=True, eq=False)
class FclObject:
    """An FCL geometry with two collision objects, so that one geometry can be both arguments
    of a query; ``hull`` holds the same for a mesh's convex hull (``None`` for primitives)."""

    first: fcl.CollisionObject
    second: fcl.CollisionObject
    hull: FclObject | None = None
    sphere: bool = False

    @property
    def is_mesh(self) -> bool:
        return self.hull is not None


def _objects(geometry: Any, hull: FclObject | None = None) -> FclObject:
    first = fcl.CollisionObject(geometry, fcl.Transform())
    return FclObject(first, fcl.CollisionObject(geometry, fcl.Transform()), hull, isinstance(geometry, fcl.Sphere))


def _bvh(mesh: TriangleMesh) -> fcl.BVHModel:
    model = fcl.BVHModel()
    model.beginModel(len(mesh.faces), len(mesh.vertices))
    vertices = np.ascontiguousarray(mesh.vertices, dtype=float)
    model.addSubModel(vertices, np.ascontiguousarray(mesh.faces, dtype=np.int32))
    model.endModel()
    return model


def _convex(mesh: TriangleMesh) -> fcl.Convex:
    hull = convex_hull(mesh)
    faces = np.asarray(hull.faces, dtype=np.int64)
    flat = np.hstack([np.full((len(faces), 1), 3, dtype=np.int64), faces]).ravel()
    return fcl.Convex(np.ascontiguousarray(hull.vertices, dtype=float), len(faces), flat)


def _transform(m: np.ndarray) -> fcl.Transform:
    return fcl.Transform(np.ascontiguousarray(m[:3, :3]), np.ascontiguousarray(m[:3, 3]))


def _placed(a: FclObject, pa: fcl.Transform, b: FclObject, pb: fcl.Transform) -> tuple[Any, Any]:
    a.first.setTransform(pa)
    b.second.setTransform(pb)
    return a.first, b.second


class FclBackend:
    name = "fcl"

    def __init__(self) -> None:
        self._distance_request = fcl.DistanceRequest(enable_signed_distance=True)
        self._nearest_request = fcl.DistanceRequest(enable_nearest_points=True, enable_signed_distance=True)
        self._collision_request = fcl.CollisionRequest(num_max_contacts=1, enable_contact=False)

    def make(self, geometry: CollisionGeometry) -> FclObject:
        if isinstance(geometry, Box | Cylinder) and geometry.ellipsoid:  # the ellipsoid, not its box's corners
            return _objects(fcl.Ellipsoid(*(float(a) for a in semi_axes(geometry))))
        if isinstance(geometry, Box):
            return _objects(fcl.Box(*(float(s) for s in geometry.size)))
        if isinstance(geometry, Capsule):  # the capsule itself: its enclosing cylinder's rims would touch
            return _objects(fcl.Capsule(float(geometry.radius), float(geometry.straight_length)))
        if isinstance(geometry, Cylinder):
            return _objects(fcl.Cylinder(float(geometry.radius), float(geometry.length)))
        if isinstance(geometry, Sphere):
            return _objects(fcl.Sphere(float(geometry.radius)))
        return _objects(_bvh(geometry), _objects(_convex(geometry)))

    def part(self, obj: FclObject, mesh: TriangleMesh) -> FclObject:
        return _objects(_bvh(mesh), obj.hull)

    def placement(self, m: np.ndarray) -> fcl.Transform:
        return _transform(m)

    def placed_distance(self, a: FclObject, pa: fcl.Transform, b: FclObject, pb: fcl.Transform) -> float:
        d = float(fcl.distance(*_placed(a, pa, b, pb), self._distance_request, fcl.DistanceResult()))
        return 0.0 if d <= 0.0 and (a.is_mesh or b.is_mesh) else d

    def placed_hull_distance(self, a: FclObject, pa: fcl.Transform, b: FclObject, pb: fcl.Transform) -> float:
        placed = _placed(a.hull or a, pa, b.hull or b, pb)
        return float(fcl.distance(*placed, self._distance_request, fcl.DistanceResult()))

    def distance(self, a: FclObject, ta: np.ndarray, b: FclObject, tb: np.ndarray) -> float:
        return self.placed_distance(a, _transform(ta), b, _transform(tb))

    def hull_distance(self, a: FclObject, ta: np.ndarray, b: FclObject, tb: np.ndarray) -> float:
        return self.placed_hull_distance(a, _transform(ta), b, _transform(tb))

    def nearest(
        self, a: FclObject, ta: np.ndarray, b: FclObject, tb: np.ndarray, hull: bool
    ) -> tuple[float, np.ndarray, np.ndarray]:
        oa, ob = (a.hull or a, b.hull or b) if hull else (a, b)
        result = fcl.DistanceResult()
        d = fcl.distance(*_placed(oa, _transform(ta), ob, _transform(tb)), self._nearest_request, result)
        first, second = (np.array(p, dtype=float) for p in result.nearest_points)
        if oa.is_mesh != ob.is_mesh and not hull:
            # FCL gives a primitive-mesh pair's points in mesh-primitive order, and a sphere's
            # and a mesh's points in the objects' own frames
            if ob.is_mesh:
                first, second = second, first
            if oa.sphere or ob.sphere:
                first, second = ta[:3, :3] @ first + ta[:3, 3], tb[:3, :3] @ second + tb[:3, 3]
        return float(d), first, second

    def collide(self, a: FclObject, ta: np.ndarray, b: FclObject, tb: np.ndarray) -> tuple[bool, float]:
        result = fcl.CollisionResult()
        fcl.collide(*_placed(a, _transform(ta), b, _transform(tb)), self._collision_request, result)
        if not result.is_collision:
            return False, 0.0
        return True, max(0.0, -self.hull_distance(a, ta, b, tb))


__all__ = ["FclBackend", "FclObject"]
