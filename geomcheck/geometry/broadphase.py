"""Broad phase: which of many bounding spheres overlap, without an all-pairs matrix.

Sweep and prune along the axis over which the centres spread most: each sphere's interval
on that axis is compared only with the intervals that start inside it, found by one sort
and one binary search per sphere. Memory and time grow with the number of spheres plus the
number of overlapping intervals, not with its square. Lengths [m].
"""

from __future__ import annotations

import numpy as np

from geomcheck.geometry.raster import expand


def overlapping_spheres(centres: np.ndarray, radii: np.ndarray, margin: float = 0.0) -> np.ndarray:
    """Pairs ``(i, j)``, ``i < j``, of spheres (``centres`` (n, 3), ``radii`` (n,)) whose gap
    ``|c_i - c_j| - r_i - r_j`` is at most ``margin`` [m]: shape (k, 2), sorted by ``i`` then ``j``."""
    centres = np.asarray(centres, dtype=float).reshape(-1, 3)
    radii = np.asarray(radii, dtype=float).reshape(-1)
    n = len(centres)
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64)
    axis = int(np.argmax(np.ptp(centres, axis=0)))
    reach = radii + 0.5 * max(margin, 0.0)
    lo, hi = centres[:, axis] - reach, centres[:, axis] + reach
    order = np.argsort(lo, kind="stable")
    lo_sorted = lo[order]
    # intervals starting at or before this one's end, after it in the sorted order
    ends = np.searchsorted(lo_sorted, hi[order], side="right")
    counts = np.maximum(ends - np.arange(n) - 1, 0)
    first, rank = expand(counts)
    a = order[first]
    b = order[first + 1 + rank]
    gap = np.linalg.norm(centres[a] - centres[b], axis=1) - radii[a] - radii[b]
    keep = gap <= margin
    pairs = np.sort(np.column_stack((a[keep], b[keep])), axis=1)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


__all__ = ["overlapping_spheres"]
