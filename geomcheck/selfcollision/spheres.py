"""Sphere covers of links: the broad phase of the collision matrix and the certificates.

Every collision shape is covered by a few spheres that together contain its whole volume
(the convex hull of the scene's support points grown by their pad, so the cover holds
whether a backend treats a mesh as a surface or as a convex solid): the hull is cut into
cells along its two longest principal axes, and each cell's part of the hull is enclosed in
a ball around the exact vertices of that part.
A link's *bound* is one sphere around all of its cover spheres. Two links whose covers do not
overlap cannot collide, and the gap between covers is a lower bound of their distance.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from geomcheck.collision.scene import CollisionScene

MAX_CELLS_PER_AXIS = 3  # cells along each of the two longest principal axes [count]
COVER_PADDING_M = 1e-6  # added to every cover radius against rounding [m]
ABSENT = -np.inf  # radius of padding slots: a gap to them is +inf
SINGLE_PRECISION_SLACK_M = 1e-5  # added to cover radii tested in float32 (rounding of ~1 m coordinates) [m]


@dataclass(frozen=True)
class LinkSpheres:
    """Sphere covers of links, in each link's frame.

    ``centres`` (n_links, k, 3) [m] and ``radii`` (n_links, k) [m], padded with
    :data:`ABSENT` radii; ``bound_centres`` (n_links, 3) and ``bound_radii`` (n_links,) [m]
    enclose each link's cover.
    """

    links: tuple[str, ...]
    centres: np.ndarray
    radii: np.ndarray
    bound_centres: np.ndarray
    bound_radii: np.ndarray

    def cover(self, row: int) -> tuple[np.ndarray, np.ndarray]:
        """The cover of the link in ``row``: centres (k, 3) and radii (k,) [m], padding dropped."""
        keep = np.isfinite(self.radii[row])
        return self.centres[row][keep], self.radii[row][keep]

    @functools.cached_property
    def width_class(self) -> np.ndarray:
        """Per link, the number of cover slots worth testing: its sphere count (covers are
        stored first, padding after), shape (n_links,)."""
        return np.maximum(np.isfinite(self.radii).sum(axis=1), 1)

    @functools.cached_property
    def bound_radii32(self) -> np.ndarray:
        """``bound_radii`` in single precision, grown by :data:`SINGLE_PRECISION_SLACK_M`."""
        return (self.bound_radii + SINGLE_PRECISION_SLACK_M).astype(np.float32)

    @functools.cached_property
    def radii32(self) -> np.ndarray:
        """``radii`` in single precision, grown by :data:`SINGLE_PRECISION_SLACK_M`."""
        return (self.radii + SINGLE_PRECISION_SLACK_M).astype(np.float32)


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


def hull_cover(points: np.ndarray) -> list[tuple[np.ndarray, float]]:
    """Balls covering the convex hull of ``points`` (n, 3) [m], as ``(centre, radius)``."""
    points = np.asarray(points, dtype=float)
    if len(points) < 4:
        return [_enclosing_ball(points)] if len(points) else []
    try:
        qhull = ConvexHull(points)
    except QhullError:  # flat or degenerate point sets
        return [_enclosing_ball(points)]
    mean = points[qhull.vertices].mean(axis=0)
    centred = points[qhull.vertices] - mean
    _, vectors = np.linalg.eigh(centred.T @ centred)
    frame = vectors[:, ::-1].T  # rows: principal axes, longest first
    local = (points - mean) @ frame.T
    lo, hi = local[qhull.vertices].min(axis=0), local[qhull.vertices].max(axis=0)
    extent = hi - lo
    cell = max(float(extent[2]), float(extent[0]) / MAX_CELLS_PER_AXIS, 1e-9)
    counts = [int(np.clip(round(float(extent[i]) / cell), 1, MAX_CELLS_PER_AXIS)) for i in (0, 1)]
    if counts == [1, 1]:
        return [_enclosing_ball(points[qhull.vertices])]
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
    return out or [_enclosing_ball(points[qhull.vertices])]


def link_spheres(scene: CollisionScene, links: Sequence[str] | None = None) -> LinkSpheres:
    """Covers of the collision shapes of ``links`` (default: every scene link), one row per
    link in that order, from the scene's support points (hull vertices, box corners, rim
    points) grown by their pad."""
    names = tuple(scene.links if links is None else links)
    covers = []
    for name in names:
        balls: list[tuple[np.ndarray, float]] = []
        for shape in scene.scene_shapes(name):
            balls.extend((c, r + shape.pad) for c, r in hull_cover(np.asarray(shape.points, dtype=float)))
        covers.append(balls)
    width = max((len(c) for c in covers), default=1) or 1
    n = len(names)
    centres = np.zeros((n, width, 3))
    radii = np.full((n, width), ABSENT)
    bound_centres = np.zeros((n, 3))
    bound_radii = np.zeros(n)
    for i, cover in enumerate(covers):
        if not cover:
            continue
        c = np.array([b[0] for b in cover])
        r = np.array([b[1] for b in cover])
        centres[i, : len(cover)] = c
        radii[i, : len(cover)] = r
        mid = 0.5 * ((c - r[:, None]).min(axis=0) + (c + r[:, None]).max(axis=0))
        bound_centres[i] = mid
        bound_radii[i] = float((np.linalg.norm(c - mid, axis=1) + r).max())
    return LinkSpheres(names, centres, radii, bound_centres, bound_radii)


def world_bounds(transforms: np.ndarray, spheres: LinkSpheres) -> np.ndarray:
    """Bounding sphere centres (b, n_links, 3) in the world [m] for link ``transforms`` (b, n_links, 4, 4)."""
    rot, shift = transforms[:, :, :3, :3], transforms[:, :, :3, 3]
    return np.asarray(np.matmul(rot, spheres.bound_centres[:, :, None])[..., 0] + shift)


def bound_gaps(bounds: np.ndarray, spheres: LinkSpheres, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Gap [m] between the bounding spheres of link pairs (``first``, ``second``: (P,) link
    rows) given their world centres ``bounds`` (b, n_links, 3): shape (b, P), single
    precision (radii grown by :data:`SINGLE_PRECISION_SLACK_M`); <= 0 overlap."""
    # link-major: gathering whole (b, 3) blocks per pair is much cheaper than along axis 1
    centres = np.ascontiguousarray(bounds.astype(np.float32).transpose(1, 0, 2))
    d = centres[first] - centres[second]
    radii = spheres.bound_radii32
    gaps = np.sqrt(np.einsum("pbi,pbi->pb", d, d)) - (radii[first] + radii[second])[:, None]
    return np.ascontiguousarray(gaps.T)


