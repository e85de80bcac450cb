"""The two sides of a fit, in the link frame: a link's visual geometry as a point cloud
(:class:`VisualCloud`) and its collision elements (:class:`CollisionElement`); with the
rounding of report data (:func:`mm`, :func:`ratio`, :func:`sig`).

Apart from :mod:`geomcheck.geometry.fit` so that the fit and the mesh comparison
(:mod:`geomcheck.geometry.meshfit`) both import them without importing each other.
Lengths [m], points (n, 3).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from geomcheck.geometry.frames import to_frame
from geomcheck.geometry.primitives import Primitive, largest_extent, signed_distance, volume
from geomcheck.geometry.surface import ConvexRegion, Solid, Surface

CONFIDENCE_Z = 1.959964  # two-sided 95 % quantile of the normal distribution: sampling error bounds [1]


def mm(value: float | None) -> float | None:
    """``value`` [m] in millimetres, to 0.1 mm (report data)."""
    return None if value is None else round(float(value) * 1000.0, 1) + 0.0


def at_nanometre(value: float) -> float:
    """A length or coordinate [m] rounded to a nanometre: a mesh face at z = 0 compiled or
    composed to z = -2.3e-16 reads as 0 on every CPU."""
    return round(float(value), 9) + 0.0  # + 0.0: no negative zero


def ratio(value: float | None, decimals: int = 4) -> float | None:
    """A dimensionless ``value`` rounded for report data."""
    return None if value is None else round(float(value), decimals) + 0.0


def sig(value: float | None, digits: int = 6) -> float | None:
    """``value`` to ``digits`` significant digits (volumes [m^3] span many decades)."""
    return None if value is None else float(f"{float(value):.{digits}g}")


@dataclass(frozen=True)
class VisualCloud:
    """A link's visual geometry as points in the link frame: the ``vertices`` (n, 3) of its
    convex hull (all unique vertices when it is flat), area-weighted ``samples`` (m, 3), the
    ``hull`` (``None`` when flat) and the ``area`` [m^2].

    Hull vertices suffice for extremes: the distance to a convex shape is a convex function,
    so over the surface it peaks at a hull vertex; the samples stand for the surface itself."""

    vertices: np.ndarray
    samples: np.ndarray
    hull: ConvexRegion | None
    area: float
    tolerance: float = 0.0  # how far a mesh vertex may lie outside ``hull`` (approximated hulls) [m]

    @classmethod
    def of(cls, solids: Sequence[Solid], count: int, seed: int) -> VisualCloud:
        """The cloud of the link-frame ``solids`` together, ``count`` samples drawn with ``seed``."""
        surface = solids[0].surface if len(solids) == 1 else Surface.merge(s.surface for s in solids)
        tolerance = max((s.hull.tolerance for s in solids if s.hull is not None), default=0.0)
        if len(solids) == 1:
            hull = solids[0].hull
        else:
            corners = [s.vertices if s.hull is None else s.hull.vertices for s in solids]
            hull = ConvexRegion.of(np.concatenate(corners)) if corners else None
            tolerance += hull.tolerance if hull is not None else 0.0
        if hull is not None:
            vertices = hull.vertices
        else:
            vertices = np.concatenate([s.vertices for s in solids]) if solids else np.zeros((0, 3))
        samples = surface.sample(count, np.random.default_rng(seed))
        return cls(vertices, samples, hull, surface.area, tolerance)

    def precision(self) -> dict[str, Any]:
        """What the fit metrics of this cloud can be trusted to, as report data.

        ``coverage_margin``: half-width of the 95 % confidence interval of a coverage share
        measured on the area-weighted samples (worst case, a share of one half);
        ``p95_quantile_range``: with 95 % confidence the 95th percentile of the samples lies
        between these quantiles of the whole surface; ``hull_tolerance_mm``: how far a mesh
        vertex may lie outside the hull whose vertices give the maxima (0: exact hull)."""
        count = len(self.samples)
        if count == 0:
            return {"surface_samples": 0, "coverage_margin": None, "p95_quantile_range": None}
        spread = CONFIDENCE_Z * np.sqrt(0.95 * 0.05 / count)
        return {
            "surface_samples": count,
            "coverage_margin": ratio(CONFIDENCE_Z * 0.5 / np.sqrt(count)),
            "p95_quantile_range": [ratio(0.95 - spread), ratio(min(1.0, 0.95 + spread))],
            "hull_tolerance_mm": mm(self.tolerance),
        }

    @functools.cached_property
    def points(self) -> np.ndarray:
        """Vertices then samples, shape (n + m, 3)."""
        return np.concatenate((self.vertices, self.samples))

    @functools.cached_property
    def _bounds(self) -> np.ndarray:
        pts = self.points
        return np.stack((pts.min(axis=0), pts.max(axis=0)))

    def bounds(self) -> np.ndarray:
        """``[min, max]`` corners, shape (2, 3) [m]."""
        return self._bounds


@dataclass(frozen=True)
class CollisionElement:
    """A ``<collision>`` element in the link frame: a ``primitive`` in the frame
    ``rotation`` (3, 3) / ``translation`` (3,), or a mesh given as a ``solid`` already moved
    into the link frame."""

    index: int
    rotation: np.ndarray
    translation: np.ndarray
    primitive: Primitive | None = None
    solid: Solid | None = None
    same_as_visual: bool = False  # a mesh identical to the link's only visual (file, scale, origin)

    @property
    def hull(self) -> ConvexRegion | None:
        """A collision mesh's convex hull in the link frame."""
        return None if self.solid is None else self.solid.hull

    @property
    def type(self) -> str:
        return "mesh" if self.primitive is None else type(self.primitive).__name__.lower()

    @property
    def volume(self) -> float:
        """Volume [m^3]; a mesh's convex hull volume."""
        if self.primitive is not None:
            return volume(self.primitive)
        return self.hull.volume if self.hull is not None else 0.0

    @property
    def centre(self) -> np.ndarray:
        """Link-frame centre (3,) [m]: the primitive's origin, the mesh hull's bounds centre."""
        if self.primitive is not None or self.hull is None:
            return np.asarray(self.translation, dtype=float)
        return 0.5 * (self.hull.vertices.min(axis=0) + self.hull.vertices.max(axis=0))

    @property
    def size(self) -> float:
        """Largest extent [m]."""
        if self.primitive is not None:
            return largest_extent(self.primitive)
        pts = self.hull.vertices if self.hull is not None else np.zeros((1, 3))
        return float(np.ptp(pts, axis=0).max())

    def local(self, points: np.ndarray) -> np.ndarray:
        """Link-frame ``points`` (n, 3) in the element's frame."""
        return to_frame(points, self.rotation, self.translation)

    def signed_distance(self, points: np.ndarray) -> np.ndarray:
        """Signed distance (n,) [m] of link-frame ``points`` (n, 3) to the element."""
        if self.primitive is not None:
            return signed_distance(self.primitive, self.local(points))
        if self.same_as_visual:
            return np.zeros(len(points))  # the visual's points lie on this very surface
        if self.hull is None:
            return np.full(len(points), np.inf)
        return self.hull.signed_distance(points)


__all__ = ["CONFIDENCE_Z", "CollisionElement", "VisualCloud", "mm", "ratio", "sig"]
