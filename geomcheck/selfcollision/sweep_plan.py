"""What a continuous-joint sweep moves and how fast: groups, round wheels, pairs, bounds.

A sweep turns one continuous joint (the *primary*) over a full turn with the rest of the
robot at the default pose. Continuous joints *directly below* it (reached from its child
link through fixed joints only: a caster's wheels) turn too:

* a child whose collision geometry is round about its own axis (a cylinder on the axis, a
  sphere centred on it: the usual wheel) occupies the same space at every angle, so the
  primary's sweep with the child at its default angle is exact for every child angle;
* any other child becomes an extra dimension of the sweep (the joint space is a torus and
  is searched as such), so the result is exact for every combination of angles.

Pairs are every two links whose relative pose the sweep changes, *including* MoveIt's
Adjacent pairs: a caster housing is the base's child, and whether it clips the base as it
turns is the very question. For an adjacent pair only a contact that depends on the angle
is a finding; one over the whole turn is the joint's own overlap.

Each child also gets a sweep of its own; it checks only the pairs *inside* the primary's
moving subtree (a wheel against its sibling wheel, the caster housing), as the primary's
sweep covers the pairs with everything outside. Pairs inside the subtree that non-round
children move are also in the primary's sweep, over every combination of their angles.

Speed bound: when the swept joints turn by ``dtheta`` (per dimension), no point of a link
moves further than ``sum_d L[d] * |dtheta_d|`` with ``L[d]`` the largest distance [m] from
the axis of any joint driven by dimension ``d`` on the link's path (times the mimic
multiplier), taken over every angle of the joints below it. That bound makes the sweep's
clearance proofs between samples sound.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from geomcheck.collision.scene import RIM_POINTS, CollisionScene
from geomcheck.kinematics import Kinematics
from geomcheck.model import Cylinder, Joint, Sphere

ON_AXIS_M = 1e-9  # a centre this close to an axis is on it [m]
PARALLEL = 1e-9  # |sin| of the angle between two axes below this: parallel [ratio]


@dataclass(frozen=True)
class SweepGroup:
    """One sweep: ``joint`` turned with ``children`` (continuous joints directly below it);
    ``dimensions`` are the variables searched (the joint and its non-round children);
    ``scope`` is the link set both links of a pair must lie in (``None``: the whole robot)."""

    joint: Joint
    children: tuple[Joint, ...]
    dimensions: tuple[str, ...]
    scope: frozenset[str] | None
    round: bool = False  # the moving geometry is the same at every angle (a wheel spinning on its axis)


@dataclass(frozen=True)
class PairPlan:
    """A link pair whose relative pose changes in a sweep, with the bound of its relative speed."""

    links: tuple[str, str]  # (moving link, other link): the first one moves
    speed: np.ndarray  # (n_dims,) [m/rad]: relative displacement bound per radian of each dimension
    far_bound: float  # a lower bound of the pair's distance over the whole sweep [m]
    adjacent: bool  # MoveIt's Adjacent (only contacts that depend on the angle are findings)
    both_move: bool  # the second link moves too (else it stays at the default pose)

    @property
    def constant(self) -> bool:
        """The pair's distance is the same at every angle: nothing moves at a nonzero speed."""
        return not self.speed.any()


def fixed_descendants(kin: Kinematics, link: str) -> list[str]:
    """``link`` and the links reached from it through fixed (non-moving) joints only."""
    out, frontier = [link], [link]
    while frontier:
        for j in kin.child_joints(frontier.pop()):
            if kin.driver(j) is None:
                out.append(j.child)
                frontier.append(j.child)
    return out


def continuous_children(kin: Kinematics, joint: Joint) -> tuple[Joint, ...]:
    """Continuous variables directly below ``joint`` (through fixed joints only), document order."""
    variables = {j.name for j in kin.joints}
    below = fixed_descendants(kin, joint.child)
    found = {j.name for link in below for j in kin.child_joints(link) if j.type == "continuous" and j.name in variables}
    return tuple(j for j in kin.joints if j.name in found)