def _norms(d: np.ndarray) -> np.ndarray:
    return np.sqrt(np.einsum("...i,...i->...", d, d))


def world_covers(
    transforms: np.ndarray, bounds: np.ndarray, spheres: LinkSpheres, links: np.ndarray | None = None
) -> np.ndarray:
    """Cover sphere centres (b, n_links, k, 3) in the world [m], single precision, for link
    ``transforms`` (b, n_links, 4, 4) and world bounding-sphere centres ``bounds`` (b,
    n_links, 3); only for the link rows ``links`` when given (the others are left unset).
    Only the first ``width_class`` slots of a link are filled: a one-sphere cover is its
    bounding sphere, and the padding is never read."""
    n_samples, n_links = transforms.shape[:2]
    out = np.empty((n_samples, n_links, spheres.centres.shape[1], 3), dtype=np.float32)
    wanted = np.zeros(n_links, dtype=bool)
    wanted[np.arange(n_links) if links is None else links] = True
    widths = spheres.width_class
    single = wanted & (widths == 1)
    out[:, single, 0] = bounds[:, single]
    for k in np.unique(widths[wanted & (widths > 1)]).tolist():
        rows = np.nonzero(wanted & (widths == k))[0]
        placed_links = transforms[:, rows]
        rot, shift = placed_links[..., :3, :3], placed_links[..., :3, 3]
        placed = np.matmul(rot, np.swapaxes(spheres.centres[rows, :k], 1, 2)).swapaxes(2, 3) + shift[:, :, None, :]
        out[:, rows, :k] = placed
    return out


def cover_gaps(
    covers: np.ndarray,
    bounds: np.ndarray,
    spheres: LinkSpheres,
    samples: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
) -> np.ndarray:
    """Gap [m] between the covers of links ``first[i]`` and ``second[i]`` in configuration
    ``samples[i]`` (all (M,)), a lower bound of the links' distance; <= 0 when some cover
    spheres overlap. ``covers`` (b, n_links, k, 3) and ``bounds`` (b, n_links, 3) are the
    world centres of the cover and bounding spheres (:func:`world_covers`, :func:`world_bounds`).
    Each cover is first tested against the other
    link's bounding sphere (2 k tests), the k x k sphere pairs only where that does not
    separate them; rows are grouped by cover size so that small covers skip the padding,
    and two one-sphere covers are their bounding spheres."""
    bound_r = spheres.bound_radii + SINGLE_PRECISION_SLACK_M
    d = bounds[samples, first] - bounds[samples, second]
    out = _norms(d) - spheres.bound_radii[first] - spheres.bound_radii[second]
    bounds32 = bounds.astype(np.float32)
    wa, wb = spheres.width_class[first], spheres.width_class[second]
    for ka, kb in sorted(set(zip(wa.tolist(), wb.tolist(), strict=True))):
        if ka == 1 and kb == 1:
            continue
        rows = np.nonzero((wa == ka) & (wb == kb))[0]
        s, a, b = samples[rows], first[rows], second[rows]
        ra, rb = spheres.radii32[a, :ka], spheres.radii32[b, :kb]
        ca, cb = covers[s, a, :ka], covers[s, b, :kb]
        to_b = (_norms(ca - bounds32[s, b][:, None, :]) - ra).min(axis=1) - bound_r[b]
        to_a = (_norms(cb - bounds32[s, a][:, None, :]) - rb).min(axis=1) - bound_r[a]
        gap = np.maximum(to_b, to_a)
        need = np.nonzero(gap <= 0)[0]
        for lo in range(0, len(need), 65536):  # bounded memory: rows x ka x kb distances
            sub = need[lo : lo + 65536]
            pair_gaps = _norms(ca[sub][:, :, None, :] - cb[sub][:, None, :, :])
            pair_gaps = pair_gaps - ra[sub][:, :, None] - rb[sub][:, None, :]
            gap[sub] = pair_gaps.reshape(len(sub), -1).min(axis=1)
        out[rows] = gap
    return out
