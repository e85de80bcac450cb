"""Triangle surfaces as numpy arrays: merging, area-weighted sampling, convex hulls.

Every array is in one frame (the link frame unless stated), lengths [m].
"""

from __future__ import annotations

import functools
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import trimesh
from scipy.spatial import ConvexHull, QhullError

from geomcheck.geometry.frames import from_frame

FLAT_RATIO = 1e-9  # smallest / largest principal spread below this: the points are flat [1]
VERTEX_DIGITS = 9  # vertices equal to this many decimals [m] are one vertex


def unique_rows(points: np.ndarray) -> np.ndarray:
    """``points`` (n, 3) without repeats (equal to ``VERTEX_DIGITS`` decimals), in order of first appearance."""
    if len(points) == 0:
        return points
    keys = np.round(points * 10.0**VERTEX_DIGITS).astype(np.int64)
    order = np.lexsort(keys.T[::-1])
    ranked = keys[order]
    first = np.ones(len(ranked), dtype=bool)
    first[1:] = np.any(ranked[1:] != ranked[:-1], axis=1)
    # the first of each run in a stable sort is the earliest occurrence
    return points[np.sort(order[first])]


@dataclass(frozen=True)
class Surface:
    """A triangle surface: ``vertices`` (n, 3) [m] and ``faces`` (m, 3) indices into them."""

    vertices: np.ndarray
    faces: np.ndarray

    @classmethod
    def from_mesh(cls, mesh: trimesh.Trimesh, rotation: np.ndarray, translation: np.ndarray) -> Surface:
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

    @functools.cached_property
    def _triangles(self) -> np.ndarray:
        return self.vertices[self.faces]

    @functools.cached_property
    def _areas(self) -> np.ndarray:
        t = self._triangles
        return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)

    def triangles(self) -> np.ndarray:
        """Corner coordinates of each face, shape (m, 3, 3) [m]."""
        return self._triangles

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
        used = self.vertices[np.unique(self.faces)] if len(self.faces) else self.vertices
        return unique_rows(used)

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
        t = self.triangles()[faces]
        return t[:, 0] + u[:, None] * (t[:, 1] - t[:, 0]) + v[:, None] * (t[:, 2] - t[:, 0])


@dataclass(frozen=True)
class ConvexRegion:
    """The convex hull of a point set: hull ``vertices`` (k, 3), outward facet ``equations``
    (f, 4) with ``n . p + d <= 0`` inside, ``facet_areas`` (f,) [m^2] and ``volume`` [m^3]."""

    vertices: np.ndarray
    equations: np.ndarray
    facet_areas: np.ndarray
    volume: float

    @classmethod
    def of(cls, points: np.ndarray) -> ConvexRegion | None:
        """Hull of ``points`` (n, 3), or ``None`` when they span no volume (fewer than 4, flat)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        if len(pts) < 4 or is_flat(pts):
            return None
        try:
            hull = ConvexHull(pts)
        except QhullError:
            return None
        t = pts[hull.simplices]
        areas = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
        return cls(pts[hull.vertices], hull.equations, areas, float(hull.volume))

    def moved(self, rotation: np.ndarray, translation: np.ndarray) -> ConvexRegion:
        """The same hull after the rigid motion ``p -> R p + t`` (``rotation`` (3, 3), ``translation`` (3,))."""
        normals = self.equations[:, :3] @ rotation.T
        offsets = self.equations[:, 3] - normals @ translation
        equations = np.column_stack((normals, offsets))
        return ConvexRegion(from_frame(self.vertices, rotation, translation), equations, self.facet_areas, self.volume)

    def signed_distance(self, points: np.ndarray) -> np.ndarray:
        """Signed distance (n,) [m] to the hull: exact inside (negative), a lower bound of the
        true distance outside (the distance to the farthest facet plane)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        return (pts @ self.equations[:, :3].T + self.equations[:, 3]).max(axis=1)


def is_flat(points: np.ndarray) -> bool:
    """Whether ``points`` (n, 3) lie on a plane or a line (or are fewer than 4)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(pts) < 4:
        return True
    spread = np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)
    return bool(spread[0] <= 0.0 or spread[2] / spread[0] < FLAT_RATIO)


def principal_axes(points: np.ndarray) -> np.ndarray:
    """Principal directions of ``points`` (n, 3), largest spread first, as the columns of a
    proper rotation (3, 3)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(pts) < 2:
        return np.eye(3)
    _, _, vt = np.linalg.svd(pts - pts.mean(axis=0), full_matrices=False)
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
    def of(cls, surface: Surface) -> Solid:
        vertices = surface.unique_vertices()
        return cls(surface, vertices, ConvexRegion.of(vertices))

    def moved(self, rotation: np.ndarray, translation: np.ndarray) -> Solid:
        """The same solid after the rigid motion ``p -> R p + t`` (nothing recomputed)."""
        hull = None if self.hull is None else self.hull.moved(rotation, translation)
        return Solid(self.surface.moved(rotation, translation), from_frame(self.vertices, rotation, translation), hull)
