"""Convex hulls of link geometry kept across runs: the inertia family's hulls, hull
distances and solid hull mass properties, backed by the active store.

Each result is a pure function of a point set (a link's or merged body's extreme points,
:func:`geomcheck.geometry.shapes.link_points`) and is keyed by the exact bytes of those
points (their sha256, with their shape), so a mesh edited, rescaled or moved gives other
points and misses; the store adds geomcheck's code and the libraries' versions (scipy's
qhull, trimesh). Without an active store everything is computed, as before. On a warm run
neither scipy nor trimesh is imported for these.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING

from geomcheck.cache import cached_arrays

if TYPE_CHECKING:
    import numpy as np

    from geomcheck.geometry.inertia import Hull, SolidHull

HULL_NAMESPACE = "link-hull"
DISTANCE_NAMESPACE = "hull-distance"
SOLID_NAMESPACE = "solid-hull"
FORMAT = 1


def points_digest(points: np.ndarray) -> list[object]:
    """The key of a point set: its shape and the sha256 of its float64 bytes."""
    import numpy as np

    exact = np.ascontiguousarray(points, dtype=float)
    return [list(exact.shape), hashlib.sha256(exact.tobytes()).hexdigest()]


def stored_hull(points: np.ndarray) -> Hull:
    """:func:`geomcheck.geometry.inertia.convex_hull` of ``points`` (n, 3) [m], from the
    active store when it holds it."""
    import numpy as np

    from geomcheck.geometry.inertia import Hull, convex_hull

    def compute() -> dict[str, np.ndarray]:
        hull = convex_hull(points)
        return {
            "lower": hull.lower,
            "upper": hull.upper,
            "volume": np.asarray(hull.volume, dtype=float),
            "triangles": hull.triangles,
            "equations": hull.equations,
        }

    arrays = cached_arrays(HULL_NAMESPACE, [FORMAT, points_digest(points)], compute)
    return Hull(
        lower=arrays["lower"],
        upper=arrays["upper"],
        volume=float(arrays["volume"]),
        triangles=arrays["triangles"],
        equations=arrays["equations"],
    )


def stored_distance_outside(hull: Hull, point: np.ndarray) -> float:
    """:func:`geomcheck.geometry.inertia.distance_outside` of ``point`` (3,) [m], the nearest
    triangle's distance (trimesh's) read from the active store when it holds it."""
    import numpy as np

    from geomcheck.geometry.inertia import distance_outside, distance_to_triangles

    if len(hull.triangles) == 0 or float((hull.equations[:, :3] @ point + hull.equations[:, 3]).max()) <= 0.0:
        return distance_outside(hull, point)  # no trimesh on these paths: nothing to keep
    key = [FORMAT, points_digest(hull.triangles), [float(v) for v in point]]
    arrays = cached_arrays(
        DISTANCE_NAMESPACE,
        key,
        lambda: {"distance": np.asarray(distance_to_triangles(hull.triangles, point), dtype=float)},
    )
    return float(arrays["distance"])


def stored_solid_hull(points: np.ndarray) -> SolidHull | None:
    """:func:`geomcheck.geometry.inertia.solid_hull` of ``points`` (n, 3) [m], from the
    active store when it holds it (a point set without volume is stored as such)."""
    import numpy as np

    from geomcheck.geometry.inertia import SolidHull, solid_hull

    def compute() -> dict[str, np.ndarray]:
        solid = solid_hull(points)
        if solid is None:
            return {"solid": np.asarray(False)}
        return {
            "solid": np.asarray(True),
            "mass": np.asarray(solid.mass, dtype=float),
            "center_mass": solid.center_mass,
            "moment_inertia": solid.moment_inertia,
        }

    arrays = cached_arrays(SOLID_NAMESPACE, [FORMAT, points_digest(points)], compute)
    if not bool(arrays["solid"]):
        return None
    return SolidHull(
        mass=float(arrays["mass"]),
        center_mass=arrays["center_mass"],
        moment_inertia=arrays["moment_inertia"],
    )


__all__ = ["points_digest", "stored_distance_outside", "stored_hull", "stored_solid_hull"]
