"""Whether a part is a body of revolution, and about which axis.

A wheel, a tyre, a flange or a pulley is round about one axis: its surface's second moments have
one distinct principal axis (two equal moments across it), and its convex hull reaches equally far
from that axis in every direction around it. Spokes, holes and treads hide inside the hull, so a
spoked wheel is as round as a solid one; a square plate (corners 41% farther out than its edges)
or a hexagonal nut (15%) is not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SECTORS = 24  # angular sectors around the axis whose farthest hull points are compared [count]


@dataclass(frozen=True)
class Revolution:
    """A part round about the line through ``centre`` (3,) along unit ``axis`` (3,) [m]: its
    largest ``radius`` [m], its ``length`` along the axis [m], and ``roundness``: how much the
    farthest reach differs between sectors around the axis, as a share of the radius."""

    axis: np.ndarray
    centre: np.ndarray
    radius: float
    length: float
    roundness: float

    def holds(self, point: np.ndarray, margin: float) -> bool:
        """Whether ``point`` (3,) lies on the part's axis within ``margin`` [m] and along it within
        the part's length (plus ``margin``): where a joint turning the part sits."""
        offset = np.asarray(point, dtype=float) - self.centre
        along = float(offset @ self.axis)
        across = float(np.linalg.norm(offset - along * self.axis))
        return across <= margin and abs(along) <= 0.5 * self.length + margin


def sector_reach(points: np.ndarray, centre: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """The farthest distance [m] from the axis line in each of :data:`SECTORS` sectors around it
    (0 for an empty sector), shape (SECTORS,)."""
    rel = points - centre
    along = rel @ axis
    radial = rel - np.outer(along, axis)
    u = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    angle = np.arctan2(radial @ v, radial @ u)
    sector = np.minimum(((angle + np.pi) / (2.0 * np.pi) * SECTORS).astype(int), SECTORS - 1)
    reach = np.zeros(SECTORS)
    np.maximum.at(reach, sector, np.linalg.norm(radial, axis=1))
    return reach


def revolution(samples: np.ndarray, hull_vertices: np.ndarray, equal_moments: float) -> Revolution | None:
    """The axis about which the surface ``samples`` (n, 3) with convex hull ``hull_vertices``
    (m, 3) is most nearly round, or ``None`` when no principal axis is distinct (two moments
    across it within ``equal_moments`` of each other [fraction], and the third apart from them:
    a sphere or a cube has no axis of its own)."""
    if len(samples) < 3 or len(hull_vertices) < 4:
        return None
    centre = samples.mean(axis=0)
    spread = samples - centre
    points = np.concatenate((hull_vertices, samples))  # the samples fill the sectors of a coarse polygon
    moments, axes = np.linalg.eigh(spread.T @ spread / len(samples))
    best: Revolution | None = None
    for k, (i, j) in ((0, (1, 2)), (2, (0, 1))):
        a, b = moments[i], moments[j]
        if abs(a - b) > equal_moments * max(a, b) or abs(moments[k] - a) <= equal_moments * max(a, moments[k]):
            continue
        found = measured(points, centre, axes[:, k] / np.linalg.norm(axes[:, k]))
        if found is not None and (best is None or found.roundness < best.roundness):
            best = found
    return best


def measured(points: np.ndarray, centre: np.ndarray, axis: np.ndarray) -> Revolution | None:
    """``points`` (n, 3) measured as a body of revolution about the line through ``centre`` along
    unit ``axis``; ``None`` when some sector around it is empty or the points lie on it."""
    reach = sector_reach(points, centre, axis)
    radius = float(reach.max())
    if radius <= 0.0 or not reach.all():
        return None
    along = (points - centre) @ axis
    return Revolution(axis, centre, radius, float(np.ptp(along)), float(1.0 - reach.min() / radius))


def about(part: Revolution, axis: np.ndarray, samples: np.ndarray, hull_vertices: np.ndarray) -> Revolution:
    """``part`` measured again about ``axis`` (a frame axis its measured axis was snapped to)."""
    found = measured(np.concatenate((hull_vertices, samples)), part.centre, axis)
    return part if found is None else found


__all__ = ["SECTORS", "Revolution", "about", "measured", "revolution", "sector_reach"]
