"""Mass properties of a link and the bounds its geometry puts on them.

A rigid body that lies inside a set of points P, with centre of mass c and mass m, obeys
for every unit direction u:

* moment about the axis through c along u:  I_u = u^T I u <= m * max_p dist(p, axis)^2
* second moment along u:  S_u = tr(I)/2 - I_u = integral ((p - c) . u)^2 dm <= m * max_p ((p - c) . u)^2

and S_u >= 0 is the triangle inequality of the principal moments. The second bound catches
a tensor computed for the wrong axis (a wheel given the inertia of a cylinder along z while
its axis is y), which the first one lets pass. Lengths [m], masses [kg], inertias [kg m^2].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geomcheck.geometry.closest import closest_points
from geomcheck.geometry.hull_mesh import solid, trimesh_hull
from geomcheck.model import Inertial

# Eigenvalues within this share of the largest one count as zero: written tensors are rounded.
EIGEN_RTOL = 1e-9
AXIS_NAMES = ("x", "y", "z")


@dataclass(frozen=True)
class MassProperties:
    """An ``<inertial>`` in the link frame.

    ``com`` shape (3,) [m]; ``tensor`` about the centre of mass along the link axes, shape
    (3, 3) [kg m^2]; ``moments`` principal moments ascending, shape (3,) [kg m^2];
    ``axes`` principal axes as columns (``axes[:, k]`` goes with ``moments[k]``), shape (3, 3).
    """

    mass: float
    com: np.ndarray
    tensor: np.ndarray
    moments: np.ndarray
    axes: np.ndarray

    @property
    def scale(self) -> float:
        """Largest principal moment magnitude [kg m^2] (1 for a zero tensor, to divide by)."""
        largest = float(np.abs(self.moments).max())
        return largest if largest > 0.0 else 1.0

    @property
    def positive_definite(self) -> bool:
        return bool(self.moments.min() > EIGEN_RTOL * self.scale)

    @property
    def positive_semidefinite(self) -> bool:
        return bool(self.moments.min() >= -EIGEN_RTOL * self.scale)

    @property
    def triangle_excess(self) -> float:
        """``C - (A + B)`` for principal moments ``A <= B <= C`` [kg m^2]; positive breaks the inequality."""
        a, b, c = self.moments
        return float(c - (a + b))


def principal_axes(tensor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments ascending, shape (3,), and axes as columns, shape (3, 3), of a symmetric tensor.

    Eigenvectors are only defined up to sign: each is flipped so that its largest component
    is positive, so that the same tensor always gives the same axes.
    """
    moments, axes = np.linalg.eigh(tensor)
    largest = np.argmax(np.abs(axes), axis=0)
    signs = np.where(axes[largest, np.arange(3)] < 0.0, -1.0, 1.0)
    return moments, axes * signs


def mass_properties(inertial: Inertial) -> MassProperties:
    """Centre of mass and tensor of ``inertial`` in the link frame (its ``origin`` rpy applied)."""
    rotation = inertial.origin.rotation()
    tensor = rotation @ inertial.tensor() @ rotation.T
    tensor = (tensor + tensor.T) / 2.0
    moments, axes = principal_axes(tensor)
    return MassProperties(
        mass=float(inertial.mass),
        com=np.asarray(inertial.origin.xyz, dtype=float),
        tensor=tensor,
        moments=moments,
        axes=axes,
    )


def combined(parts: list[tuple[float, np.ndarray, np.ndarray]]) -> MassProperties:
    """Mass properties of rigid parts merged into one body: each part its mass [kg], centre
    of mass (3,) [m] and tensor about it (3, 3) [kg m^2], all in one frame; masses positive.

    The tensors are moved to the common centre of mass by the parallel-axis theorem, as
    pinocchio, sdformat and MuJoCo do when they merge links across fixed joints."""
    masses = np.array([m for m, _, _ in parts], dtype=float)
    coms = np.array([c for _, c, _ in parts], dtype=float).reshape(-1, 3)
    mass = float(masses.sum())
    com = masses @ coms / mass
    offsets = coms - com
    shifted = masses[:, None, None] * (
        np.einsum("ij,ij->i", offsets, offsets)[:, None, None] * np.eye(3) - np.einsum("ij,ik->ijk", offsets, offsets)
    )
    tensor = np.sum([t for _, _, t in parts], axis=0) + shifted.sum(axis=0)
    tensor = (tensor + tensor.T) / 2.0
    moments, axes = principal_axes(tensor)
    return MassProperties(mass=mass, com=com, tensor=tensor, moments=moments, axes=axes)


