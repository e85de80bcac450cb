"""Smallest enclosing shapes of point sets: balls (circles, spheres) and oriented boxes.

Input points are (n, d) arrays [m]; callers pass convex hull vertices, so n stays small.
"""

from __future__ import annotations

import numpy as np

from geomcheck.geometry.surface import ConvexRegion, principal_axes, row_blocks

BALL_RELATIVE_EPS = 1e-10  # a point this much (relative) beyond the radius is outside [1]
BOX_ANGLE_STEPS = 30  # in-plane angles tried per box axis, over a quarter turn [count]
BOX_REFINE_STEPS = 15  # finer angles around the best coarse one [count]
BOX_FACET_AXES = 12  # largest hull facets whose normals are tried as box axes [count]
BOX_REFINED_AXES = 3  # best coarse axes refined with finer angles [count]
BOX_TIE_RELATIVE = 1e-6  # boxes whose volumes differ by less than this share are a tie [ratio]
PARALLEL_SINE = 1e-9  # an axis within this sine of a plane's normal has no direction in the plane [1]
SHUFFLE_SEED = 0  # fixed order for the randomised incremental ball algorithm
CORE_GROWTH = 8  # points added to the core set per round [count]
CORE_DIRECTIONS = np.array(
    [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, -1, 0], [1, 0, 1], [1, 0, -1], [0, 1, 1], [0, 1, -1],
     [1, 1, 1], [1, 1, -1], [1, -1, 1], [-1, 1, 1]],
    dtype=float,
)  # fmt: skip


def _sub(a: list[float], b: list[float]) -> list[float]:
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def _dot(a: list[float], b: list[float]) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a: list[float], b: list[float]) -> list[float]:
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _ball_through(boundary: list[list[float]]) -> tuple[list[float], float] | None:
    """Smallest ball with every point of ``boundary`` (1 to 4 points, as 3-D lists) on its
    surface; ``None`` when they are degenerate (collinear triple, coplanar quadruple).
    Closed forms in plain floats: these tiny solves dominate Welzl's algorithm otherwise."""
    p0 = boundary[0]
    if len(boundary) == 1:
        return list(p0), 0.0
    if len(boundary) == 2:
        c = [(p0[i] + boundary[1][i]) / 2.0 for i in range(3)]
        return c, _dot(_sub(boundary[1], c), _sub(boundary[1], c)) ** 0.5
    a, b = _sub(boundary[1], p0), _sub(boundary[2], p0)
    axb = _cross(a, b)
    n2 = _dot(axb, axb)
    scale = _dot(a, a) * _dot(b, b)
    if n2 <= 1e-24 * scale:
        return None
    if len(boundary) == 3:
        aa, bb = _dot(a, a), _dot(b, b)
        w = _cross([aa * b[i] - bb * a[i] for i in range(3)], axb)
        off = [w[i] / (2.0 * n2) for i in range(3)]
        return [p0[i] + off[i] for i in range(3)], _dot(off, off) ** 0.5
    d = _sub(boundary[3], p0)
    det = _dot(d, axb)
    if abs(det) <= 1e-12 * scale**0.5 * _dot(d, d) ** 0.5:
        return None
    aa, bb, dd = _dot(a, a), _dot(b, b), _dot(d, d)
    bxd, dxa = _cross(b, d), _cross(d, a)
    off = [(aa * bxd[i] + bb * dxa[i] + dd * axb[i]) / (2.0 * det) for i in range(3)]
    return [p0[i] + off[i] for i in range(3)], _dot(off, off) ** 0.5


