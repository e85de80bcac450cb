"""The kinematic chain between two links, in the frame of their lowest common ancestor.

A pair's relative pose depends only on the joints on the tree path between the two links;
certification bounds it over their ranges and the witness search moves only them. A chain
is evaluated directly (a few small matrix products), much cheaper than the whole robot's
forward kinematics. Trees, mimic folding and ranges are those of :class:`Kinematics`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from geomcheck.collision.scene import CollisionScene
from geomcheck.kinematics import VARIABLE_TYPES, Kinematics, rotation_matrices
from geomcheck.model import Cylinder, Shape, Sphere

REVOLUTE, PRISMATIC = 0, 1

# joint name -> (variable name, multiplier, offset): value = multiplier * q[variable] + offset
Drivers = Mapping[str, tuple[str, float, float]]


def drivers(kin: Kinematics) -> dict[str, tuple[str, float, float]]:
    """The variable that drives each moving joint of ``kin``: itself, or a mimic's leader
    (chains of mimics folded, as :class:`Kinematics` does)."""
    variables = {j.name for j in kin.joints}
    out = {name: (name, 1.0, 0.0) for name in variables}
    joint_map = kin.robot.joint_map
    for joint in kin.robot.joints:
        if joint.name in variables or joint.mimic is None or joint.type not in VARIABLE_TYPES:
            continue
        mult, off, current, seen = 1.0, 0.0, joint, {joint.name}
        while current.mimic is not None and current.name not in variables:
            leader = joint_map.get(current.mimic.joint)
            if leader is None or leader.name in seen or leader.type not in VARIABLE_TYPES:
                break
            mult, off = mult * current.mimic.multiplier, mult * current.mimic.offset + off
            seen.add(leader.name)
            current = leader
        if current is not joint and current.name in variables:
            out[joint.name] = (current.name, mult, off)
    return out


def joint_ranges(kin: Kinematics) -> dict[str, tuple[float, float]]:
    """``(lower, upper)`` ([rad] or [m]) of every joint that moves in ``kin``: the limits of
    its variables, and for a mimic joint the image of its leader's range."""
    limits = {j.name: (float(lo), float(hi)) for j, lo, hi in zip(kin.joints, kin.lower, kin.upper, strict=True)}
    out = {}
    for joint, (variable, mult, off) in drivers(kin).items():
        lo, hi = limits[variable]
        ends = sorted((mult * lo + off, mult * hi + off))
        out[joint] = (ends[0], ends[1])
    return out


@dataclass(frozen=True)
class Step:
    """One moving joint on a chain: motion ``kind`` (REVOLUTE or PRISMATIC) along the unit
    ``axis`` (3,) of the joint frame over ``[lower, upper]`` ([rad] or [m]); its value is
    ``multiplier * q[variable] + offset`` (``variable`` indexes the configuration)."""

    joint: str
    kind: int
    axis: np.ndarray
    lower: float
    upper: float
    variable: int
    multiplier: float
    offset: float


