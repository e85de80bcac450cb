"""Suggested collision primitives: the box, cylinder or sphere of a given type that encloses
a set of points tightly, placed in the link frame, with ready-to-paste URDF.

Among nearly equally tight candidates the simplest frame wins: the element's own
orientation, then the link axes, then an arbitrary orientation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from geomcheck.geometry.enclosing import minimal_ball, minimum_box
from geomcheck.geometry.frames import canonical_box_frame, rotation_between, snap_rotation
from geomcheck.geometry.primitives import Primitive, signed_distance, volume
from geomcheck.geometry.surface import ConvexRegion, principal_axes
from geomcheck.model import Box, Capsule, Cylinder, Sphere, rpy_from_matrix

MIN_EXTENT_M = 0.001  # suggested edges, lengths and radii are at least this [m]
# a capsule fitted about an axis tries radii from the points' reach off the axis up to this
# many times it, in CAPSULE_RADII steps: a fatter capsule's shorter straight part can be smaller
CAPSULE_RADIUS_SPAN = 2.0
CAPSULE_RADII = 65
LENGTH_DECIMALS = 4  # URDF lengths printed to 0.1 mm
ANGLE_DECIMALS = 4  # URDF angles printed to 1e-4 rad

# frames putting a cylinder's z axis on the link's x, y and z axes, simplest rpy first
AXIS_FRAMES = (
    ("x", np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])),  # rpy 0 pi/2 0
    ("y", np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])),  # rpy pi/2 0 0
    ("z", np.eye(3)),
)


def fmt(value: float, decimals: int = LENGTH_DECIMALS) -> str:
    """``value`` for a URDF attribute: fixed decimals, trailing zeros and ``-0`` removed."""
    text = f"{value:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "", "-") else text


def urdf_snippet(primitive: Primitive, rotation: np.ndarray, translation: np.ndarray) -> str:
    """``<origin .../>`` and ``<geometry>...</geometry>`` lines for a collision element."""
    rpy = rpy_from_matrix(snap_rotation(rotation))
    xyz = " ".join(fmt(v) for v in translation)
    angles = " ".join(fmt(v, ANGLE_DECIMALS) for v in rpy)
    if isinstance(primitive, Box):
        shape = f'<box size="{" ".join(fmt(v) for v in primitive.size)}"/>'
    elif isinstance(primitive, Cylinder):
        shape = f'<cylinder radius="{fmt(primitive.radius)}" length="{fmt(primitive.length)}"/>'
    else:
        shape = f'<sphere radius="{fmt(primitive.radius)}"/>'
    return f'<origin xyz="{xyz}" rpy="{angles}"/>\n<geometry>{shape}</geometry>'


def geometry_dict(primitive: Primitive) -> dict[str, Any]:
    """The primitive's URDF attributes as report data [m]."""
    if isinstance(primitive, Box):
        return {"size": [round(float(v), 6) + 0.0 for v in primitive.size]}
    if isinstance(primitive, Cylinder):
        return {"radius": round(primitive.radius, 6), "length": round(primitive.length, 6)}
    return {"radius": round(primitive.radius, 6)}


@dataclass(frozen=True)
class Suggestion:
    """A fitted primitive in the link frame (``rotation`` (3, 3) columns = its axes,
    ``translation`` (3,) [m]), with its ``coverage`` of the points it was fitted to and its
    ``slack`` (volume over the points' hull volume; ``None`` when they span no volume)."""

    primitive: Primitive
    rotation: np.ndarray
    translation: np.ndarray
    frame: str  # "element", "link" or "oriented": which candidate frame won
    coverage: float
    slack: float | None

    @property
    def type(self) -> str:
        return type(self.primitive).__name__.lower()

    @property
    def volume(self) -> float:
        return volume(self.primitive)

    def urdf(self) -> str:
        return urdf_snippet(self.primitive, self.rotation, self.translation)

    def to_dict(self) -> dict[str, Any]:
        rpy = rpy_from_matrix(snap_rotation(self.rotation))
        return {
            "type": self.type,
            "origin": {
                "xyz": [round(float(v), 6) + 0.0 for v in self.translation],
                "rpy": [round(float(v), 6) + 0.0 for v in rpy],
            },
            "geometry": geometry_dict(self.primitive),
            "urdf": self.urdf(),
            "coverage": round(self.coverage, 4) + 0.0,
            "slack": None if self.slack is None else round(self.slack, 3) + 0.0,
        }


