"""The closest point of a triangle to a point, for many pairs at once, with numpy.

:func:`closest_points` is ``trimesh.triangles.closest_point`` (trimesh 4.x and 5.x; Ericson,
*Real-Time Collision Detection*, 5.1.5), repeated operation for operation so that its
distances are trimesh's to the last bit, without importing trimesh (about 0.4 s of a cold
check that needs one point-to-hull distance).
"""

from __future__ import annotations

import numpy as np

TOL_ZERO = 1e-13  # trimesh's ``tol.zero``: the regions' boundaries are widened by it [m^2]


def closest_points(triangles: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The point (n, 3) [m] of each triangle of ``triangles`` (n, 3, 3) nearest to the point
    of the same row of ``points`` (n, 3): a corner, a point of an edge or of the face,
    whichever Voronoi region of the triangle holds the point."""
    triangles = np.asarray(triangles, dtype=np.float64)
    points = np.asarray(points, dtype=np.float64)
    result = np.zeros_like(points)
    remain = np.ones(len(points), dtype=bool)
    ones = [1.0, 1.0, 1.0]
    a, b, c = triangles[:, 0, :], triangles[:, 1, :], triangles[:, 2, :]
    ab, ac = b - a, c - a
    ap = points - a
    d1 = np.dot(ab * ap, ones)
    d2 = np.dot(ac * ap, ones)
    is_a = np.logical_and(d1 < TOL_ZERO, d2 < TOL_ZERO)
    result[is_a] = a[is_a]
    remain[is_a] = False
    _collapsed_first_edge(a, ab, ac, ap, result, remain)
    bp = points - b
    d3 = np.dot(ab * bp, ones)
    d4 = np.dot(ac * bp, ones)
    is_b = (d3 > -TOL_ZERO) & (d4 <= d3) & remain
    result[is_b] = b[is_b]
    remain[is_b] = False
    vc = (d1 * d4) - (d3 * d2)
    is_ab = (vc < TOL_ZERO) & (d1 > -TOL_ZERO) & (d3 < TOL_ZERO) & remain
    if is_ab.any():
        v = (d1[is_ab] / (d1[is_ab] - d3[is_ab])).reshape((-1, 1))
        result[is_ab] = a[is_ab] + (v * ab[is_ab])
        remain[is_ab] = False
    cp = points - c
    d5 = np.dot(ab * cp, ones)
    d6 = np.dot(ac * cp, ones)
    is_c = (d6 > -TOL_ZERO) & (d5 <= d6) & remain
    result[is_c] = c[is_c]
    remain[is_c] = False
    vb = (d5 * d2) - (d1 * d6)
    is_ac = (vb < TOL_ZERO) & (d2 > -TOL_ZERO) & (d6 < TOL_ZERO) & remain
    if is_ac.any():
        w = (d2[is_ac] / (d2[is_ac] - d6[is_ac])).reshape((-1, 1))
        result[is_ac] = a[is_ac] + w * ac[is_ac]
        remain[is_ac] = False
    va = (d3 * d6) - (d5 * d4)
    is_bc = (va < TOL_ZERO) & ((d4 - d3) > -TOL_ZERO) & ((d5 - d6) > -TOL_ZERO) & remain
    if is_bc.any():
        d43 = d4[is_bc] - d3[is_bc]
        w = (d43 / (d43 + (d5[is_bc] - d6[is_bc]))).reshape((-1, 1))
        result[is_bc] = b[is_bc] + w * (c[is_bc] - b[is_bc])
        remain[is_bc] = False
    if remain.any():  # inside the face: barycentric coordinates
        _inside_face(a, ab, ac, va, vb, vc, result, remain)
    return result


def _collapsed_first_edge(
    a: np.ndarray, ab: np.ndarray, ac: np.ndarray, ap: np.ndarray, result: np.ndarray, remain: np.ndarray
) -> None:
    """A triangle whose first edge has no length: the nearest point of its other edge, in ``result``
    (its rows then no longer ``remain``)."""
    collapsed_ab = np.all(ab == 0.0, axis=1)
    if collapsed_ab.any():
        segment = ac[collapsed_ab]
        length_squared = np.sum(segment**2, axis=1)
        factor = np.zeros(len(segment), dtype=np.float64)
        np.divide(np.sum(ap[collapsed_ab] * segment, axis=1), length_squared, out=factor, where=length_squared > 0)
        result[collapsed_ab] = a[collapsed_ab] + np.clip(factor, 0, 1)[:, None] * segment
        remain[collapsed_ab] = False


def _inside_face(
    a: np.ndarray,
    ab: np.ndarray,
    ac: np.ndarray,
    va: np.ndarray,
    vb: np.ndarray,
    vc: np.ndarray,
    result: np.ndarray,
    remain: np.ndarray,
) -> None:
    """The rows that ``remain``: points over the face, at their barycentric coordinates."""
    denom = 1.0 / (va[remain] + vb[remain] + vc[remain])
    v = (vb[remain] * denom).reshape((-1, 1))
    w = (vc[remain] * denom).reshape((-1, 1))
    result[remain] = a[remain] + (ab[remain] * v) + (ac[remain] * w)
