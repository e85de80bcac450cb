"""Rasterising triangles onto a grid and tracing the covered region's boundary.

The union of many overlapping triangles (a mesh seen along an axis) is cheap and robust
on a raster: every triangle marks cells, vectorised over triangles and rows, and the
boundary of the marked cells is traced with marching squares (contourpy). Corners are
passed as separate (m, 2) arrays so no numpy reduction runs along a length-3 axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import contourpy
import numpy as np


@dataclass(frozen=True)
class Grid:
    """A raster over a plane: cell (row j, column i) spans
    ``origin + (i, j) * pixel`` to ``origin + (i + 1, j + 1) * pixel`` [m]."""

    origin: np.ndarray  # (2,) lower corner (u, v) [m]
    pixel: float  # cell edge [m]
    shape: tuple[int, int]  # (rows along v, columns along u)
    lower: np.ndarray | None = None  # (2,) the box the grid was made to cover [m], when known
    upper: np.ndarray | None = None

    @classmethod
    def covering(cls, lower: np.ndarray, upper: np.ndarray, pixel: float, pad: int = 2) -> Grid:
        """The grid over the box ``lower``..``upper`` (each (2,) [m]) with ``pad`` empty cells around it.

        The box's sides fall on cell centres, not cell edges, so that faces seen edge-on at
        the extremes mark the same number of cells on every side.
        """
        lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
        cells = np.ceil(np.maximum(upper - lower, 0.0) / pixel + 1.0).astype(int) + 2 * pad
        origin = lower - (pad + 0.5) * pixel
        return cls(origin, float(pixel), (int(cells[1]), int(cells[0])), lower, upper)

    def to_cells(self, points: np.ndarray) -> np.ndarray:
        """Points (n, 2) [m] in cell units (cell (i, j) spans i..i+1, j..j+1)."""
        return (np.asarray(points, dtype=float) - self.origin) / self.pixel

    def from_cells(self, centres: np.ndarray) -> np.ndarray:
        """Cell-index coordinates (n, 2), cell centres at integers, back to (u, v) [m]."""
        return self.origin + (np.asarray(centres, dtype=float) + 0.5) * self.pixel


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z of the cross product of 2-D vectors (..., 2)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def expand(counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For items with ``counts`` (m,): the item of each of ``counts.sum()`` slots and its rank in the item."""
    owner = np.repeat(np.arange(len(counts)), counts)
    first = np.cumsum(counts) - counts
    return owner, np.arange(int(counts.sum())) - first[owner]


def _mark_spans(mask: np.ndarray, row: np.ndarray, first: np.ndarray, last: np.ndarray) -> None:
    """Set cells ``first..last`` (inclusive, clipped) of each ``row`` through a per-row difference array."""
    rows, cols = mask.shape
    first = np.clip(first, 0, cols)
    last = np.clip(last, -1, cols - 1)
    ok = first <= last
    width = cols + 1
    size = rows * width
    starts = np.bincount(row[ok] * width + first[ok], minlength=size)
    stops = np.bincount(row[ok] * width + last[ok] + 1, minlength=size)
    mask |= np.cumsum((starts - stops).reshape(rows, width), axis=1)[:, :cols] > 0


def _mark_points(points: np.ndarray, mask: np.ndarray) -> None:
    """Set the cells holding ``points`` (n, 2) [cells]."""
    rows, cols = mask.shape
    cells = np.floor(points).astype(np.int64)
    np.clip(cells[:, 0], 0, cols - 1, out=cells[:, 0])
    np.clip(cells[:, 1], 0, rows - 1, out=cells[:, 1])
    mask[cells[:, 1], cells[:, 0]] = True