def _pick(volumes: list[float], margin: float) -> int:
    """Index of the first (simplest) candidate within ``1 + margin`` of the smallest volume."""
    finite = [v for v in volumes if np.isfinite(v)]
    if not finite:  # degenerate points (NaN, under- or overflow): the first candidate, not StopIteration
        return 0
    best = min(finite)
    return next(i for i, v in enumerate(volumes) if v <= best * (1.0 + margin) + 1e-15)


def _box_in_frame(points: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    local = points @ rotation
    lo, hi = local.min(axis=0), local.max(axis=0)
    return rotation @ (0.5 * (lo + hi)), np.maximum(hi - lo, MIN_EXTENT_M)


def fit_box(
    points: np.ndarray, hull: ConvexRegion | None, own: np.ndarray | None, margin: float
) -> tuple[Box, np.ndarray, np.ndarray, str]:
    """Box enclosing ``points`` (n, 3): ``(box, rotation, translation, frame)``."""
    frames: list[tuple[str, np.ndarray]] = []
    if own is not None:
        frames.append(("element", own))
    frames.append(("link", np.eye(3)))
    fitted = [_box_in_frame(points, r) for _, r in frames]
    simplest = min(float(np.prod(s)) for _, s in fitted)
    # no box is smaller than the hull: a simple frame that close needs no search
    if hull is None or simplest > hull.volume * (1.0 + margin):
        rotation, _, size = minimum_box(points, hull)
        rotation, size = canonical_box_frame(rotation, size)
        frames.append(("oriented", rotation))
        fitted.append(_box_in_frame(points, rotation))
    i = _pick([float(np.prod(s)) for _, s in fitted], margin)
    centre, size = fitted[i]
    return Box(tuple(float(v) for v in size)), frames[i][1], centre, frames[i][0]  # type: ignore[arg-type]


def hull_2d(points: np.ndarray) -> np.ndarray:
    """The vertices of the 2-D convex hull of ``points`` (n, 2); all of them when degenerate."""
    from scipy.spatial import ConvexHull, QhullError  # scipy is imported when a hull is first needed

    try:
        return points[ConvexHull(points).vertices]
    except (QhullError, ValueError):
        return points


def _cylinder_along(points: np.ndarray, rotation: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Enclosing cylinder along ``rotation``'s z axis: radius, length [m], centre (3,)."""
    local = points @ rotation
    centre_2d, radius = minimal_ball(hull_2d(local[:, :2]))
    lo, hi = local[:, 2].min(), local[:, 2].max()
    centre_local = np.array([centre_2d[0], centre_2d[1], 0.5 * (lo + hi)])
    return max(radius, MIN_EXTENT_M), max(float(hi - lo), MIN_EXTENT_M), rotation @ centre_local


def _rough_cylinder_volumes(points: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """Volumes (r,) [m^3] of cylinders along each rotation's z axis (r, 3, 3), centred on the
    points' bounding box across the axis: an upper bound, within a few percent of the smallest."""
    local = np.einsum("nk,rkj->rnj", points, rotations)  # (r, n, 3)
    lo, hi = local.min(axis=1), local.max(axis=1)
    centre = 0.5 * (lo + hi)
    radius = np.linalg.norm(local[:, :, :2] - centre[:, None, :2], axis=2).max(axis=1)
    return np.pi * radius**2 * (hi[:, 2] - lo[:, 2])


def axis_frame(axis: np.ndarray) -> np.ndarray:
    """A rotation whose z column is ``axis`` (3,) up to sign: the link-axis frames for x, y,
    z, else the smallest rotation from z."""
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    for _, frame in AXIS_FRAMES:
        if abs(float(frame[:, 2] @ a)) > 1.0 - 1e-9:
            return frame
    if a[int(np.argmax(np.abs(a)))] < 0:
        a = -a
    return rotation_between(np.array([0.0, 0.0, 1.0]), a)


def fit_cylinder(
    points: np.ndarray, principal: np.ndarray, own: np.ndarray | None, margin: float
) -> tuple[Cylinder, np.ndarray, np.ndarray, str]:
    """Cylinder enclosing ``points`` (n, 3) along the best of the element's axis, the link
    axes and the ``principal`` axes (columns of (3, 3)): ``(cylinder, rotation, translation, frame)``."""
    frames: list[tuple[str, np.ndarray]] = []
    if own is not None:
        frames.append(("element", own))
    frames.extend(("link", f) for _, f in AXIS_FRAMES)
    frames.extend(("oriented", axis_frame(a)) for a in principal.T)
    # rank the axes on a cheap bound, then fit the chosen one exactly
    i = _pick(list(_rough_cylinder_volumes(points, np.array([r for _, r in frames]))), margin)
    radius, length, centre = _cylinder_along(points, frames[i][1])
    return Cylinder(radius, length), frames[i][1], centre, frames[i][0]


def capsule_along(points: np.ndarray, rotation: np.ndarray, centre: np.ndarray) -> Capsule:
    """The capsule of least volume enclosing ``points`` (n, 3) whose axis is ``rotation``'s z
    column through ``centre`` (3,) [m] (a fitted cylinder's axis), sliding along it: for each
    radius tried, the straight part is as short as leaves every point within the radius of it."""
    local = (np.asarray(points, dtype=float) - centre) @ rotation
    along = local[:, 2]
    off_axis = np.linalg.norm(local[:, :2], axis=1)
    reach = max(float(off_axis.max()), MIN_EXTENT_M)
    radii = reach * np.linspace(1.0, CAPSULE_RADIUS_SPAN, CAPSULE_RADII)  # (r,)
    # a point at distance rho off the axis fits in the caps within sqrt(r^2 - rho^2) of the segment's ends
    cap = np.sqrt(np.maximum(radii[:, None] ** 2 - off_axis[None, :] ** 2, 0.0))  # (r, n)
    straight = np.maximum((along - cap).max(axis=1) - (along + cap).min(axis=1), 0.0)  # (r,)
    volumes = np.pi * radii**2 * straight + 4.0 / 3.0 * np.pi * radii**3
    best = int(np.argmin(volumes))
    return Capsule(float(radii[best]), float(straight[best] + 2.0 * radii[best]))


def fit_sphere(points: np.ndarray) -> tuple[Sphere, np.ndarray, np.ndarray, str]:
    """Smallest sphere enclosing ``points`` (n, 3): ``(sphere, identity, centre, "link")``."""
    centre, radius = minimal_ball(points)
    return Sphere(max(radius, MIN_EXTENT_M)), np.eye(3), centre, "link"


def suggest(
    kind: type[Box] | type[Cylinder] | type[Sphere],
    points: np.ndarray,
    samples: np.ndarray,
    hull: ConvexRegion | None,
    own_rotation: np.ndarray | None,
    margin: float,
    tolerance: float,
) -> Suggestion | None:
    """A primitive of type ``kind`` fitted to ``points`` (n, 3; hull vertices suffice), its
    coverage measured on the area-weighted ``samples`` (m, 3) within ``tolerance`` [m]."""
    if len(points) == 0 or not np.isfinite(points).all():
        return None
    enclose = hull.vertices if hull is not None else points
    fitted: tuple[Primitive, np.ndarray, np.ndarray, str]
    if kind is Box:
        fitted = fit_box(enclose, hull, own_rotation, margin)
    elif issubclass(kind, Cylinder):  # a capsule too: it is measured as the cylinder enclosing it
        fitted = fit_cylinder(enclose, principal_axes(samples if len(samples) else points), own_rotation, margin)
    else:
        fitted = fit_sphere(enclose)
    primitive, rotation, translation, frame = fitted
    probe = samples if len(samples) else points
    inside = signed_distance(primitive, (probe - translation) @ rotation) <= tolerance
    slack = volume(primitive) / hull.volume if hull is not None and hull.volume > 0 else None
    return Suggestion(primitive, rotation, translation, frame, float(inside.mean()), slack)