def _enclose(
    points: np.ndarray, listed: list[list[float]], limit: int, fixed: list[int], eps: float
) -> tuple[np.ndarray, float]:
    """Smallest ball holding ``points[:limit]`` (n, 3) with the points ``fixed`` (indices) on
    its boundary (Welzl, move-to-front form; the scan for the next outside point is vectorised)."""
    if fixed:
        ball = _ball_through([listed[i] for i in fixed])
        if ball is None:  # degenerate support: drop the oldest fixed point
            return _enclose(points, listed, limit, fixed[1:], eps)
        centre, radius = np.array(ball[0]), ball[1]
        start = 0
    else:
        centre, radius = points[0].copy(), 0.0
        start = 1
    if len(fixed) == 4:
        return centre, radius
    i = start
    while i < limit:
        dist = np.sqrt(((points[i:limit] - centre) ** 2).sum(axis=1))
        outside = np.flatnonzero(dist > radius + eps)
        if len(outside) == 0:
            break
        i += int(outside[0])
        centre, radius = _enclose(points, listed, i, [*fixed, i], eps)
        i += 1
    return centre, radius


def _welzl(pts3: np.ndarray, scale: float) -> tuple[np.ndarray, float]:
    order = np.random.default_rng(SHUFFLE_SEED).permutation(len(pts3))
    pts3 = pts3[order]
    return _enclose(pts3, pts3.tolist(), len(pts3), [], BALL_RELATIVE_EPS * scale)


