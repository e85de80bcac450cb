"""Orthographic silhouettes and outlines of a link's shapes, for the report's pictures.

A silhouette is the filled outline of a mesh seen along one axis of the link frame. It is
computed by rasterising the projected triangles on a grid (numpy, vectorised over
triangles and pixels), tracing the filled region's boundary rings with marching squares
(contourpy) and simplifying them with a Douglas-Peucker pass run over all rings at once.
Rasterising makes the union of many overlapping triangles cheap and robust; its error is
at most one pixel outwards. Primitives (box, cylinder, sphere) are outlined exactly as the
convex hull of their projected corners or rims.

Views look at the link from outside along one axis, with right-handed screen axes:
``front`` from +x (u = y, v = z), ``side`` from -y (u = x, v = z), ``top`` from +z
(u = x, v = y). Coordinates are in the link frame [m]; a ring is an (k, 2) array of
(u, v) points, open (the last point joins the first), drawn with the even-odd rule so
that rings inside rings are holes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from geomcheck.geometry.frames import from_frame
from geomcheck.geometry.raster import Grid, cross, expand, rasterize_faces, trace_cells
from geomcheck.geometry.surface import ANALYSIS
from geomcheck.model import Box, Cylinder, Pose, Sphere

VIEWS: Mapping[str, tuple[int, int]] = {"front": (1, 2), "side": (0, 2), "top": (0, 1)}
AXIS_NAMES = "xyz"


def project(points: np.ndarray, view: str) -> np.ndarray:
    """Points (n, 3) [m] onto the ``view`` plane: (n, 2) (u, v) [m]."""
    return np.asarray(points, dtype=float)[:, list(VIEWS[view])]


def transform(points: np.ndarray, pose: Pose) -> np.ndarray:
    """Points (n, 3) given in a shape's frame, expressed in the link frame by ``pose``."""
    points = np.asarray(points, dtype=float)
    if pose.rpy == (0.0, 0.0, 0.0):
        return points + np.asarray(pose.xyz, dtype=float)
    return from_frame(points, pose.rotation(), np.asarray(pose.xyz, dtype=float))


def _corners(ring: np.ndarray) -> np.ndarray:
    """A closed ring without the points that lie on a straight run (exact: traced points
    sit on half cells); still closed."""
    open_ring = ring[:-1]
    if len(open_ring) < 4:
        return ring
    turn = cross(open_ring - np.roll(open_ring, 1, axis=0), np.roll(open_ring, -1, axis=0) - open_ring)
    kept = open_ring[turn != 0]
    return np.concatenate([kept, kept[:1]]) if len(kept) >= 3 else ring