@dataclass(frozen=True)
class Chain:
    """Path from an ancestor frame down to a link: moving ``steps`` top-down, and the rigid
    transforms around them: ``fixed[i]`` (4, 4) sits above ``steps[i]`` (after the previous
    step's motion); ``fixed[-1]`` leads to the link frame. ``len(fixed) == len(steps) + 1``."""

    steps: tuple[Step, ...]
    fixed: tuple[np.ndarray, ...]

    @functools.cached_property
    def _factors(self) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]:
        """Per step, (F0, F1, F2) (4, 4) with ``motion(v) @ after = F0 + sin(v) F1 + (1 - cos(v)) F2``
        for a rotation (Rodrigues) and ``F0 + v F1`` for a translation."""
        out = []
        for step, after in zip(self.steps, self.fixed[1:], strict=True):
            g1, g2 = np.zeros((4, 4)), np.zeros((4, 4))
            if step.kind == PRISMATIC:
                g1[:3, 3] = step.axis
            else:
                x, y, z = step.axis
                k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
                g1[:3, :3], g2[:3, :3] = k, k @ k
            out.append((after, g1 @ after, g2 @ after))
        return tuple(out)

    def transform_and_joints(self, q: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        """For one configuration ``q`` (n_joints,): the ancestor-from-link transform (4, 4) and,
        per step, the ancestor-from-joint transform (4, 4) before the step's motion (the joint's
        axis and origin in the ancestor frame)."""
        out, joints = self.fixed[0], []
        for step, (f0, f1, f2) in zip(self.steps, self._factors, strict=True):
            joints.append(out)
            v = step.multiplier * float(q[step.variable]) + step.offset
            if step.kind == PRISMATIC:
                out = out @ (f0 + v * f1)
            else:
                out = out @ (f0 + math.sin(v) * f1 + (1.0 - math.cos(v)) * f2)
        return out, joints

    def transforms(self, q: np.ndarray) -> np.ndarray:
        """Ancestor-from-link transforms for configurations ``q`` (b, n_joints): (b, 4, 4)."""
        b = q.shape[0]
        out = np.broadcast_to(self.fixed[0], (b, 4, 4)).copy()
        for step, after in zip(self.steps, self.fixed[1:], strict=True):
            value = step.multiplier * q[:, step.variable] + step.offset
            motion = np.broadcast_to(np.eye(4), (b, 4, 4)).copy()
            if step.kind == PRISMATIC:
                motion[:, :3, 3] = value[:, None] * step.axis
            else:
                motion[:, :3, :3] = rotation_matrices(step.axis, value)
            out = out @ motion @ after
        return out


def ancestors(kin: Kinematics, link: str) -> list[str]:
    """``link`` and the frames above it up to the root of ``kin``'s tree, bottom-up."""
    out = [link]
    while (joint := kin.parent_joint(out[-1])) is not None:
        out.append(joint.parent)
    return out


def common_ancestor(kin: Kinematics, a: str, b: str) -> str:
    """The lowest frame at or above both links (both must be in ``kin``'s tree)."""
    above_b = set(ancestors(kin, b))
    return next(x for x in ancestors(kin, a) if x in above_b)


def _unit(axis: tuple[float, float, float]) -> np.ndarray | None:
    a = np.asarray(axis, dtype=float)
    n = float(np.linalg.norm(a))
    return a / n if n > 0 else None


def chain(kin: Kinematics, ancestor: str, link: str, driven: Drivers | None = None) -> Chain:
    """The chain from ``ancestor`` down to ``link`` in ``kin``'s tree. Joints driven by a
    variable move (see :func:`drivers`); others (fixed joints, planar/floating roots held at
    their origin, a zero axis) are rigid at their ``<origin>``."""
    driven = drivers(kin) if driven is None else driven
    ranges = {j.name: (float(lo), float(hi)) for j, lo, hi in zip(kin.joints, kin.lower, kin.upper, strict=True)}
    joints = []
    current = link
    while current != ancestor:
        joint = kin.parent_joint(current)
        if joint is None:
            raise ValueError(f"{ancestor!r} is not above {link!r}")
        joints.append(joint)
        current = joint.parent
    steps: list[Step] = []
    fixed: list[np.ndarray] = []
    pending = np.eye(4)
    for joint in reversed(joints):
        pending = pending @ joint.origin.matrix()
        axis = _unit(joint.axis)
        if joint.name not in driven or axis is None:
            continue
        variable, mult, off = driven[joint.name]
        lo, hi = ranges[variable]
        ends = sorted((mult * lo + off, mult * hi + off))
        kind = PRISMATIC if joint.type == "prismatic" else REVOLUTE
        steps.append(Step(joint.name, kind, axis, ends[0], ends[1], kin.index(variable), mult, off))
        fixed.append(pending)
        pending = np.eye(4)
    fixed.append(pending)
    return Chain(tuple(steps), tuple(fixed))


@dataclass(frozen=True)
class PairPath:
    """The two chains of a link pair from their common ancestor, and the variables
    (configuration indices, sorted) whose values change the pair's relative pose."""

    first: Chain
    second: Chain
    variables: tuple[int, ...]

    @property
    def rigid(self) -> bool:
        return not self.variables

    def transforms(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Ancestor-from-link transforms of both links for ``q`` (b, n_joints): two (b, 4, 4)."""
        return self.first.transforms(q), self.second.transforms(q)


def pair_path(kin: Kinematics, a: str, b: str, driven: Drivers | None = None) -> PairPath:
    """The :class:`PairPath` of links ``a`` and ``b``."""
    driven = drivers(kin) if driven is None else driven
    top = common_ancestor(kin, a, b)
    first, second = chain(kin, top, a, driven), chain(kin, top, b, driven)
    variables = sorted({s.variable for s in (*first.steps, *second.steps)})
    return PairPath(first, second, tuple(variables))


def _on_axis(point: np.ndarray, axis: np.ndarray, tol: float = 1e-9) -> bool:
    return bool(np.linalg.norm(point - (point @ axis) * axis) <= tol)


def symmetric_variables(kin: Kinematics, scene: CollisionScene) -> frozenset[int]:
    """Configuration indices of the revolute variables that cannot change any distance: the
    joint's child link is the only link of its subtree with collision geometry, and every one
    of its shapes is a sphere centred on the joint axis or a cylinder around it (a wheel
    spinning on its axle). Such a variable can be held at any value."""
    driven = drivers(kin)
    leaders = {v for j, (v, _, _) in driven.items() if j != v}  # variables that also drive mimics
    with_geometry = set(scene.links)
    out = set()
    for joint in kin.joints:
        if joint.type not in ("revolute", "continuous") or joint.name in leaders:
            continue
        axis = _unit(joint.axis)
        below = kin.subtree(joint.child)
        if axis is None or any(link in with_geometry for link in below[1:]):
            continue
        shapes = scene.scene_shapes(joint.child)
        if shapes and all(_symmetric(s.shape, axis) for s in shapes):
            out.add(kin.index(joint.name))
    return frozenset(out)


def _symmetric(shape: Shape, axis: np.ndarray) -> bool:
    """Whether ``shape`` (in its link frame) is unchanged by rotations about the line through
    the origin along the unit ``axis``."""
    pose = shape.origin.matrix()
    centre = pose[:3, 3]
    if isinstance(shape.geometry, Sphere):
        return _on_axis(centre, axis)
    if isinstance(shape.geometry, Cylinder):
        along = pose[:3, 2]
        return bool(np.linalg.norm(np.cross(along, axis)) <= 1e-9) and _on_axis(centre, axis)
    return False
