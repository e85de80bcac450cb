"""Exact geometry of URDF primitives in their own frame, vectorised over points.

A primitive's frame is the one its ``<origin>`` defines: a box centred on it, a cylinder
along its z axis centred on it, a sphere centred on it. Points are arrays of shape (n, 3)
in that frame [m]; signed distances are [m], negative inside, zero on the surface, and
exact (not a bound) for every point. An ellipsoid (a box or cylinder marked ``ellipsoid``: the
ellipsoid inscribed in it) is measured as itself; its extents are its box's, which it touches on
every side. A capsule's distances are those of the cylinder that encloses it
(:class:`geomcheck.model.Capsule`): its fitted replacement is that cylinder, which a fix writes
back as the capsule it encloses (:mod:`geomcheck.patch.plan_formats`); its volume is its own, so
that how much bigger than its part it is (GC302) is the capsule's. The collision engines collide
it as the capsule.
"""

from __future__ import annotations

import numpy as np

from geomcheck.model import Box, Capsule, Cylinder, Sphere

ELLIPSOID_STEPS = 80  # bisection steps of the nearest point's parameter: past float64's resolution [count]

Primitive = Box | Cylinder | Sphere


def _rounded_sdf(outward: np.ndarray) -> np.ndarray:
    """Signed distance from per-axis excess distances ``outward`` (n, k) of a convex
    product shape: Euclidean norm of the positive part outside, largest part inside."""
    outside = np.linalg.norm(np.maximum(outward, 0.0), axis=1)
    inside = np.minimum(outward.max(axis=1), 0.0)
    return outside + inside


def box_signed_distance(points: np.ndarray, size: np.ndarray) -> np.ndarray:
    """Signed distance (n,) [m] of ``points`` (n, 3) to a centred box of edge lengths ``size`` (3,) [m]."""
    return _rounded_sdf(np.abs(points) - 0.5 * np.asarray(size, dtype=float))


def cylinder_signed_distance(points: np.ndarray, radius: float, length: float) -> np.ndarray:
    """Signed distance (n,) [m] of ``points`` (n, 3) to a centred cylinder along z ([m])."""
    radial = np.hypot(points[:, 0], points[:, 1]) - radius
    axial = np.abs(points[:, 2]) - 0.5 * length
    return _rounded_sdf(np.column_stack((radial, axial)))


def sphere_signed_distance(points: np.ndarray, radius: float) -> np.ndarray:
    """Signed distance (n,) [m] of ``points`` (n, 3) to a centred sphere of ``radius`` [m]."""
    return np.linalg.norm(points, axis=1) - radius