def reach(points: np.ndarray, origin: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """How far ``points`` (n, 3) [m] lie from lines and planes through ``origin`` (3,).

    ``directions`` are unit vectors as columns, shape (3, k). Returns ``(axis_reach,
    plane_reach)``, each shape (k,) [m]: the largest distance of any point from the line
    through ``origin`` along each direction, and from the plane through ``origin`` normal to it.
    """
    offsets = points - origin
    along = offsets @ directions
    squared = np.einsum("ij,ij->i", offsets, offsets)[:, None] - along**2
    axis_reach = np.sqrt(np.clip(squared, 0.0, None).max(axis=0))
    plane_reach = np.abs(along).max(axis=0)
    return axis_reach, plane_reach


@dataclass(frozen=True)
class GeometryBounds:
    """Moments against the limits the geometry sets, per test direction.

    ``directions`` shape (3, k), columns: the three principal axes, then the link's x, y, z.
    Every other field has shape (k,). ``moments`` [kg m^2] about the axis through the centre
    of mass, ``moment_bound = mass * axis_reach^2``; ``spread`` the second moment along the
    direction [kg m^2], ``spread_bound = mass * plane_reach^2``.
    """

    labels: tuple[str, ...]
    directions: np.ndarray
    moments: np.ndarray
    axis_reach: np.ndarray
    moment_bound: np.ndarray
    spread: np.ndarray
    plane_reach: np.ndarray
    spread_bound: np.ndarray


def geometry_bounds(props: MassProperties, points: np.ndarray) -> GeometryBounds:
    """The bounds of the module docstring for ``props`` inside ``points`` (n, 3) [m], link frame."""
    directions = np.concatenate([props.axes, np.eye(3)], axis=1)
    moments = np.einsum("ik,ij,jk->k", directions, props.tensor, directions)
    spread = np.trace(props.tensor) / 2.0 - moments
    axis_reach, plane_reach = reach(points, props.com, directions)
    labels = tuple(f"principal axis {k + 1}" for k in range(3)) + tuple(f"link {a} axis" for a in AXIS_NAMES)
    return GeometryBounds(
        labels=labels,
        directions=directions,
        moments=moments,
        axis_reach=axis_reach,
        moment_bound=props.mass * axis_reach**2,
        spread=spread,
        plane_reach=plane_reach,
        spread_bound=props.mass * plane_reach**2,
    )


def exceedance(value: np.ndarray, bound: np.ndarray) -> np.ndarray:
    """``value / bound`` elementwise, ``inf`` where the bound is zero and the value is not, 0 where both are
    (and ``inf`` where a bound of a degenerate mesh is so small that the ratio overflows)."""
    value = np.clip(value, 0.0, None)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = np.where(bound > 0.0, value / np.where(bound > 0.0, bound, 1.0), np.where(value > 0.0, np.inf, 0.0))
    return ratio


@dataclass(frozen=True)
class Hull:
    """Convex hull of a link's geometry. ``lower``/``upper`` bounding box corners, shape (3,) [m];
    ``volume`` [m^3] (0 when the points are flat); ``triangles`` shape (f, 3, 3) and
    ``equations`` (f, 4) of its faces (empty when flat)."""

    lower: np.ndarray
    upper: np.ndarray
    volume: float
    triangles: np.ndarray
    equations: np.ndarray


def convex_hull(points: np.ndarray) -> Hull:
    """Hull of ``points`` (n, 3) [m]; flat or degenerate point sets give a hull without faces."""
    from scipy.spatial import ConvexHull, QhullError  # scipy is imported when a hull is first needed

    lower, upper = points.min(axis=0), points.max(axis=0)
    try:
        hull = ConvexHull(points)
    except (QhullError, ValueError):
        return Hull(lower, upper, 0.0, np.zeros((0, 3, 3)), np.zeros((0, 4)))
    return Hull(lower, upper, float(hull.volume), points[hull.simplices], hull.equations)


def distance_outside(hull: Hull, point: np.ndarray) -> float:
    """Euclidean distance [m] from ``point`` (3,) to the hull, 0 inside; to the bounding box when the hull is flat."""
    if len(hull.triangles) == 0:
        gap = np.maximum(hull.lower - point, 0.0) + np.maximum(point - hull.upper, 0.0)
        return float(np.linalg.norm(gap))
    if float((hull.equations[:, :3] @ point + hull.equations[:, 3]).max()) <= 0.0:
        return 0.0
    return distance_to_triangles(hull.triangles, point)


def distance_to_triangles(triangles: np.ndarray, point: np.ndarray) -> float:
    """Euclidean distance [m] from ``point`` (3,) to the nearest of ``triangles`` (f, 3, 3)."""
    nearest = closest_points(triangles, np.tile(point, (len(triangles), 1)))
    return float(np.linalg.norm(nearest - point, axis=1).min())


@dataclass(frozen=True)
class SolidHull:
    """The solid convex hull of a point set at unit density: ``mass`` [kg] (its volume
    [m^3] times 1 kg/m^3), ``center_mass`` (3,) [m] and ``moment_inertia`` (3, 3) [kg m^2]
    about the centre of mass, in the points' frame."""

    mass: float
    center_mass: np.ndarray
    moment_inertia: np.ndarray


def solid_hull(points: np.ndarray) -> SolidHull | None:
    """The mass properties of the solid convex hull of ``points`` (n, 3) [m] (trimesh's hull
    and integrals: :mod:`geomcheck.geometry.hull_mesh`), ``None`` when the points span no
    volume (qhull refuses them, or the hull is not a closed solid)."""
    # a flat hull's centre of mass is 0/0 (computed while orienting the hull): refused below
    with np.errstate(invalid="ignore", divide="ignore"):
        try:
            vertices, faces = trimesh_hull(points)
        except Exception:  # qhull refuses flat or degenerate point sets
            return None
        properties = solid(vertices, faces)
    if properties is None:
        return None
    volume, centre, inertia = properties
    return SolidHull(mass=volume, center_mass=np.asarray(centre, dtype=float), moment_inertia=inertia)
