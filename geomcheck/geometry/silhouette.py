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
from dataclasses import dataclass

import contourpy
import numpy as np
from scipy.spatial import ConvexHull, QhullError

from geomcheck.model import Box, Cylinder, Pose, Sphere

VIEWS: Mapping[str, tuple[int, int]] = {"front": (1, 2), "side": (0, 2), "top": (0, 1)}
AXIS_NAMES = "xyz"


@dataclass(frozen=True)
class Grid:
    """A raster over a view plane: cell (row j, column i) spans
    ``origin + (i, j) * pixel`` to ``origin + (i + 1, j + 1) * pixel`` [m]."""

    origin: np.ndarray  # (2,) lower corner (u, v) [m]
    pixel: float  # cell edge [m]
    shape: tuple[int, int]  # (rows along v, columns along u)

    @classmethod
    def covering(cls, lower: np.ndarray, upper: np.ndarray, pixel: float, pad: int = 2) -> Grid:
        """The grid over the box ``lower``..``upper`` (each (2,) [m]) with ``pad`` empty cells around it.

        The box's sides fall on cell centres, not cell edges, so that faces seen edge-on at
        the extremes mark the same number of cells on every side.
        """
        extent = np.maximum(np.asarray(upper, float) - np.asarray(lower, float), 0.0)
        cells = np.ceil(extent / pixel + 1.0).astype(int) + 2 * pad
        origin = np.asarray(lower, float) - (pad + 0.5) * pixel
        return cls(origin=origin, pixel=float(pixel), shape=(int(cells[1]), int(cells[0])))


def project(points: np.ndarray, view: str) -> np.ndarray:
    """Points (n, 3) [m] onto the ``view`` plane: (n, 2) (u, v) [m]."""
    return np.asarray(points, dtype=float)[:, list(VIEWS[view])]


