"""A lower bound of a spinning link's distance to a still one over *every* spin angle: the
distance to its solid of revolution, one query per swivel angle instead of a spin search.

A caster wheel spins about its axle while its caster swivels about the vertical: the sweep of
the caster is a torus of (swivel, spin) angles. Over a whole turn of the spin the wheel stays
inside the solid its collision geometry sweeps about the axle, which is the same solid at
every spin angle. Its cross-section in ``(r, z)`` about the axle (distance from the axle,
height along it) is held by the convex hull ``H`` of the support points' images
``(+-(r + pad), z +- pad)``: a point of a triangle (or of a support's hull, grown by its pad)
is a convex combination of corners whose ``r`` is at least its own (``r`` is convex) and whose
``z`` it shares. ``H`` is symmetric about ``r = 0``, so the solid it sweeps, ``r <= R(z)``
with ``R`` concave, is convex; rings of :data:`RING_POINTS` points on circles circumscribing
``R`` at ``H``'s corners span a convex polytope ``P`` holding it.

The distance from the still link's triangles (and primitives) to ``P`` as a *solid* is then at
most the distance to the wheel at any spin angle. ``P`` is fixed in the wheel's link frame up
to the spin, about which it is round: placed with the link's frame at any spin it is the same
set, so one query bounds every spin angle of a swivel angle. When the swivel turns by ``dt``
no point of ``P`` moves further than ``speed * |dt|`` (its largest distance from the swivel
axis): the bound at a cell's swivel centre less that proves the whole cell, whatever its spin
interval, without splitting the spin.

Only the still link's triangles (and primitives) that can come within ``cap`` [m] of ``P``
over the whole swivel turn are asked: their boxes in radius and height about the swivel axis
(:func:`geomcheck.selfcollision.turn_bound.triangle_boxes`), which the turn keeps, within
``cap`` of the cylinder about that axis holding ``P``; a bound is at most ``cap``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from geomcheck.collision.base import MeshArrays, is_exact_hull
from geomcheck.collision.scene import CollisionScene
from geomcheck.kinematics import Kinematics
from geomcheck.model import Joint, Sphere
from geomcheck.selfcollision.crop import part_mesh
from geomcheck.selfcollision.sweep_plan import PairPlan, SweepGroup, axis_distance
from geomcheck.selfcollision.turn_bound import support_box, triangle_boxes

RING_POINTS = 128  # points per circle of the polytope: it bulges R (1 / cos(pi / n) - 1) out [count]
RIM_BAND = 0.05  # support points this close to the largest radius are on the rim [ratio of it]
RIM_GAP_RAD = np.pi / 4  # a rim with no azimuth gap wider than this goes all round: a wheel [rad]
ON_AXIS_M = 1e-9  # a corner of the cross-section this close to the axle is on it [m]


@dataclass(frozen=True)
class Spin:
    """The two joints that move a link in a two-angle sweep: ``swivel`` (the group's first
    variable, turned ``multiplier`` per unit) and, below it, ``spin``."""

    swivel: Joint
    multiplier: float
    spin: Joint


def spinning_joints(kin: Kinematics, group: SweepGroup, plan: PairPlan) -> Spin | None:
    """The :class:`Spin` of ``plan``'s moving link past its still second link when the group's
    first variable turns it by one revolute joint and one other variable spins it by one
    revolute joint below that one (a caster wheel in its caster's sweep); else ``None``."""
    if plan.both_move or plan.constant or len(group.dimensions) < 2:
        return None
    path = kin.root_path(plan.links[0])  # from the root down
    driven = [(j, d) for j in path if (d := kin.driver(j)) is not None and d[0] in group.dimensions]
    if len(driven) != 2 or driven[0][1][0] != group.dimensions[0] or driven[1][1][0] == group.dimensions[0]:
        return None
    (swivel, (_, multiplier)), (spin, _) = driven
    if any(j.type not in ("revolute", "continuous") for j in (swivel, spin)):
        return None
    return Spin(swivel, float(multiplier), spin)


def _basis(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.array([1.0, 0.0, 0.0]) if abs(direction[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(direction, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(direction, u)


def cross_section(points: np.ndarray, pad: float, point: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Corners ``(R, z)`` (k, 2) [m] of the convex cross-section ``H`` (``r >= 0`` half, by
    increasing ``z``) holding ``points`` (n, 3) grown by ``pad`` swept about the axis through
    ``point`` along the unit ``direction``."""
    rel = points - point
    z = rel @ direction
    r = axis_distance(points, point, direction) + pad
    ends = [z - pad, z + pad] if pad > 0 else [z]
    rz = np.concatenate([np.stack([side * r, h], axis=1) for side in (1.0, -1.0) for h in ends])
    from scipy.spatial import ConvexHull  # only when a wheel is swept: a check that fails early never loads it

    corners = rz[ConvexHull(rz).vertices]
    right = corners[corners[:, 0] > -ON_AXIS_M]
    right[:, 0] = np.maximum(right[:, 0], 0.0)
    return right[np.argsort(right[:, 1], kind="stable")]


def polytope_points(section: np.ndarray, point: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Points (m, 3) whose convex hull holds the solid that ``section`` (:func:`cross_section`)
    sweeps about the axis: a circumscribing ring per corner off the axle, the corner on it."""
    u, v = _basis(direction)
    t = 2 * np.pi * np.arange(RING_POINTS) / RING_POINTS
    ring = np.cos(t)[:, None] * u + np.sin(t)[:, None] * v  # (n, 3)
    out = []
    for radius, height in section:
        centre = point + height * direction
        if radius <= ON_AXIS_M:
            out.append(centre[None])
        else:
            # the polygon's edges touch the circle of ``radius``: its corners lie further out
            out.append(centre + (radius / np.cos(np.pi / RING_POINTS)) * ring)
    return np.concatenate(out)


def goes_round(points: np.ndarray, pad: float, point: np.ndarray, direction: np.ndarray) -> bool:
    """Whether ``points`` (n, 3) (grown by ``pad``) fill their solid of revolution about the axis
    near its rim, as a wheel's tread does: the points within :data:`RIM_BAND` of the largest
    radius leave no azimuth gap wider than :data:`RIM_GAP_RAD`. Only then is the distance to the
    solid close to the distance at some spin angle; a bar spinning about its end is far below
    it, and its bound would prove nothing at the cost of a query per cell."""
    r = axis_distance(points, point, direction) + pad
    u, v = _basis(direction)
    rel = points[r >= (1.0 - RIM_BAND) * r.max()] - point
    azimuth = np.sort(np.arctan2(rel @ v, rel @ u))
    gaps = np.diff(np.concatenate([azimuth, azimuth[:1] + 2 * np.pi]))
    return bool(gaps.max() <= RIM_GAP_RAD)


def _hull_mesh(points: np.ndarray) -> MeshArrays:
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points)
    used, faces = np.unique(hull.simplices.ravel(), return_inverse=True)
    return MeshArrays(np.ascontiguousarray(points[used]), faces.reshape(-1, 3).astype(np.int64))


@dataclass
class RevolutionBound:
    """The bound of one pair: ``solid`` (``P`` in the moving link's frame, an engine object
    whose convex hull is ``P``) against each of the still link's shapes, placed once."""

    scene: CollisionScene
    solid: Any
    still: list[tuple[Any, Any]]  # (engine object, placement) per still shape that can come near
    speed: float  # [m/rad]: largest displacement of P per radian of the swept variable
    cap: float  # [m]
    spin: str  # the variable that spins the link
    _found: dict[float, float] = field(default_factory=dict)  # bound per swivel value [m]
    queries: int = 0  # distance queries asked [count]

    def at(self, values: np.ndarray, frames: np.ndarray) -> np.ndarray:
        """The bound [m] (n,) at swept-variable ``values`` (n,) with the moving link's world
        ``frames`` (n, 4, 4) there (any spin): at most :attr:`cap`."""
        out = np.empty(len(values))
        backend = self.scene.backend
        for k, value in enumerate(values.tolist()):
            found = self._found.get(value)
            if found is None:
                placed = backend.placement(frames[k])
                found = self.cap
                for obj, where in self.still:
                    self.queries += 1
                    found = min(found, backend.placed_hull_distance(obj, where, self.solid, placed))
                self._found[value] = found
            out[k] = found
        return out


def _cylinder_gaps(boxes: np.ndarray, radius: np.ndarray, height: np.ndarray) -> np.ndarray:
    """The (r, z) gaps [m] (n,) of cylindrical ``boxes`` (n, 6) to the cylinder about the same axis
    reaching the largest of ``radius`` and spanning ``height`` (P's points')."""
    gap_r = np.maximum(0.0, boxes[:, 0] - radius.max())
    gap_z = np.maximum(0.0, np.maximum(boxes[:, 2] - height.max(), height.min() - boxes[:, 3]))
    return np.hypot(gap_r, gap_z)


def _cylinder_box(
    point: np.ndarray, direction: np.ndarray, radius: np.ndarray, height: np.ndarray, pad: float
) -> tuple[np.ndarray, np.ndarray]:
    """The world box ``(low (3,), high (3,))`` of that cylinder grown by ``pad`` [m]."""
    centre = point + (height.max() + height.min()) / 2 * direction
    extent = (height.max() - height.min()) / 2 * np.abs(direction)
    extent = extent + radius.max() * np.sqrt(np.clip(1.0 - direction**2, 0.0, None)) + pad
    return centre - extent, centre + extent


def _triangles_object(scene: CollisionScene, mesh: MeshArrays) -> Any:
    """An engine object of ``mesh``'s triangles whose hull query is asked of the triangles
    themselves: a part of a primitive, which has no hull of its own to stand for it."""
    return scene.backend.part(scene.backend.make(Sphere(1.0)), mesh)


def revolution_bound(
    kin: Kinematics, scene: CollisionScene, q0: np.ndarray, group: SweepGroup, plan: PairPlan, cap: float
) -> RevolutionBound | None:
    """The :class:`RevolutionBound` of ``plan``'s pair in ``group``'s sweep, when one variable
    swivels and another spins its moving link (:func:`spinning_joints`), for bounds up to ``cap`` [m]."""
    spin = spinning_joints(kin, group, plan)
    if spin is None:
        return None
    moving, still = plan.links
    shapes = scene.scene_shapes(moving)
    if not shapes:
        return None
    frames = kin.link_transforms(q0[None], [moving, still])[0]
    inverse = np.linalg.inv(frames[0])
    point, direction = (v[0] for v in kin.axis(spin.spin, q0[None]))
    point_l, direction_l = inverse[:3, :3] @ point + inverse[:3, 3], inverse[:3, :3] @ direction
    support = np.concatenate([s.points for s in shapes])  # link frame
    pad = max(s.pad for s in shapes)
    if not goes_round(support, pad, point_l, direction_l):
        return None
    section = cross_section(support, pad, point_l, direction_l)
    points = polytope_points(section, point_l, direction_l)
    polytope = _hull_mesh(points)
    if not is_exact_hull(polytope):
        return None  # the engines would hold a bounded hull, which may leave some of P out
    solid = scene.backend.make(polytope)
    world = points @ frames[0][:3, :3].T + frames[0][:3, 3]
    swivel_point, swivel_direction = (v[0] for v in kin.axis(spin.swivel, q0[None]))
    radius = axis_distance(world, swivel_point, swivel_direction)
    height = (world - swivel_point) @ swivel_direction
    placed = scene.placements(still, frames[1][None])[0]
    axis = (swivel_point, swivel_direction)
    objects = []
    for shape, where in zip(scene.scene_shapes(still), placed, strict=True):
        if shape.mesh is None:
            corners = shape.points @ frames[1][:3, :3].T + frames[1][:3, 3]  # link frame to world
            if _cylinder_gaps(support_box(corners, shape.pad, *axis), radius, height)[0] < cap:
                objects.append((shape.obj, where))
            continue
        world_shape = frames[1] @ shape.pose
        triangles = shape.mesh.vertices[shape.mesh.faces] @ world_shape[:3, :3].T + world_shape[:3, 3]
        # boxed about the axis only where their world boxes meet the cylinder's (most do not)
        lo, hi = _cylinder_box(swivel_point, swivel_direction, radius, height, cap)
        near = np.flatnonzero(((triangles.min(axis=1) < hi) & (triangles.max(axis=1) > lo)).all(axis=1))
        near = near[_cylinder_gaps(triangle_boxes(triangles[near], *axis), radius, height) < cap]
        if len(near):
            objects.append((_triangles_object(scene, part_mesh(shape.mesh, near)), where))
    speed = abs(spin.multiplier) * float(radius.max())
    driver = kin.driver(spin.spin)
    assert driver is not None
    return RevolutionBound(scene, solid, objects, speed, cap, driver[0])
