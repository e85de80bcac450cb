"""Collision geometry shared across a joint.

Some descriptions cover a link partly with an adjacent link's collision geometry: Franka's
capsule model runs each capsule from joint to joint, symmetric about the joint axis, so it
stands for both links at every joint angle. An element of a neighbour counts for a link
when the joint between them is fixed, or when the joint is revolute or continuous and the
element is invariant under rotation about the joint axis (a sphere centred on the axis, a
cylinder along it). Frames: the neighbour's elements are moved into the link's frame at
joint position zero; lengths [m].
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from geomcheck.geometry.fit import CollisionElement
from geomcheck.model import Cylinder, Robot, Sphere

ON_AXIS_M = 1e-4  # a centre this close to the joint axis is on it [m]
PARALLEL_COS = 1.0 - 1e-6  # axes this parallel are the same direction [1]
ROTATING = ("revolute", "continuous")


@dataclass(frozen=True)
class Neighbour:
    """An adjacent ``link`` across ``joint``: its frame in this link's frame (``rotation``
    (3, 3), ``translation`` (3,)), and the joint's rotation axis (unit, (3,)) through
    ``point`` (3,) in this link's frame; ``axis`` is ``None`` for a fixed joint."""

    link: str
    joint: str
    rotation: np.ndarray
    translation: np.ndarray
    axis: np.ndarray | None
    point: np.ndarray


def neighbours(robot: Robot, link: str) -> list[Neighbour]:
    """The links joined to ``link`` by a fixed, revolute or continuous joint: parent first,
    then children in document order."""
    out = []
    joints = []
    parent = robot.parent_joint.get(link)
    if parent is not None:
        joints.append((parent, parent.parent, True))
    joints.extend((j, j.child, False) for j in robot.child_joints.get(link, ()))
    for joint, other, is_parent in joints:
        if other not in robot.link_map or (joint.type != "fixed" and joint.type not in ROTATING):
            continue
        r, t = joint.origin.rotation(), np.asarray(joint.origin.xyz, dtype=float)
        axis = np.asarray(joint.axis, dtype=float)
        norm = float(np.linalg.norm(axis))
        if joint.type != "fixed" and norm == 0.0:
            continue
        if is_parent:
            # joint origin: this link's frame in the parent's; the axis is in this link's frame
            rotation, translation = r.T, -r.T @ t
            axis_here, point = axis / max(norm, 1e-12), np.zeros(3)
        else:
            rotation, translation = r, t
            axis_here, point = r @ axis / max(norm, 1e-12), t
        out.append(
            Neighbour(other, joint.name, rotation, translation, None if joint.type == "fixed" else axis_here, point)
        )
    return out


def sharing_neighbours(robot: Robot, link: str) -> list[Neighbour]:
    """:func:`neighbours`, and the links fixed to a neighbour across a moving joint, which move
    with it: Laikago's ``FL_thigh_shoulder``, fixed to the hip, carries the cylinder about the
    thigh joint that covers the thigh's motor. Each such link keeps the joint (axis and point) of
    the neighbour it is fixed to; its frame is composed along the fixed joints. Links fixed to
    ``link`` itself are one rigid body with it, and only those it is fixed to directly lend: a
    camera cluster's frames, fixed to one another, each carry a placeholder at their origin that
    would stand for the whole cluster's geometry."""
    direct = neighbours(robot, link)
    seen = {link, *(n.link for n in direct)}
    out = list(direct)
    queue = [n for n in direct if n.axis is not None]
    while queue:
        via = queue.pop(0)
        for fixed in neighbours(robot, via.link):
            if fixed.axis is not None or fixed.link in seen:
                continue
            seen.add(fixed.link)
            n = replace(
                via,
                link=fixed.link,
                rotation=via.rotation @ fixed.rotation,
                translation=via.rotation @ fixed.translation + via.translation,
            )
            out.append(n)
            queue.append(n)
    return out


def moved(element: CollisionElement, rotation: np.ndarray, translation: np.ndarray) -> CollisionElement:
    """``element`` after the rigid motion ``p -> R p + t``."""
    solid = None if element.solid is None else element.solid.moved(rotation, translation)
    return replace(
        element,
        rotation=rotation @ element.rotation,
        translation=rotation @ element.translation + translation,
        solid=solid,
        same_as_visual=False,
    )


def _on_axis(centre: np.ndarray, axis: np.ndarray, point: np.ndarray) -> bool:
    off = centre - point
    return float(np.linalg.norm(off - (off @ axis) * axis)) <= ON_AXIS_M


def invariant(element: CollisionElement, neighbour: Neighbour) -> bool:
    """Whether ``element`` (in this link's frame) is the same at every position of the joint."""
    if neighbour.axis is None:
        return True
    prim = element.primitive
    if isinstance(prim, Sphere):
        return _on_axis(element.translation, neighbour.axis, neighbour.point)
    if isinstance(prim, Cylinder):
        parallel = abs(float(element.rotation[:, 2] @ neighbour.axis)) >= PARALLEL_COS
        return parallel and _on_axis(element.translation, neighbour.axis, neighbour.point)
    return False