def transform(points: np.ndarray, pose: Pose) -> np.ndarray:
    """Points (n, 3) given in a shape's frame, expressed in the link frame by ``pose``."""
    return np.asarray(points, dtype=float) @ pose.rotation().T + np.asarray(pose.xyz, dtype=float)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _expand(counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For items with ``counts`` (m,): the item of each of ``counts.sum()`` slots and its rank in the item."""
    owner = np.repeat(np.arange(len(counts)), counts)
    first = np.cumsum(counts) - counts
    return owner, np.arange(int(counts.sum())) - first[owner]


def _fill_centres(p: np.ndarray, mask: np.ndarray) -> None:
    """Set the cells of ``mask`` whose centre lies in a triangle of ``p`` (m, 3, 2) [cells].

    Scanline fill: each triangle, its corners sorted bottom to top, is cut by the rows
    whose centre line it spans; on each row the long edge (bottom to top) bounds one
    side and the lower or upper short edge the other. The spans of covered cell centres
    go to a per-row difference array.
    """
    rows = mask.shape[0]
    order = np.argsort(p[:, :, 1], axis=1)
    q = np.take_along_axis(p, order[:, :, None], axis=1)
    (x0, y0), (x1, y1), (x2, y2) = q[:, 0].T, q[:, 1].T, q[:, 2].T
    row_lo = np.clip(np.ceil(y0 - 0.5), 0, rows).astype(np.int64)
    row_hi = np.clip(np.floor(y2 - 0.5), -1, rows - 1).astype(np.int64)
    tri, rank = _expand(np.maximum(row_hi - row_lo + 1, 0))
    if len(tri) == 0:
        return
    row = row_lo[tri] + rank
    y = row + 0.5

    def slope(xa: np.ndarray, ya: np.ndarray, xb: np.ndarray, yb: np.ndarray) -> np.ndarray:
        dy = yb - ya
        return np.divide(xb - xa, dy, out=np.zeros_like(dy), where=dy > 0)

    long_x = x0[tri] + (y - y0[tri]) * slope(x0, y0, x2, y2)[tri]
    lower = y < y1[tri]
    short_x = np.where(
        lower,
        x0[tri] + (y - y0[tri]) * slope(x0, y0, x1, y1)[tri],
        x1[tri] + (y - y1[tri]) * slope(x1, y1, x2, y2)[tri],
    )
    first = np.ceil(np.minimum(long_x, short_x) - 0.5).astype(np.int64)
    last = np.floor(np.maximum(long_x, short_x) - 0.5).astype(np.int64)
    _mark_spans(mask, row, first, last)


def _mark_spans(mask: np.ndarray, row: np.ndarray, first: np.ndarray, last: np.ndarray) -> None:
    """Set cells ``first..last`` (inclusive, clipped) of each ``row`` through a per-row difference array."""
    rows, cols = mask.shape
    first = np.clip(first, 0, cols)
    last = np.clip(last, -1, cols - 1)
    ok = first <= last
    width = cols + 1
    size = rows * width
    diff = np.bincount(row[ok] * width + first[ok], minlength=size) - np.bincount(
        row[ok] * width + last[ok] + 1, minlength=size
    )
    mask |= np.cumsum(diff.reshape(rows, width), axis=1)[:, :cols] > 0


def _trace_segments(start: np.ndarray, end: np.ndarray, mask: np.ndarray) -> None:
    """Set every cell the segments ``start``..``end`` (each (n, 2) [pixels]) pass through.

    Each segment is cut into the row bands it crosses; on each band it covers the cells
    between its x at the band's lower and upper edge.
    """
    rows, cols = mask.shape
    y_lo = np.minimum(start[:, 1], end[:, 1])
    y_hi = np.maximum(start[:, 1], end[:, 1])
    row_lo = np.clip(np.floor(y_lo), 0, rows - 1).astype(int)
    row_hi = np.clip(np.floor(y_hi), 0, rows - 1).astype(int)
    seg, rank = _expand(row_hi - row_lo + 1)
    row = row_lo[seg] + rank
    a, b = start[seg], end[seg]
    dy = b[:, 1] - a[:, 1]
    flat = dy == 0
    band_lo = np.maximum(row, y_lo[seg])
    band_hi = np.minimum(row + 1, y_hi[seg])
    slope = np.where(flat, 0.0, (b[:, 0] - a[:, 0]) / np.where(flat, 1.0, dy))
    x0 = np.where(flat, np.minimum(a[:, 0], b[:, 0]), a[:, 0] + (band_lo - a[:, 1]) * slope)
    x1 = np.where(flat, np.maximum(a[:, 0], b[:, 0]), a[:, 0] + (band_hi - a[:, 1]) * slope)
    first = np.floor(np.clip(np.minimum(x0, x1), -1, cols)).astype(int)
    last = np.floor(np.clip(np.maximum(x0, x1), -1, cols)).astype(int)
    _mark_spans(mask, row, first, last)


def _rasterize_pixels(p: np.ndarray, mask: np.ndarray) -> None:
    """Set the cells of ``mask`` covered by the triangles ``p`` (m, 3, 2) given in cells.

    Triangles thinner than a cell (smallest altitude below one cell) cannot hold a whole
    cell, so every cell they touch holds one of their corners or is crossed by one of
    their edges: their edges are traced (or, for one that fits in a single cell, that
    cell is set). The others are scanline-filled at cell centres.
    """
    if len(p) == 0:
        return
    rows, cols = mask.shape
    following = p[:, [1, 2, 0]]
    edge_length = np.hypot(*(following - p).transpose(2, 0, 1))  # (m, 3): edge k runs from corner k to k+1
    area2 = np.abs(_cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    thin = area2 < np.maximum(edge_length.max(axis=1), 1e-12)
    _fill_centres(p[~thin], mask)
    low = np.floor(p.min(axis=1)).astype(np.int64)
    one_cell = thin & np.all(low == np.floor(p.max(axis=1)).astype(np.int64), axis=1)
    cells = np.clip(low[one_cell], 0, [cols - 1, rows - 1])
    mask[cells[:, 1], cells[:, 0]] = True
    traced = thin & ~one_cell
    _trace_segments(p[traced].reshape(-1, 2), following[traced].reshape(-1, 2), mask)


def rasterize(triangles: np.ndarray, grid: Grid) -> np.ndarray:
    """Cells covered by the triangles (m, 3, 2) [m]: a (rows, columns) boolean mask.

    A cell is covered when its centre lies in a triangle; triangles thinner than a cell
    (slivers, tiny or edge-on faces) mark every cell they touch instead, so thin plates,
    rods and finely tessellated surfaces stay whole.
    """
    mask = np.zeros(grid.shape, dtype=bool)
    _rasterize_pixels((np.asarray(triangles, dtype=float).reshape(-1, 3, 2) - grid.origin) / grid.pixel, mask)
    return mask


def _trace_cells(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Boundary rings of the covered cells in cell-index coordinates (cell centres at integers):
    all points (N, 2) and the ring offsets (k + 1,); every ring is closed."""
    empty = (np.zeros((0, 2)), np.zeros(1, dtype=np.int64))
    if not mask.any():
        return empty
    generator = contourpy.contour_generator(z=mask.astype(np.float64), name="serial", fill_type="ChunkCombinedOffset")
    filled = generator.filled(0.5, 1.5)  # ChunkCombinedOffset: ([points or None], [offsets or None])
    points, offsets = filled[0], filled[1]
    if points[0] is None:
        return empty
    return np.asarray(points[0], dtype=float), np.asarray(offsets[0], dtype=np.int64)


def trace(mask: np.ndarray, grid: Grid) -> list[np.ndarray]:
    """Boundary rings of the covered cells, closed (first point repeated last), in (u, v) [m]."""
    points, offsets = _trace_cells(mask)
    xy = grid.origin + (points + 0.5) * grid.pixel
    return [xy[offsets[i] : offsets[i + 1]] for i in range(len(offsets) - 1)]


def _corners(ring: np.ndarray) -> np.ndarray:
    """A closed ring without the points that lie on a straight run (exact: traced points
    sit on half cells); still closed."""
    open_ring = ring[:-1]
    if len(open_ring) < 4:
        return ring
    turn = _cross(open_ring - np.roll(open_ring, 1, axis=0), np.roll(open_ring, -1, axis=0) - open_ring)
    kept = open_ring[turn != 0]
    return np.concatenate([kept, kept[:1]]) if len(kept) >= 3 else ring


def panel_silhouettes(panels: Sequence[tuple[np.ndarray, Grid]]) -> list[list[np.ndarray]]:
    """Silhouette rings of several sets of projected triangles, each (m, 3, 2) [m] on its own
    grid, rasterised and traced together in one atlas (the grids stacked in rows).

    Returns, per panel, closed rings in (u, v) [m] clipped to the bounds of its triangles:
    the raster errs outwards by up to a cell, the silhouette never leaves those bounds.
    """
    widths = [g.shape[1] for _, g in panels]
    heights = np.array([g.shape[0] for _, g in panels], dtype=np.int64)
    starts = np.cumsum(heights) - heights
    mask = np.zeros((int(heights.sum()), max(widths, default=0)), dtype=bool)
    cells = [
        (tri - grid.origin) / grid.pixel + np.array([0.0, float(start)])
        for (tri, grid), start in zip(panels, starts, strict=True)
    ]
    if cells:
        _rasterize_pixels(np.concatenate(cells), mask)
    points, offsets = _trace_cells(mask)
    out: list[list[np.ndarray]] = [[] for _ in panels]
    owner = np.searchsorted(starts, points[offsets[:-1], 1] + 0.5, side="right") - 1
    for ring, k in enumerate(owner):
        tri, grid = panels[k]
        local = _corners(points[offsets[ring] : offsets[ring + 1]]) - np.array([0.0, float(starts[k])])
        flat = tri.reshape(-1, 2)
        out[k].append(np.clip(grid.origin + (local + 0.5) * grid.pixel, flat.min(axis=0), flat.max(axis=0)))
    return out


def _ring_area(ring: np.ndarray) -> float:
    """Signed area of an open or closed ring (k, 2) [m^2]."""
    return float(0.5 * np.sum(_cross(ring, np.roll(ring, -1, axis=0))))


def convex_outline(points: np.ndarray) -> np.ndarray:
    """Convex hull of 2-D points (n, 2), counter-clockwise, open; the extreme pair for collinear points."""
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
    ring_of, _ = _expand(sizes)
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
        seg, rank = _expand(e - s - 1)
        idx = s[seg] + 1 + rank
        a, b, p = pts[s][seg], pts[e][seg], pts[idx]
        chord = b - a
        length = np.hypot(*chord.T)
        off_chord = np.abs(_cross(chord, p - a)) / np.where(length > 0, length, 1.0)
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
    link frame, faces (m, 3), every vertex used) in each of the :data:`VIEWS`, on grids of
    ``pixel`` [m] cells."""
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return {view: [] for view in VIEWS}
    panels = []
    for view in VIEWS:
        projected = project(vertices, view)
        panels.append((projected[faces], Grid.covering(projected.min(axis=0), projected.max(axis=0), pixel)))
    return dict(zip(VIEWS, panel_silhouettes(panels), strict=True))


def mesh_silhouette(vertices: np.ndarray, faces: np.ndarray, view: str, grid: Grid) -> list[np.ndarray]:
    """Closed boundary rings of the filled silhouette of a mesh (vertices (n, 3) [m] in the
    link frame, faces (m, 3)) seen in ``view``, at the resolution of ``grid``."""
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return []
    return panel_silhouettes([(project(vertices, view)[faces], grid)])[0]


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
