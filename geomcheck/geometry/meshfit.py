"""Comparison of a collision mesh with its link's visual geometry, both ways.

Containment is judged against convex hulls (a collision mesh is usually the convex hull or
a simplification of the visual mesh): how far the collision mesh reaches beyond the visual
hull, and (in :mod:`geomcheck.geometry.fit`) how far the visual sticks out of the collision
hull. Surface distances between the two point sets give a Hausdorff-like figure whose
resolution is the sample spacing. Lengths [m].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geomcheck.geometry.elements import CollisionElement, VisualCloud
from geomcheck.thresholds import FitThresholds

COMPARISON_SAMPLE_DIVISOR = 4  # the collision mesh gets this fraction of the visual's samples [1]


@dataclass(frozen=True)
class MeshComparison:
    """``gaps``: per link axis and side, how far the collision mesh's bounds reach beyond
    the visual's [m] (negative: the visual reaches further); ``reverse_coverage``: share of
    the collision surface inside the visual hull or within tolerance; ``overshoot_*``: how far
    the collision mesh reaches out of the visual hull [m]; ``surface_distance_*``: distances
    between the two surfaces' points, both ways [m]."""

    gaps: dict[str, float]
    reverse_coverage: float
    overshoot_max: float
    overshoot_p95: float
    surface_distance_max: float
    surface_distance_p95: float


def compare_meshes(visual: VisualCloud, element: CollisionElement, th: FitThresholds) -> MeshComparison | None:
    """Compare the collision mesh ``element`` with ``visual``; ``None`` without a mesh."""
    from scipy.spatial import cKDTree  # scipy is imported when first needed

    if element.solid is None or len(visual.vertices) == 0:
        return None
    if element.same_as_visual:
        zero = {f"{a}{side}": 0.0 for a in "xyz" for side in "-+"}
        return MeshComparison(zero, 1.0, 0.0, 0.0, 0.0, 0.0)
    rng = np.random.default_rng(th.seed)
    solid = element.solid
    coll_vertices = solid.vertices if solid.hull is None else solid.hull.vertices
    coll_samples = solid.surface.sample(max(1, th.surface_samples // COMPARISON_SAMPLE_DIVISOR), rng)
    coll_points = np.concatenate((coll_vertices, coll_samples))
    vis_lo, vis_hi = visual.bounds()
    lo, hi = coll_points.min(axis=0), coll_points.max(axis=0)
    gaps = {}
    for axis, name in enumerate("xyz"):
        gaps[f"{name}-"] = float(vis_lo[axis] - lo[axis])
        gaps[f"{name}+"] = float(hi[axis] - vis_hi[axis])
    if visual.hull is not None:
        # distance to a convex hull is convex: its maximum over the mesh is at a hull vertex
        over_max = float(max(0.0, visual.hull.signed_distance(coll_vertices).max()))
        sd_samples = visual.hull.signed_distance(coll_samples)
        reverse = float(np.mean(sd_samples <= th.protrusion_tolerance_m)) if len(sd_samples) else 1.0
        over_p95 = max(0.0, float(np.percentile(sd_samples, 95))) if len(sd_samples) else over_max
    else:
        reverse, over_max, over_p95 = 1.0, 0.0, 0.0
    to_visual = cKDTree(visual.points).query(coll_points)[0]
    to_collision = cKDTree(coll_points).query(visual.points)[0]
    both = np.concatenate((to_visual, to_collision))
    return MeshComparison(
        gaps=gaps,
        reverse_coverage=reverse,
        overshoot_max=over_max,
        overshoot_p95=over_p95,
        surface_distance_max=float(both.max()),
        surface_distance_p95=float(np.percentile(both, 95)),
    )


__all__ = ["COMPARISON_SAMPLE_DIVISOR", "MeshComparison", "compare_meshes"]
