"""Sphere covers of convex hulls: a few balls that together contain the whole hull.

The hull is cut into cells along its two longest principal axes, and each cell's part of the
hull is enclosed in a ball around the exact vertices of that part (not of the whole cell), so
long thin parts get tight covers.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

MAX_CELLS_PER_AXIS = 3  # cells along each of the two longest principal axes [count]
COVER_PADDING_M = 1e-6  # added to every cover radius against rounding [m]


def _enclosing_ball(points: np.ndarray) -> tuple[np.ndarray, float]:
    """A ball containing ``points`` (n, 3): centred on their bounding box."""
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    return centre, float(np.linalg.norm(points - centre, axis=1).max()) + COVER_PADDING_M


@dataclass(frozen=True)
class _Hull:
    """A convex hull in its principal frame: vertices (n, 3), unique edges (m, 2) and
    half-spaces ``normals @ u <= offsets`` (f, 3), (f,)."""

    vertices: np.ndarray
    edges: np.ndarray
    normals: np.ndarray
    offsets: np.ndarray


def _cell_points(hull: _Hull, x: tuple[float, float], y: tuple[float, float]) -> np.ndarray:
    """Vertices of the hull cut to the prism ``x0 <= u <= x1, y0 <= v <= y1`` (w free),
    shape (n, 3). A vertex of the cut polytope is a hull vertex inside the prism, a hull edge
    crossing a side plane, or a prism edge (a line along w) entering or leaving the hull."""
    v = hull.vertices
    tol = 1e-9 * max(1.0, float(np.abs(v).max()))
    inside = (v[:, 0] >= x[0] - tol) & (v[:, 0] <= x[1] + tol) & (v[:, 1] >= y[0] - tol) & (v[:, 1] <= y[1] + tol)
    found = [v[inside]]
    ea, eb = v[hull.edges[:, 0]], v[hull.edges[:, 1]]
    for axis, other, bounds, other_bounds in ((0, 1, x, y), (1, 0, y, x)):
        for c in bounds:
            da, db = ea[:, axis] - c, eb[:, axis] - c
            cross = da * db < 0
            t = da[cross] / (da[cross] - db[cross])
            p = ea[cross] + t[:, None] * (eb[cross] - ea[cross])
            keep = (p[:, other] >= other_bounds[0] - tol) & (p[:, other] <= other_bounds[1] + tol)
            found.append(p[keep])
    nz = hull.normals[:, 2]
    flat, up, down = np.abs(nz) < 1e-12, nz > 1e-12, nz < -1e-12
    for cu in x:
        for cv in y:
            rhs = hull.offsets - hull.normals[:, 0] * cu - hull.normals[:, 1] * cv
            if (rhs[flat] < -tol).any():
                continue
            hi = (rhs[up] / nz[up]).min() if up.any() else np.inf
            lo = (rhs[down] / nz[down]).max() if down.any() else -np.inf
            if lo <= hi + tol and np.isfinite(lo) and np.isfinite(hi):
                found.append(np.array([[cu, cv, lo], [cu, cv, hi]]))
    return np.concatenate(found)


def _qhull(points: np.ndarray) -> Any:
    """scipy's ``ConvexHull`` of ``points``, or ``None`` for a flat or degenerate set."""
    from scipy.spatial import ConvexHull, QhullError  # scipy is imported when a hull is first needed

    try:
        return ConvexHull(points)
    except QhullError:
        return None


def _faces_hull(
    points: np.ndarray, faces: Sequence[Sequence[int]], mean: np.ndarray, frame: np.ndarray, local: np.ndarray
) -> _Hull:
    """The :class:`_Hull` of points whose hull faces are known (point-index polygons), in the
    principal frame (``local`` = ``(points - mean) @ frame.T``): each face's outward normal
    from its first three corners, its edges from consecutive corners."""
    corners = points[np.array([face[:3] for face in faces])]  # (f, 3, 3): three corners of each face
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1)[:, None]  # the caller saw no face without area
    inward = np.einsum("fi,fi->f", normals, points.mean(axis=0) - corners[:, 0]) > 0
    normals[inward] = -normals[inward]
    offsets = np.einsum("fi,fi->f", normals, corners[:, 0])
    edges = {(min(a, b), max(a, b)) for face in faces for a, b in zip(face, (*face[1:], face[0]), strict=True)}
    return _Hull(local, np.array(sorted(edges)), normals @ frame.T, offsets - normals @ mean)


def _has_area(points: np.ndarray, faces: Sequence[Sequence[int]]) -> bool:
    """Whether every face of ``faces`` (point-index polygons of ``points``) spans an area that
    a normal can be computed from (relative to the points' extent)."""
    corners = points[np.array([face[:3] for face in faces])]
    areas = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    extent = float(np.ptp(points, axis=0).max())
    return bool(areas.min() > 1e-12 * extent * extent)


def hull_cover(points: np.ndarray, faces: Sequence[Sequence[int]] | None = None) -> list[tuple[np.ndarray, float]]:
    """Balls covering the convex hull of ``points`` (n, 3) [m], as ``(centre, radius)``.

    ``faces``, when known, are the hull's faces as polygons of point indices, every point a
    vertex (a box's corners, a cylinder's rim points): no hull is computed (and scipy is not
    imported); a hull short enough for one ball gets the very ball qhull's hull gives."""
    points = np.asarray(points, dtype=float)
    if len(points) < 4:
        return [_enclosing_ball(points)] if len(points) else []
    qhull = None
    if faces is not None and not _has_area(points, faces):
        faces = None  # a box or cylinder of zero width: qhull finds it flat, one ball covers it
    if faces is not None:
        vertices = np.arange(len(points))
    else:
        qhull = _qhull(points)
        if qhull is None:
            return [_enclosing_ball(points)]
        vertices = qhull.vertices
    mean = points[vertices].mean(axis=0)
    centred = points[vertices] - mean
    _, vectors = np.linalg.eigh(centred.T @ centred)
    frame = vectors[:, ::-1].T  # rows: principal axes, longest first
    local = (points - mean) @ frame.T
    lo, hi = local[vertices].min(axis=0), local[vertices].max(axis=0)
    extent = hi - lo
    cell = max(float(extent[2]), float(extent[0]) / MAX_CELLS_PER_AXIS, 1e-9)
    counts = [int(np.clip(round(float(extent[i]) / cell), 1, MAX_CELLS_PER_AXIS)) for i in (0, 1)]
    if counts == [1, 1]:
        return [_enclosing_ball(points[vertices])]
    if faces is not None:
        hull = _faces_hull(points, faces, mean, frame, local)
    else:
        assert qhull is not None
        tri = qhull.simplices
        edges = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]]), axis=1), axis=0)
        normals = qhull.equations[:, :3] @ frame.T
        offsets = -(qhull.equations[:, :3] @ mean + qhull.equations[:, 3])
        hull = _Hull(local, edges, normals, offsets)
    xs = np.linspace(lo[0], hi[0], counts[0] + 1)
    ys = np.linspace(lo[1], hi[1], counts[1] + 1)
    out = []
    for i in range(counts[0]):
        for j in range(counts[1]):
            pts = _cell_points(hull, (xs[i], xs[i + 1]), (ys[j], ys[j + 1]))
            if len(pts):
                centre, radius = _enclosing_ball(pts)
                out.append((mean + centre @ frame, radius))
    return out or [_enclosing_ball(points[vertices])]