def minimal_ball(points: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre (d,) and radius [m] of the smallest ball (d = 2: circle, d = 3: sphere)
    enclosing ``points`` (n, d).

    Welzl's algorithm on a core set: the extreme points along a few directions, grown by
    the points left outside until none is (the ball of a subset that holds every point is
    the ball of the whole set)."""
    pts = np.asarray(points, dtype=float)
    dim = pts.shape[1]
    if len(pts) == 0:
        return np.zeros(dim), 0.0
    pts3 = np.zeros((len(pts), 3))
    pts3[:, :dim] = pts
    scale = float(np.ptp(pts3, axis=0).max()) or 1.0
    proj = pts3 @ CORE_DIRECTIONS.T
    core = np.unique(np.concatenate((np.argmin(proj, axis=0), np.argmax(proj, axis=0))))
    while True:
        centre, radius = _welzl(pts3[core], scale)
        dist = np.sqrt(((pts3 - centre) ** 2).sum(axis=1))
        outside = np.flatnonzero(dist > radius + BALL_RELATIVE_EPS * scale)
        if len(outside) == 0:
            break
        worst = outside[np.argsort(-dist[outside], kind="stable")[:CORE_GROWTH]]
        core = np.unique(np.concatenate((core, worst)))
    centre = centre[:dim]
    # guard against round-off: the radius really encloses every point
    return centre, float(max(radius, np.sqrt(((pts - centre) ** 2).sum(axis=1)).max()))


def _unit_rows(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


def _plane_bases(axes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the plane normal to each row of ``axes`` (a, 3)."""
    helper = np.where(np.abs(axes[:, :1]) < 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    u = _unit_rows(np.cross(axes, helper))
    v = np.cross(axes, u)
    return u, v


def _tied(volumes: np.ndarray) -> np.ndarray:
    """``volumes`` [m^3] with those within :data:`BOX_TIE_RELATIVE` of the least made equal to
    it: boxes that close are a tie, decided by candidate order, not by a CPU's last digits."""
    least = float(np.min(volumes)) if volumes.size else 0.0
    return np.where(volumes <= least * (1.0 + BOX_TIE_RELATIVE), least, volumes)


def _first_least(volumes: np.ndarray) -> int:
    """Flat index of the first of the least ``volumes`` (ties: :func:`_tied`)."""
    return int(np.argmin(_tied(volumes)))


def extents_along(points: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Width (k,) [m] of ``points`` (n, 3) along each unit row of ``directions`` (k, 3),
    projected a block of points at a time (memory bounded for any n and k)."""
    lo, hi = np.full(len(directions), np.inf), np.full(len(directions), -np.inf)
    for block in row_blocks(len(points), len(directions)):
        projected = points[block] @ directions.T
        lo = np.minimum(lo, projected.min(axis=0))
        hi = np.maximum(hi, projected.max(axis=0))
    return hi - lo


def _best_in_plane(points: np.ndarray, axes: np.ndarray, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each axis (a, 3) and in-plane angle (a, m): the box volume, shape (a, m), and the
    frames (a, m, 3, 3) whose first column is the axis."""
    u, v = _plane_bases(axes)
    c, s = np.cos(angles)[..., None], np.sin(angles)[..., None]
    d1 = c * u[:, None] + s * v[:, None]  # (a, m, 3)
    d2 = -s * u[:, None] + c * v[:, None]
    a, m = angles.shape
    spans = extents_along(points, np.concatenate((d1, d2)).reshape(-1, 3)).reshape(2, a, m)
    vol = extents_along(points, axes)[:, None] * spans[0] * spans[1]
    frames = np.stack((np.broadcast_to(axes[:, None], d1.shape), d1, d2), axis=-1)
    return vol, frames


def minimum_box(points: np.ndarray, hull: ConvexRegion | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A tight oriented bounding box of ``points`` (n, 3): ``(rotation (3, 3), centre (3,),
    size (3,))`` [m], the rotation's columns being the box axes.

    Tries as first axis the link axes, the principal axes and the normals of the largest
    hull facets, and for each a quarter turn of in-plane angles, refined around the best:
    within a fraction of a degree of the smallest box.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    candidates = [np.eye(3), principal_axes(pts).T]
    if hull is not None and len(hull.equations) > 0:
        # a box face lies on a hull facet in most tight boxes; big (merged coplanar) facets first
        normals = np.round(hull.equations[:, :3], 6)
        unique, inverse = np.unique(normals, axis=0, return_inverse=True)
        area = np.bincount(inverse.ravel(), weights=hull.facet_areas, minlength=len(unique))
        # areas to a relative 1e-9: equal facets of a symmetric part keep their order on every CPU
        share = np.round(area / max(float(area.max()), np.finfo(float).tiny), 9)
        order = np.lexsort((np.arange(len(unique)), -share))
        candidates.append(unique[order[:BOX_FACET_AXES]])
    axes = _unit_rows(np.concatenate(candidates))
    grid = np.linspace(0.0, 0.5 * np.pi, BOX_ANGLE_STEPS, endpoint=False)
    # the other candidate axes seen in each plane: exact angles when two box faces are facets
    u, v = _plane_bases(axes)
    along_u, along_v = (axes @ u.T).T, (axes @ v.T).T  # (a, a): axis j seen in the plane of axis i
    # an axis along the plane's normal (axis i itself, or its opposite) has no angle in it: the
    # arctangent of two noise values would be a different angle on every CPU
    lying = np.hypot(along_u, along_v) > PARALLEL_SINE
    seen = np.where(lying, np.mod(np.arctan2(along_v, along_u), 0.5 * np.pi), 0.0)
    coarse = np.concatenate((np.broadcast_to(grid, (len(axes), len(grid))), seen), axis=1)
    vol, _ = _best_in_plane(pts, axes, coarse)
    step = grid[1] - grid[0]
    # refine the few most promising axes only
    top = np.argsort(_tied(vol.min(axis=1)), kind="stable")[:BOX_REFINED_AXES]
    best = coarse[top, [_first_least(row) for row in vol[top]]]
    fine = np.concatenate((best[:, None], best[:, None] + np.linspace(-step, step, BOX_REFINE_STEPS)[None]), axis=1)
    vol_f, frames_f = _best_in_plane(pts, axes[top], fine)
    a, m = np.unravel_index(_first_least(vol_f), vol_f.shape)
    rotation = frames_f[a, m].copy()
    if np.linalg.det(rotation) < 0:
        rotation[:, 2] = -rotation[:, 2]
    local = pts @ rotation
    lo, hi = local.min(axis=0), local.max(axis=0)
    return rotation, rotation @ (0.5 * (lo + hi)), hi - lo