def is_round(kin: Kinematics, scene: CollisionScene, joint: Joint, q0: np.ndarray) -> bool:
    """Whether the collision geometry below ``joint`` is the same at every angle of it: only fixed
    joints below, and every shape a sphere centred on the axis or a cylinder along it."""
    links = kin.subtree(joint.child)
    if any(kin.driver(j) is not None for link in links for j in kin.child_joints(link)):
        return False
    point, direction = (v[0] for v in kin.axis(joint, q0[None]))
    frames = kin.link_transforms(q0[None])[0]
    for link in links:
        for shape in scene.scene_shapes(link):
            world = frames[kin.link_index(link)] @ shape.pose
            on_axis = bool(np.linalg.norm(np.cross(world[:3, 3] - point, direction)) < ON_AXIS_M)
            round_shape = False
            if isinstance(shape.shape.geometry, Sphere):
                round_shape = on_axis
            elif isinstance(shape.shape.geometry, Cylinder):
                round_shape = on_axis and bool(np.linalg.norm(np.cross(world[:3, 2], direction)) < PARALLEL)
            if not round_shape:
                return False
    return True


def sweep_groups(kin: Kinematics, scene: CollisionScene, q0: np.ndarray) -> tuple[SweepGroup, ...]:
    """One group per continuous variable joint of the tree, in document order."""
    continuous = [j for j in kin.joints if j.type == "continuous" and kin.parent_joint(j.child) is j]
    children = {j.name: continuous_children(kin, j) for j in continuous}
    parent_of = {c.name: j for j in continuous for c in children[j.name]}
    out = []
    for joint in continuous:
        kids = children[joint.name]
        extra = tuple(c.name for c in kids if not is_round(kin, scene, c, q0))
        parent = parent_of.get(joint.name)
        scope = frozenset(kin.subtree(parent.child)) if parent is not None else None
        out.append(SweepGroup(joint, kids, (joint.name, *extra), scope, is_round(kin, scene, joint, q0)))
    return tuple(out)


