"""Triangle surfaces as numpy arrays: merging, area-weighted sampling, convex hulls.

Every array is in one frame (the link frame unless stated), lengths [m].
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

if TYPE_CHECKING:
    from scipy.spatial import ConvexHull

from geomcheck.geometry.frames import from_frame
from geomcheck.load.stl import first_indices
from geomcheck.thresholds import AnalysisThresholds

ANALYSIS = AnalysisThresholds()

FLAT_RATIO = 1e-9  # smallest / largest principal spread below this: the points are flat [1]
VERTEX_DIGITS = 9  # vertices equal to this many decimals [m] are one vertex


def unique_rows(points: np.ndarray) -> np.ndarray:
    """``points`` (n, 3) without repeats (equal to ``VERTEX_DIGITS`` decimals), in order of first appearance."""
    if len(points) == 0:
        return points
    keys = np.round(points * 10.0**VERTEX_DIGITS).astype(np.int64)
    return points[first_indices(keys)]


def row_blocks(rows: int, columns: int, analysis: AnalysisThresholds = ANALYSIS) -> Iterator[slice]:
    """Slices of ``rows`` rows such that a block of (rows, ``columns``) stays within
    ``analysis.chunk_elements``: the memory of a points x planes product is bounded."""
    step = max(1, analysis.chunk_elements // max(columns, 1))
    for start in range(0, rows, step):
        yield slice(start, min(rows, start + step))


class TriangleMesh(Protocol):
    """Anything with ``vertices`` (n, 3) [m] and ``faces`` (m, 3): a loaded mesh, a trimesh
    object, a tessellated primitive."""

    @property
    def vertices(self) -> np.ndarray: ...

    @property
    def faces(self) -> np.ndarray: ...


@dataclass(frozen=True)
class Surface:
    """A triangle surface: ``vertices`` (n, 3) [m] and ``faces`` (m, 3) indices into them."""

    vertices: np.ndarray
    faces: np.ndarray

    @classmethod
    def from_mesh(cls, mesh: TriangleMesh, rotation: np.ndarray, translation: np.ndarray) -> Surface:
        """``mesh`` moved into the parent frame of ``rotation`` (3, 3) / ``translation`` (3,)."""
        vertices = from_frame(np.asarray(mesh.vertices, dtype=float), rotation, translation)
        return cls(vertices, np.asarray(mesh.faces, dtype=np.int64))

    def moved(self, rotation: np.ndarray, translation: np.ndarray) -> Surface:
        """The same surface after the rigid motion ``p -> R p + t``."""
        return Surface(from_frame(self.vertices, rotation, translation), self.faces)

    @classmethod
    def merge(cls, surfaces: Iterable[Surface]) -> Surface:
        """One surface holding all of ``surfaces``."""
        vertices, faces, offset = [], [], 0
        for s in surfaces:
            vertices.append(s.vertices)
            faces.append(s.faces + offset)
            offset += len(s.vertices)
        if not vertices:
            return cls(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
        return cls(np.concatenate(vertices), np.concatenate(faces))

    def triangles(self, faces: np.ndarray | slice = slice(None)) -> np.ndarray:
        """Corner coordinates of the ``faces`` (all by default), shape (m, 3, 3) [m]."""
        return self.vertices[self.faces[faces]]

    @functools.cached_property
    def _areas(self) -> np.ndarray:
        areas = np.empty(len(self.faces))
        # a block of triangles at a time: the corner array of a big mesh is never whole in memory
        for block in row_blocks(len(self.faces), 9):
            t = self.triangles(block)
            areas[block] = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
        return areas

    def face_areas(self) -> np.ndarray:
        """Area of each face, shape (m,) [m^2]."""
        return self._areas

    @property
    def area(self) -> float:
        """Total area [m^2]."""
        return float(self._areas.sum()) if len(self.faces) else 0.0

    def unique_vertices(self) -> np.ndarray:
        """The vertices used by faces, duplicates (STL repeats corners) removed, in first-use
        order, shape (k, 3) [m]."""
        if not len(self.faces):
            return unique_rows(self.vertices)
        used = np.zeros(len(self.vertices), dtype=bool)
        used[self.faces.reshape(-1)] = True
        return unique_rows(self.vertices[used])

    def sample(self, count: int, rng: np.random.Generator) -> np.ndarray:
        """``count`` points uniformly distributed over the surface by area, shape (count, 3) [m]."""
        areas = self.face_areas()
        total = float(areas.sum())
        if count <= 0 or total <= 0.0:
            return np.zeros((0, 3))
        cumulative = np.cumsum(areas)
        faces = np.searchsorted(cumulative, rng.random(count) * total, side="right")
        faces = np.minimum(faces, len(areas) - 1)
        u, v = rng.random(count), rng.random(count)
        flip = u + v > 1.0
        u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
        t = self.triangles(faces)
        return t[:, 0] + u[:, None] * (t[:, 1] - t[:, 0]) + v[:, None] * (t[:, 2] - t[:, 0])


@dataclass(frozen=True)
class ConvexRegion:
    """The convex hull of a point set: hull ``vertices`` (k, 3), outward facet ``equations``
    (f, 4) with ``n . p + d <= 0`` inside, ``facet_areas`` (f,) [m^2] and ``volume`` [m^3].

    ``tolerance`` [m] is 0 for an exact hull. A hull of more points than
    ``AnalysisThresholds.hull_exact_points`` is approximated (its vertices are input points,
    so it lies inside the exact hull): no input point lies further than ``tolerance`` above
    any of its facets, and its size stays bounded whatever the number of points."""

    vertices: np.ndarray
    equations: np.ndarray
    facet_areas: np.ndarray
    volume: float
    tolerance: float = 0.0

    @classmethod
    def of(cls, points: np.ndarray, analysis: AnalysisThresholds = ANALYSIS) -> ConvexRegion | None:
        """Hull of ``points`` (n, 3), or ``None`` when they span no volume (fewer than 4, flat)."""
        found = bounded_hull(points, analysis)
        if found is None:
            return None
        pts, hull, tolerance = found
        t = pts[hull.simplices]
        areas = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
        return cls(pts[hull.vertices], hull.equations, areas, float(hull.volume), tolerance)

    def moved(self, rotation: np.ndarray, translation: np.ndarray) -> ConvexRegion:
        """The same hull after the rigid motion ``p -> R p + t`` (``rotation`` (3, 3), ``translation`` (3,))."""
        normals = self.equations[:, :3] @ rotation.T
        offsets = self.equations[:, 3] - normals @ translation
        equations = np.column_stack((normals, offsets))
        moved = from_frame(self.vertices, rotation, translation)
        return ConvexRegion(moved, equations, self.facet_areas, self.volume, self.tolerance)

    def signed_distance(self, points: np.ndarray) -> np.ndarray:
        """Signed distance (n,) [m] to the hull: exact inside (negative), a lower bound of the
        true distance outside (the distance to the farthest facet plane). Evaluated in blocks
        of points, so memory stays bounded however many points and facets there are; a hull of
        many facets (a CAD part's fillets) skips, for each point, the groups of facets whose
        planes cannot be the farthest (:class:`FacetGroups`): the result is the same."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        groups = self.facet_groups
        if groups is not None and len(pts) >= PRUNE_MIN_POINTS:
            return groups.farthest_plane(pts, self.equations)
        return farthest_plane(pts, self.equations)

    @functools.cached_property
    def facet_groups(self) -> FacetGroups | None:
        """The facets grouped by normal, for a hull of at least ``PRUNE_MIN_FACETS`` facets."""
        if len(self.equations) < PRUNE_MIN_FACETS or not len(self.vertices):
            return None
        return FacetGroups.of(self.equations, np.asarray(self.vertices, dtype=float).mean(axis=0))


PRUNE_MIN_FACETS = 1024  # a hull of fewer facets is evaluated whole [count]
PRUNE_MIN_POINTS = 64  # fewer points are evaluated against every facet [count]
GROUP_DIRECTIONS = 128  # facets are grouped by the nearest of this many directions [count]


def farthest_plane(points: np.ndarray, equations: np.ndarray) -> np.ndarray:
    """The largest ``n . p + d`` over the planes ``equations`` (f, 4) for each point (n, 3),
    in blocks of points."""
    out = np.empty(len(points))
    normals, offsets = equations[:, :3].T, equations[:, 3]
    for block in row_blocks(len(points), len(offsets)):
        out[block] = (points[block] @ normals + offsets).max(axis=1)
    return out


def sphere_directions(count: int) -> np.ndarray:
    """``count`` unit vectors (count, 3) spread evenly over the sphere (a Fibonacci lattice)."""
    i = np.arange(count) + 0.5
    z = 1.0 - 2.0 * i / count
    azimuth = np.pi * (1.0 + 5.0**0.5) * i
    r = np.sqrt(1.0 - z * z)
    return np.column_stack((r * np.cos(azimuth), r * np.sin(azimuth), z))


@dataclass(frozen=True)
class FacetGroups:
    """A hull's facets grouped by the nearest of ``GROUP_DIRECTIONS`` directions, each group
    with its direction ``axes`` (g, 3), the farthest its normals turn from it ``spread`` (g,)
    and the least distance of its planes from the hull's ``centre`` ``nearest`` (g,) [m].

    For a point ``p = centre + q``, a facet of the group has ``n . p + d = n . q - h <=
    axis . q + spread |q| - nearest``: a group whose bound is below the largest value found so
    far holds no farther plane, and is not evaluated for that point."""

    centre: np.ndarray
    axes: np.ndarray
    spread: np.ndarray
    nearest: np.ndarray
    members: tuple[np.ndarray, ...]
    seeds: np.ndarray  # one facet per group, its normal nearest the group's direction

    @classmethod
    def of(cls, equations: np.ndarray, centre: np.ndarray) -> FacetGroups:
        normals = equations[:, :3]
        heights = -(equations[:, 3] + normals @ centre)
        directions = sphere_directions(GROUP_DIRECTIONS)
        nearest_direction = np.argmax(normals @ directions.T, axis=1)
        axes, spread, nearest, members, seeds = [], [], [], [], []
        for g in np.unique(nearest_direction):
            idx = np.flatnonzero(nearest_direction == g)
            axis = directions[g]
            axes.append(axis)
            spread.append(float(np.linalg.norm(normals[idx] - axis, axis=1).max()))
            nearest.append(float(heights[idx].min()))
            members.append(idx)
            seeds.append(int(idx[np.argmax(normals[idx] @ axis)]))
        return cls(centre, np.array(axes), np.array(spread), np.array(nearest), tuple(members), np.array(seeds))

    def farthest_plane(self, points: np.ndarray, equations: np.ndarray) -> np.ndarray:
        """:func:`farthest_plane` of ``points`` (n, 3) over ``equations`` (the hull's), exactly,
        evaluating each group only for the points its bound does not rule out."""
        out = farthest_plane(points, equations[self.seeds])
        q = points - self.centre
        reach = np.linalg.norm(q, axis=1)
        # a round-off's margin: a bound computed a few ulps low must not skip the farthest plane
        margin = 1e-9 * (float(reach.max()) + float(np.abs(self.nearest).max()) + 1.0)
        for g, idx in enumerate(self.members):
            bound = q @ self.axes[g] + self.spread[g] * reach - self.nearest[g] + margin
            need = np.flatnonzero(bound > out)
            if len(need):
                out[need] = np.maximum(out[need], farthest_plane(points[need], equations[idx]))
        return out


def bounded_hull(
    points: np.ndarray, analysis: AnalysisThresholds = ANALYSIS
) -> tuple[np.ndarray, ConvexHull, float] | None:
    """``(input points (k, 3), qhull hull over them, tolerance [m])`` of ``points`` (n, 3), or
    ``None`` when they span no volume. Up to ``analysis.hull_exact_points`` points the hull
    is exact (tolerance 0); above, no point lies more than the tolerance above a facet."""
    from scipy.spatial import ConvexHull, QhullError  # scipy is imported when a hull is first needed

    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(pts) < 4 or is_flat(pts):
        return None
    tolerance = 0.0
    if len(pts) > analysis.hull_exact_points:
        pts = _outside_core(pts, analysis)
        tolerance = analysis.hull_tolerance_fraction * float(np.linalg.norm(np.ptp(pts, axis=0)))
    try:
        # qhull's W option: points less than W above a facet are not added, so a finely
        # tessellated curved surface gets a hull of about diagonal / W facets, not millions
        hull = ConvexHull(pts, qhull_options=f"W{tolerance:.9g}") if tolerance > 0.0 else ConvexHull(pts)
    except QhullError:
        return None
    return pts, hull, tolerance


def enclosing_vertices(pts: np.ndarray, hull: ConvexHull, tolerance: float) -> np.ndarray:
    """Vertices (k, 3) [m] of a polytope holding every input point of a :func:`bounded_hull`:
    the hull itself when exact, else the hull with each facet pushed out by the tolerance
    (a point at most that far above every facet plane is inside it, sharp edges included)."""
    from scipy.spatial import HalfspaceIntersection, QhullError  # scipy is imported when a hull is first needed

    if tolerance <= 0.0:
        return np.asarray(pts[hull.vertices])
    inside = pts[hull.vertices].mean(axis=0)
    halfspaces = hull.equations.copy()
    halfspaces[:, 3] -= tolerance
    try:
        return np.asarray(HalfspaceIntersection(halfspaces, inside).intersections)
    except QhullError:
        # degenerate facets: the hull's bounding box grown by the tolerance still holds every point
        lo, hi = pts.min(axis=0) - tolerance, pts.max(axis=0) + tolerance
        return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


# directions whose extreme points span the core polytope: the 26 neighbours of a cube cell
CORE_DIRECTIONS = np.array(
    [(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if x or y or z], dtype=float
)


def _outside_core(points: np.ndarray, analysis: AnalysisThresholds) -> np.ndarray:
    """``points`` (n, 3) without those strictly inside the hull of their extreme points along
    ``CORE_DIRECTIONS``: such points are no hull vertex (Akl-Toussaint), and dropping them is
    exact. Most vertices of a CAD mesh go; on a finely tessellated sphere none do."""
    from scipy.spatial import ConvexHull, QhullError  # scipy is imported when a hull is first needed

    extremes = np.unique(np.argmax(CORE_DIRECTIONS @ points.T, axis=1))
    try:
        core = ConvexHull(points[extremes])
    except QhullError:
        return points
    # a margin of round-off keeps points on the core's facets, which may be hull vertices
    margin = 1e-9 * float(np.linalg.norm(np.ptp(points, axis=0)))
    keep = np.ones(len(points), dtype=bool)
    normals, offsets = core.equations[:, :3].T, core.equations[:, 3]
    for block in row_blocks(len(points), len(offsets), analysis):
        keep[block] = (points[block] @ normals + offsets).max(axis=1) >= -margin
    return points[keep]


def is_flat(points: np.ndarray) -> bool:
    """Whether ``points`` (n, 3) lie on a plane or a line (or are fewer than 4)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(pts) < 4:
        return True
    if not np.isfinite(pts).all():
        return True
    try:
        spread = np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)
    except np.linalg.LinAlgError:  # spreads underflowing to subnormals: no volume to speak of
        return True
    return bool(spread[0] <= 0.0 or spread[2] / spread[0] < FLAT_RATIO)


def principal_axes(points: np.ndarray) -> np.ndarray:
    """Principal directions of ``points`` (n, 3), largest spread first, as the columns of a
    proper rotation (3, 3)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(pts) < 2 or not np.isfinite(pts).all():
        return np.eye(3)
    centred = pts - pts.mean(axis=0)
    scale = float(np.abs(centred).max())
    if not scale > 0.0:  # every point the same: any frame is as good
        return np.eye(3)
    try:  # scaled to unit size: spreads of 1e-20 m and less would underflow LAPACK's iteration
        _, _, vt = np.linalg.svd(centred / scale, full_matrices=False)
    except np.linalg.LinAlgError:
        return np.eye(3)
    axes = vt.T.copy()
    if axes.shape[1] < 3:
        return np.eye(3)
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    return axes


@dataclass(frozen=True)
class Solid:
    """A surface with what the checks derive from it once: its unique ``vertices`` (k, 3)
    and convex ``hull`` (``None`` when flat)."""

    surface: Surface
    vertices: np.ndarray
    hull: ConvexRegion | None

    @classmethod
    def of(cls, surface: Surface, analysis: AnalysisThresholds = ANALYSIS, distinct: bool = False) -> Solid:
        """The solid of ``surface``; ``distinct`` says its vertices are already all used and
        free of repeats (welded on reading), which spares sorting them again."""
        vertices = surface.vertices if distinct else surface.unique_vertices()
        return cls(surface, vertices, ConvexRegion.of(vertices, analysis))

    def moved(self, rotation: np.ndarray, translation: np.ndarray) -> Solid:
        """The same solid after the rigid motion ``p -> R p + t`` (nothing recomputed)."""
        hull = None if self.hull is None else self.hull.moved(rotation, translation)
        return Solid(self.surface.moved(rotation, translation), from_frame(self.vertices, rotation, translation), hull)