def _used_bounds(points: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper corner (2,) of the points (n, 2) that ``faces`` (m, 3) use."""
    used = np.zeros(len(points), dtype=bool)
    used[faces] = True
    if not used.any():
        return np.full(2, -np.inf), np.full(2, np.inf)
    return points[used].min(axis=0), points[used].max(axis=0)


def panel_silhouettes(panels: Sequence[tuple[np.ndarray, np.ndarray, Grid]]) -> list[list[np.ndarray]]:
    """Silhouette rings of several triangle sets, each given as 2-D points (n, 2) [m], faces
    (m, 3) and its own grid, rasterised and traced together in one atlas (the grids
    stacked in rows).

    Returns, per panel, closed rings in (u, v) [m] clipped to the box its grid was made to
    cover, else to the bounds of the points its faces use: the raster errs outwards by up
    to a cell, the silhouette never leaves them.
    """
    widths = [grid.shape[1] for _, _, grid in panels]
    heights = np.array([grid.shape[0] for _, _, grid in panels], dtype=np.int64)
    starts = np.cumsum(heights) - heights
    mask = np.zeros((int(heights.sum()), max(widths, default=0)), dtype=bool)
    block = ANALYSIS.raster_chunk_triangles
    for (points, faces, grid), start in zip(panels, starts, strict=True):
        cells = grid.to_cells(points) + np.array([0.0, float(start)])
        rasterize_faces(cells, faces, mask, block)
    points, offsets = trace_cells(mask)
    bounds = [(g.lower, g.upper) if g.lower is not None else _used_bounds(p, f) for p, f, g in panels]
    out: list[list[np.ndarray]] = [[] for _ in panels]
    owner = np.searchsorted(starts, points[offsets[:-1], 1] + 0.5, side="right") - 1
    for ring, k in enumerate(owner):
        grid = panels[k][2]
        local = _corners(points[offsets[ring] : offsets[ring + 1]]) - np.array([0.0, float(starts[k])])
        out[k].append(np.clip(grid.from_cells(local), *bounds[k]))
    return out


def _ring_area(ring: np.ndarray) -> float:
    """Signed area of an open or closed ring (k, 2) [m^2]."""
    return float(0.5 * np.sum(cross(ring, np.roll(ring, -1, axis=0))))


def convex_outline(points: np.ndarray) -> np.ndarray:
    """Convex hull of 2-D points (n, 2), counter-clockwise, open; the extreme pair for collinear points."""
    from scipy.spatial import ConvexHull, QhullError  # scipy is imported when a hull is first needed

    pts = np.asarray(points, dtype=float)
    try:
        hull = ConvexHull(pts)
    except (QhullError, ValueError):  # fewer than 3 points, or collinear: the outline is a segment
        pts = np.unique(pts, axis=0)
        if len(pts) < 2:
            return pts
        direction = pts[-1] - pts[0]
        along = pts @ direction
        return pts[[int(np.argmin(along)), int(np.argmax(along))]]
    return pts[hull.vertices]


def canonical_outline(points: np.ndarray, step: float) -> np.ndarray:
    """The convex outline of 2-D points (n, 2) [m] on a grid of ``step`` [m], written one way
    only: counter-clockwise, without vertices on a straight edge, starting at the smallest
    (x, y). Rounding first and testing collinearity on the grid (a turn of grid points is a
    whole multiple of ``step`` squared) makes the ring independent of the last digits a CPU
    or BLAS kernel gives the points, and of where qhull starts."""
    grid = np.round(np.round(np.asarray(points, dtype=float) / step) * step, 10) + 0.0  # + 0.0: no -0.0
    ring = convex_outline(np.unique(grid, axis=0)) if len(grid) else grid
    if len(ring) >= 3:
        before, after = ring - np.roll(ring, 1, axis=0), np.roll(ring, -1, axis=0) - ring
        turn = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
        ring = ring[np.abs(turn) > step * step / 2]
    if len(ring) == 0:
        return ring
    first = int(np.lexsort((ring[:, 1], ring[:, 0]))[0])
    return np.roll(ring, -first, axis=0)


def simplify_rings(rings: Sequence[np.ndarray], tolerance: float) -> list[np.ndarray]:
    """Douglas-Peucker simplification of closed rings (each (k, 2), first point repeated last).

    Every ring is split at its first point and the point farthest from it; then all
    segments of all rings are refined together, one numpy pass per recursion level.
    Returns open rings, one per input ring, in order. A ring that collapses (a thin strip
    simplified to a line) is replaced by its convex hull, so thin parts stay visible.
    """
    rings = [np.asarray(r, dtype=float) for r in rings]
    if not rings:
        return []
    sizes = np.array([len(r) for r in rings])
    pts = np.concatenate(rings)
    starts = np.cumsum(sizes) - sizes
    ends = starts + np.maximum(sizes - 1, 0)
    ring_of, _ = expand(sizes)
    reach = np.hypot(*(pts - pts[starts][ring_of]).T)
    far = np.array([s + int(np.argmax(reach[s : e + 1])) for s, e in zip(starts, ends, strict=True)])
    keep = np.zeros(len(pts), dtype=bool)
    keep[starts] = keep[ends] = keep[far] = True
    seg_s, seg_e = np.concatenate([starts, far]), np.concatenate([far, ends])
    while True:
        active = seg_e - seg_s >= 2
        s, e = seg_s[active], seg_e[active]
        if len(s) == 0:
            break
        seg, rank = expand(e - s - 1)
        idx = s[seg] + 1 + rank
        a, b, p = pts[s][seg], pts[e][seg], pts[idx]
        chord = b - a
        length = np.hypot(*chord.T)
        off_chord = np.abs(cross(chord, p - a)) / np.where(length > 0, length, 1.0)
        dist = np.where(length > 0, off_chord, np.hypot(*(p - a).T))
        first = np.cumsum(e - s - 1) - (e - s - 1)
        dmax = np.maximum.reduceat(dist, first)
        split_at = np.minimum.reduceat(np.where(dist >= dmax[seg], idx, len(pts)), first)
        split = dmax > tolerance
        keep[split_at[split]] = True
        seg_s = np.concatenate([s[split], split_at[split]])
        seg_e = np.concatenate([split_at[split], e[split]])
    out = []
    for ring, s, e in zip(rings, starts, ends, strict=True):
        if len(ring) < 4:  # not a closed polygon: nothing to simplify
            out.append(ring)
            continue
        simple = pts[s:e][keep[s:e]]
        if len(simple) < 3 or abs(_ring_area(simple)) < 0.25 * abs(_ring_area(ring)):
            simple = convex_outline(ring[:-1])
        out.append(simple)
    return out


def round_rings(rings: Sequence[np.ndarray], step: float) -> list[np.ndarray]:
    """Rings with coordinates rounded to ``step`` [m], repeated points dropped, rings of
    fewer than two distinct points dropped."""
    out = []
    for ring in rings:
        r = np.round(np.round(np.asarray(ring, dtype=float) / step) * step, 10) + 0.0  # + 0.0: no -0.0
        distinct = np.any(r != np.roll(r, 1, axis=0), axis=1)
        r = r[distinct] if distinct.any() else r[:1]
        if len(r) >= 2:
            out.append(r)
    return out


def mesh_silhouettes(vertices: np.ndarray, faces: np.ndarray, pixel: float) -> dict[str, list[np.ndarray]]:
    """Closed boundary rings of the filled silhouette of a mesh (vertices (n, 3) [m] in the
    link frame, faces (m, 3)) in each of the :data:`VIEWS`, on grids of ``pixel`` [m]
    cells sized to the vertices (pass only used vertices for a tight grid)."""
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return {view: [] for view in VIEWS}
    panels = []
    for view in VIEWS:
        projected = project(vertices, view)
        grid = Grid.covering(projected.min(axis=0), projected.max(axis=0), pixel)
        panels.append((projected, faces, grid))
    return dict(zip(VIEWS, panel_silhouettes(panels), strict=True))


def mesh_silhouette(vertices: np.ndarray, faces: np.ndarray, view: str, grid: Grid) -> list[np.ndarray]:
    """Closed boundary rings of the filled silhouette of a mesh (vertices (n, 3) [m] in the
    link frame, faces (m, 3)) seen in ``view``, on ``grid``."""
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return []
    return panel_silhouettes([(project(vertices, view), faces, grid)])[0]


def circle(centre: np.ndarray, radius: float, segments: int) -> np.ndarray:
    """A regular polygon of ``segments`` corners on a circle, (segments, 2) [m]."""
    angle = np.arange(segments) * (2 * np.pi / segments)
    return np.asarray(centre, dtype=float) + radius * np.stack([np.cos(angle), np.sin(angle)], axis=1)


def primitive_points(geometry: Box | Cylinder | Sphere, pose: Pose, segments: int) -> np.ndarray:
    """Corner points (n, 3) of a primitive in the link frame whose convex hull is the
    primitive (boxes exactly, cylinders as prisms of ``segments`` sides)."""
    if isinstance(geometry, Box):
        signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
        local = signs * np.asarray(geometry.size, dtype=float) / 2
    elif isinstance(geometry, Cylinder):
        rim = circle(np.zeros(2), geometry.radius, segments)
        ends = np.repeat([-geometry.length / 2, geometry.length / 2], segments)
        local = np.column_stack([np.concatenate([rim, rim]), ends])
    else:
        local = np.zeros((1, 3))
    return transform(local, pose)


def primitive_outline(geometry: Box | Cylinder | Sphere, pose: Pose, view: str, segments: int) -> np.ndarray:
    """Outline of a primitive placed by ``pose`` in the link frame, seen in ``view``: an open
    ring (k, 2) [m]. A sphere projects to a circle; boxes and cylinders to the hull of their
    projected corners."""
    if isinstance(geometry, Sphere):
        centre = project(np.asarray([pose.xyz], dtype=float), view)[0]
        return circle(centre, geometry.radius, segments)
    return convex_outline(project(primitive_points(geometry, pose, segments), view))