def ellipsoid_signed_distance(points: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Signed distance (n,) [m] of ``points`` (n, 3) to a centred ellipsoid of semi-axes ``axes`` (3,) [m].

    The nearest surface point of ``p`` is ``e^2 p / (t + e^2)`` for the largest root ``t >
    -min(e)^2`` of ``sum((e p / (t + e^2))^2) = 1``, decreasing in ``t`` there, found by
    bisection (Eberly, *Distance from a point to an ellipse, an ellipsoid, or a
    hyperellipsoid*). Coordinates are taken by magnitude, those at zero nudged off it by a
    relative 1e-12 so that every bracket's lower end is above the root."""
    e = np.asarray(axes, dtype=float)
    if not (e > 0.0).all():  # flat or empty (a zero semi-axis, GC1xx's): measured as its flat box
        return box_signed_distance(np.asarray(points, dtype=float), 2.0 * e)
    p = np.maximum(np.abs(np.asarray(points, dtype=float)), 1e-12 * float(e.max()))
    e2 = e**2
    lo = np.full(len(p), -float(e2.min()))
    hi = float(e.max()) * np.linalg.norm(p, axis=1) + float(e2.max())
    for _ in range(ELLIPSOID_STEPS):
        mid = 0.5 * (lo + hi)
        above = (((e * p) / (mid[:, None] + e2)) ** 2).sum(axis=1) > 1.0
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    t = 0.5 * (lo + hi)
    nearest = e2 * p / (t[:, None] + e2)
    distance = np.linalg.norm(p - nearest, axis=1)
    inside = ((p / e) ** 2).sum(axis=1) <= 1.0
    return np.where(inside, -distance, distance)


def semi_axes(primitive: Box | Cylinder) -> np.ndarray:
    """The semi-axes (3,) [m] of the ellipsoid inscribed in a box or a cylinder."""
    return half_extents(primitive)


def signed_distance(primitive: Primitive, points: np.ndarray) -> np.ndarray:
    """Exact signed distance (n,) [m] of ``points`` (n, 3), in the primitive's frame."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if isinstance(primitive, Box | Cylinder) and primitive.ellipsoid:
        return ellipsoid_signed_distance(pts, semi_axes(primitive))
    if isinstance(primitive, Box):
        return box_signed_distance(pts, np.asarray(primitive.size, dtype=float))
    if isinstance(primitive, Cylinder):
        return cylinder_signed_distance(pts, primitive.radius, primitive.length)
    return sphere_signed_distance(pts, primitive.radius)


LEAST_DISTANCE_PROBE = 64  # every 64th point is measured first, to bound the least distance [count]


def least_signed_distance(primitive: Primitive, points: np.ndarray, at_most: float = np.inf) -> float:
    """The least signed distance [m] of ``points`` (n, 3, n > 0), in the primitive's frame, or
    ``at_most`` when that is less: ``min(at_most, signed_distance(primitive, points).min())``,
    measured only at the points that can attain it. A point's excess over the primitive's half
    extents along one axis is at most its signed distance (the primitive lies in its bounding
    box), so a point whose excess exceeds the distance of a probed point, or ``at_most`` (the
    least of the points before, for points that come a batch at a time), is never the nearest."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    bound = min(float(at_most), float(signed_distance(primitive, pts[::LEAST_DISTANCE_PROBE]).min()))
    excess = (np.abs(pts) - half_extents(primitive)).max(axis=1)
    candidates = pts[excess <= bound]
    if not len(candidates):  # every point is farther than at_most (the probe's points are candidates)
        return bound
    return min(bound, float(signed_distance(primitive, candidates).min()))


def contains(primitive: Primitive, points: np.ndarray, tolerance: float = 0.0) -> np.ndarray:
    """Whether each point (n, 3) lies inside the primitive or within ``tolerance`` [m] of it, (n,) bool."""
    return signed_distance(primitive, points) <= tolerance


def volume(primitive: Primitive) -> float:
    """Volume [m^3]."""
    if isinstance(primitive, Box | Cylinder) and primitive.ellipsoid:
        return float(4.0 / 3.0 * np.pi * np.prod(semi_axes(primitive)))
    if isinstance(primitive, Capsule):  # its own volume: how much bigger than its part it is
        r = primitive.radius
        return float(np.pi * r**2 * primitive.straight_length + 4.0 / 3.0 * np.pi * r**3)
    if isinstance(primitive, Box):
        return float(np.prod(primitive.size))
    if isinstance(primitive, Cylinder):
        return float(np.pi * primitive.radius**2 * primitive.length)
    return float(4.0 / 3.0 * np.pi * primitive.radius**3)


def half_extents(primitive: Primitive) -> np.ndarray:
    """Half the primitive's extent along its own x, y, z axes, shape (3,) [m]."""
    if isinstance(primitive, Box):
        return 0.5 * np.asarray(primitive.size, dtype=float)
    if isinstance(primitive, Cylinder):
        return np.array([primitive.radius, primitive.radius, 0.5 * primitive.length])
    return np.full(3, float(primitive.radius))


def largest_extent(primitive: Primitive) -> float:
    """The primitive's largest edge, diameter or length [m]."""
    return float(2.0 * half_extents(primitive).max())


def gap_names(primitive: Primitive) -> tuple[str, ...]:
    """Names of the gaps :func:`extent_gaps` returns, in order."""
    if isinstance(primitive, Box):
        return ("x-", "x+", "y-", "y+", "z-", "z+")
    if isinstance(primitive, Cylinder):
        return ("radial", "z-", "z+")
    return ("radial",)


def extent_gaps(primitive: Primitive, points: np.ndarray) -> dict[str, float]:
    """Signed gaps [m] between the primitive's faces and the extremes of ``points`` (n, 3).

    Positive: the primitive reaches beyond the points on that side; negative: the points
    stick out. Box: ``x-, x+, y-, y+, z-, z+``; cylinder: ``radial`` (radius minus the
    largest distance from the axis), ``z-, z+``; sphere: ``radial`` (from the centre).
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if isinstance(primitive, Sphere):
        return {"radial": float(primitive.radius - np.linalg.norm(pts, axis=1).max())}
    h = half_extents(primitive)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    axial = {"z-": float(lo[2] + h[2]), "z+": float(h[2] - hi[2])}
    if isinstance(primitive, Cylinder):
        reach = float(np.hypot(pts[:, 0], pts[:, 1]).max())
        return {"radial": primitive.radius - reach, **axial}
    return {
        "x-": float(lo[0] + h[0]),
        "x+": float(h[0] - hi[0]),
        "y-": float(lo[1] + h[1]),
        "y+": float(h[1] - hi[1]),
        **axial,
    }


def extent_coverage(primitive: Primitive, points: np.ndarray) -> dict[str, tuple[float, float, float, float, float]]:
    """Per axis of the primitive, ``(share, primitive_extent, points_extent, low, high)``: the
    share of the points' extent [fraction] that the primitive spans, both extents [m], and
    the points' interval along the axis in the primitive's frame [m].

    Box: ``x``, ``y``, ``z``; cylinder: ``radial`` (diameters about the axis; the interval is
    0 to the largest distance from it) and ``z``; sphere: ``radial`` (about the centre).
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out: dict[str, tuple[float, float, float, float, float]] = {}
    if isinstance(primitive, Box | Cylinder):
        h = half_extents(primitive)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        axes = (0, 1, 2) if isinstance(primitive, Box) else (2,)
        for axis in axes:
            span = float(hi[axis] - lo[axis])
            overlap = max(0.0, min(hi[axis], h[axis]) - max(lo[axis], -h[axis]))
            share = overlap / span if span > 0.0 else float(abs(lo[axis]) <= h[axis])
            out["xyz"[axis]] = (share, float(2.0 * h[axis]), span, float(lo[axis]), float(hi[axis]))
    if isinstance(primitive, Cylinder | Sphere):
        reach = float(
            np.hypot(pts[:, 0], pts[:, 1]).max()
            if isinstance(primitive, Cylinder)
            else np.linalg.norm(pts, axis=1).max()
        )
        share = min(1.0, primitive.radius / reach) if reach > 0.0 else 1.0
        out = {"radial": (float(share), 2.0 * primitive.radius, 2.0 * reach, 0.0, reach), **out}
    return out


def volume_samples(primitive: Primitive, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` points uniformly distributed in the primitive's volume, shape (count, 3) [m]."""
    if isinstance(primitive, Box | Cylinder) and primitive.ellipsoid:  # the unit ball, stretched
        return volume_samples(Sphere(1.0), count, rng) * semi_axes(primitive)
    u = rng.random((count, 3))
    if isinstance(primitive, Box):
        return (u - 0.5) * np.asarray(primitive.size, dtype=float)
    if isinstance(primitive, Cylinder):
        r = primitive.radius * np.sqrt(u[:, 0])
        theta = 2.0 * np.pi * u[:, 1]
        return np.column_stack((r * np.cos(theta), r * np.sin(theta), (u[:, 2] - 0.5) * primitive.length))
    direction = rng.normal(size=(count, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    return direction * (primitive.radius * np.cbrt(u[:, :1]))