def _sorted_by_y(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(a, b)`` per row swapped so that the first has the smaller y."""
    swap = (a[:, 1] > b[:, 1])[:, None]
    return np.where(swap, b, a), np.where(swap, a, b)


def _fill_centres(a: np.ndarray, b: np.ndarray, c: np.ndarray, mask: np.ndarray) -> None:
    """Set the cells whose centre lies in a triangle (corners ``a``, ``b``, ``c``, each (m, 2) [cells]).

    Scanline fill: each triangle, its corners sorted bottom to top, is cut by the rows
    whose centre line it spans; on each row the long edge (bottom to top) bounds one
    side and the lower or upper short edge the other.
    """
    a, b = _sorted_by_y(a, b)
    b, c = _sorted_by_y(b, c)
    a, b = _sorted_by_y(a, b)
    (x0, y0), (x1, y1), (x2, y2) = a.T, b.T, c.T
    rows = mask.shape[0]
    row_lo = np.clip(np.ceil(y0 - 0.5), 0, rows).astype(np.int64)
    row_hi = np.clip(np.floor(y2 - 0.5), -1, rows - 1).astype(np.int64)
    tri, rank = expand(np.maximum(row_hi - row_lo + 1, 0))
    if len(tri) == 0:
        return
    row = row_lo[tri] + rank
    y = row + 0.5

    def slope(xa: np.ndarray, ya: np.ndarray, xb: np.ndarray, yb: np.ndarray) -> np.ndarray:
        dy = yb - ya
        return np.divide(xb - xa, dy, out=np.zeros_like(dy), where=dy > 0)

    long_x = x0[tri] + (y - y0[tri]) * slope(x0, y0, x2, y2)[tri]
    short_x = np.where(
        y < y1[tri],
        x0[tri] + (y - y0[tri]) * slope(x0, y0, x1, y1)[tri],
        x1[tri] + (y - y1[tri]) * slope(x1, y1, x2, y2)[tri],
    )
    first = np.ceil(np.minimum(long_x, short_x) - 0.5).astype(np.int64)
    last = np.floor(np.maximum(long_x, short_x) - 0.5).astype(np.int64)
    _mark_spans(mask, row, first, last)


def _trace_segments(start: np.ndarray, end: np.ndarray, mask: np.ndarray) -> None:
    """Set every cell the segments ``start``..``end`` (each (n, 2) [cells]) pass through.

    Each segment is cut into the row bands it crosses; on each band it covers the cells
    between its x at the band's lower and upper edge.
    """
    rows, cols = mask.shape
    start, end = _sorted_by_y(start, end)
    row_lo = np.clip(np.floor(start[:, 1]), 0, rows - 1).astype(np.int64)
    row_hi = np.clip(np.floor(end[:, 1]), 0, rows - 1).astype(np.int64)
    seg, rank = expand(row_hi - row_lo + 1)
    row = row_lo[seg] + rank
    (xa, ya), (xb, yb) = start[seg].T, end[seg].T
    dy = yb - ya
    slope = np.divide(xb - xa, dy, out=np.zeros_like(dy), where=dy > 0)
    x0 = xa + (np.maximum(row, ya) - ya) * slope
    x1 = np.where(dy > 0, xa + (np.minimum(row + 1, yb) - ya) * slope, xb)
    first = np.floor(np.clip(np.minimum(x0, x1), -1, cols)).astype(np.int64)
    last = np.floor(np.clip(np.maximum(x0, x1), -1, cols)).astype(np.int64)
    _mark_spans(mask, row, first, last)


def rasterize_cells(a: np.ndarray, b: np.ndarray, c: np.ndarray, mask: np.ndarray) -> None:
    """Set the cells of ``mask`` covered by the triangles with corners ``a``, ``b``, ``c``
    (each (m, 2), in cells).

    Triangles thinner than a cell (smallest altitude below one cell) cannot hold a whole
    cell, so every cell they touch holds one of their corners or is crossed by one of
    their edges: their edges are traced. The others are scanline-filled at cell centres.
    """
    if len(a) == 0:
        return
    longest = np.maximum(np.maximum(np.hypot(*(b - a).T), np.hypot(*(c - b).T)), np.hypot(*(a - c).T))
    thin = np.abs(cross(b - a, c - a)) < np.maximum(longest, 1e-12)
    wide = ~thin
    _fill_centres(a[wide], b[wide], c[wide], mask)
    # a triangle no longer than a cell touches at most a 2 x 2 block: its corners and edge
    # midpoints find those cells (finely tessellated surfaces are mostly such triangles)
    small = thin & (longest <= 1.0)
    sa, sb, sc = a[small], b[small], c[small]
    _mark_points(np.concatenate([sa, sb, sc, (sa + sb) / 2, (sb + sc) / 2, (sc + sa) / 2]), mask)
    t = thin & ~small
    ta, tb, tc = a[t], b[t], c[t]
    _trace_segments(np.concatenate([ta, tb, tc]), np.concatenate([tb, tc, ta]), mask)


def rasterize_faces(cells: np.ndarray, faces: np.ndarray, mask: np.ndarray, block: int) -> None:
    """:func:`rasterize_cells` for the triangles ``faces`` (m, 3) of the vertices ``cells``
    (n, 2, in cells), ``block`` triangles at a time (memory bounded for any m).

    The same cells are set, with less work on finely tessellated meshes: a triangle no
    longer than a cell whose corners share one cell marks just that cell, and every
    vertex's cell is marked once rather than once per triangle that uses it."""
    corner_cells = np.floor(cells).astype(np.int64)
    small_vertices = np.zeros(len(cells), dtype=bool)
    for first in range(0, len(faces), block):
        f = faces[first : first + block]
        a, b, c = cells[f[:, 0]], cells[f[:, 1]], cells[f[:, 2]]
        longest = np.maximum(np.maximum(np.hypot(*(b - a).T), np.hypot(*(c - b).T)), np.hypot(*(a - c).T))
        thin = np.abs(cross(b - a, c - a)) < np.maximum(longest, 1e-12)
        wide = ~thin
        _fill_centres(a[wide], b[wide], c[wide], mask)
        small = thin & (longest <= 1.0)
        small_vertices[f[small].reshape(-1)] = True
        ca, cb, cc = corner_cells[f[:, 0]], corner_cells[f[:, 1]], corner_cells[f[:, 2]]
        one_cell = np.all((ca == cb) & (cb == cc), axis=1)
        spread = small & ~one_cell
        sa, sb, sc = a[spread], b[spread], c[spread]
        _mark_points(np.concatenate([(sa + sb) / 2, (sb + sc) / 2, (sc + sa) / 2]), mask)
        # the edges of the other thin triangles are traced, each once (neighbours share
        # them, and a segment marks the same cells in either direction)
        start, end = _unique_edges(f[thin & ~small], len(cells))
        _trace_segments(cells[start], cells[end], mask)
    _mark_points(cells[small_vertices], mask)


def _unique_edges(faces: np.ndarray, vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """The distinct edges of ``faces`` (m, 3) over ``vertices`` vertices, as the vertex indices
    (k,) of their ends, smaller first."""
    ends = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    keys = np.unique(ends[:, 0].astype(np.int64) * vertices + ends[:, 1])
    return keys // vertices, keys % vertices


def rasterize(triangles: np.ndarray, grid: Grid) -> np.ndarray:
    """Cells covered by the triangles (m, 3, 2) [m]: a (rows, columns) boolean mask.

    A cell is covered when its centre lies in a triangle; triangles thinner than a cell
    (slivers, tiny or edge-on faces) mark every cell they touch instead, so thin plates,
    rods and finely tessellated surfaces stay whole.
    """
    mask = np.zeros(grid.shape, dtype=bool)
    cells = grid.to_cells(np.asarray(triangles, dtype=float).reshape(-1, 2)).reshape(-1, 3, 2)
    rasterize_cells(cells[:, 0], cells[:, 1], cells[:, 2], mask)
    return mask


def trace_cells(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
    points, offsets = trace_cells(mask)
    xy = grid.from_cells(points)
    return [xy[offsets[i] : offsets[i + 1]] for i in range(len(offsets) - 1)]