def _perpendicular_basis(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.array([1.0, 0.0, 0.0]) if abs(direction[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(direction, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(direction, u)


def axis_distance(points: np.ndarray, point: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Distances [m] of ``points`` (n, 3) from the line through ``point`` along the unit ``direction``."""
    return np.linalg.norm(np.cross(points - point, direction), axis=1)


def swept_support(points: np.ndarray, pad: float, point: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, float]:
    """Support (points, pad) of everything ``points`` (+ ``pad``) covers turning a full turn about
    the axis: the cylinder around the axis spanning their axial extent and largest radius."""
    rel = points - point
    axial = rel @ direction
    radius = float(axis_distance(points, point, direction).max()) + pad
    u, v = _perpendicular_basis(direction)
    t = np.linspace(0.0, 2 * np.pi, RIM_POINTS, endpoint=False)
    ring = radius * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)
    ends = [point + (a * direction) for a in (axial.min() - pad, axial.max() + pad)]
    return np.concatenate([end + ring for end in ends]), radius * float(1.0 - np.cos(np.pi / RIM_POINTS))


@dataclass(frozen=True)
class LinkMotion:
    """How a link moves in a sweep: its speed bound per dimension and a bound of the space it sweeps."""

    speed: np.ndarray  # (n_dims,) [m/rad]
    sphere: tuple[np.ndarray, float]  # world sphere holding the link at every sweep angle
    circle: tuple[np.ndarray, np.ndarray, np.ndarray, float] | None  # (axis point, dir, centre, radius):
    # set when one joint moves the link: its bounding sphere's centre runs on a circle


def link_motion(
    kin: Kinematics,
    scene: CollisionScene,
    link: str,
    dims: tuple[str, ...],
    frames: np.ndarray,
    axes: dict[str, tuple[np.ndarray, np.ndarray]],
) -> LinkMotion:
    """Speed bound and swept-space bound of ``link`` when the variables ``dims`` turn, the rest at
    the default pose (``frames``: world-from-link (n_links, 4, 4) and ``axes``: tree joint axes there)."""
    world = frames[kin.link_index(link)]
    centre, radius = scene.bounding_sphere(link)
    centre = world[:3, :3] @ centre + world[:3, 3]
    supports = [(s.points @ world[:3, :3].T + world[:3, 3], s.pad) for s in scene.scene_shapes(link)]
    speed = np.zeros(len(dims))
    instances = []
    for joint in reversed(kin.root_path(link)):  # from the link up to the root
        driver = kin.driver(joint)
        if driver is None or driver[0] not in dims:
            continue
        point, direction = axes[joint.name]
        reach = max(float(axis_distance(p, point, direction).max()) + pad for p, pad in supports)
        speed[dims.index(driver[0])] += abs(driver[1]) * reach
        supports = [swept_support(p, pad, point, direction) for p, pad in supports]
        instances.append((point, direction))
    circle = None
    if len(instances) == 1:
        point, direction = instances[0]
        circle = (point, direction, centre, radius)
    sphere_centre, sphere_radius = centre, radius
    for point, direction in instances:
        foot = point + ((sphere_centre - point) @ direction) * direction
        sphere_radius += float(np.linalg.norm(sphere_centre - foot))
        sphere_centre = foot
    return LinkMotion(speed, (sphere_centre, sphere_radius), circle)


def _circle_distance(circle: tuple[np.ndarray, np.ndarray, np.ndarray, float], target: np.ndarray) -> float:
    """Distance [m] from ``target`` to the circle run by the centre of a turning sphere."""
    point, direction, centre, _ = circle
    rel_c, rel_t = centre - point, target - point
    h_c, h_t = rel_c @ direction, rel_t @ direction
    r_c = float(np.linalg.norm(rel_c - h_c * direction))
    r_t = float(np.linalg.norm(rel_t - h_t * direction))
    return float(np.hypot(r_t - r_c, h_t - h_c))


def far_bound(a: LinkMotion, b: LinkMotion, b_static: bool) -> float:
    """A lower bound [m] of the distance between two links over the whole sweep."""
    (ca, ra), (cb, rb) = a.sphere, b.sphere
    bound = float(np.linalg.norm(ca - cb)) - ra - rb
    if b_static and a.circle is not None:
        bound = max(bound, _circle_distance(a.circle, cb) - a.circle[3] - rb)
    return bound


def plan_pairs(
    kin: Kinematics,
    scene: CollisionScene,
    group: SweepGroup,
    q0: np.ndarray,
    adjacent: Iterable[tuple[str, str]],
) -> tuple[tuple[str, ...], list[PairPlan]]:
    """The links that move in the sweep (with collision geometry or not) and every link pair whose
    relative pose it changes, inside the group's scope. Adjacent pairs are kept (flagged): a
    caster housing is the base's child, and whether it clips the base is the sweep's question."""
    dims = group.dimensions
    adjacent_set = set(adjacent)
    moving_all = tuple(
        link for link in kin.link_names if any((kin.driver(j) or ("",))[0] in dims for j in kin.root_path(link))
    )
    frames = kin.link_transforms(q0[None])[0]
    axes = kin.tree_axes(q0)
    usable = [link for link in scene.links if link in kin.link_names]
    motions = {link: link_motion(kin, scene, link, dims, frames, axes) for link in usable}
    moving = set(moving_all)
    pairs = []
    for i, a in enumerate(usable):
        for b in usable[i + 1 :]:
            if group.scope is not None and not (a in group.scope and b in group.scope):
                continue
            if not set(kin.path_joints(a, b)) & set(dims):
                continue  # rigid with respect to each other in this sweep
            first, second = (a, b) if a in moving else (b, a)
            ma, mb = motions[first], motions[second]
            bound = far_bound(ma, mb, second not in moving)
            is_adjacent = (a, b) in adjacent_set or (b, a) in adjacent_set
            both = second in moving
            # a round moving set against a still link: the occupied space never changes
            speed = np.zeros(len(dims)) if group.round and not both else ma.speed + mb.speed
            pairs.append(PairPlan((first, second), speed, bound, is_adjacent, both))
    return moving_all, pairs
