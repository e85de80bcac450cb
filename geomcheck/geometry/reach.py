"""Rigid groups of a robot and convex bounds of the space its moving bodies sweep.

A rigid group is a set of links joined by fixed joints: they never move relative to each
other. Every other group hangs below a chain of moving joints; the space it can occupy, over
every joint position, is bounded by sweeping its collision geometry's convex bound through
that chain, joint by joint towards the root: a revolute or continuous joint turns the bound
into the cylinder of revolution about its axis (a full turn, whatever the limits), a
prismatic joint stretches it along its axis over its limits. Each step keeps a convex point
set whose hull contains the exact sweep (distances to an axis and along it are convex, so
their extremes over a convex set are at its vertices). A floating or planar joint, or a
prismatic one without limits, reaches anywhere: no bound. Frames: every pose is the link's
frame in its group's anchor (the group's link nearest the root); lengths [m].
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from geomcheck.geometry.elements import CollisionElement
from geomcheck.geometry.primitives import half_extents
from geomcheck.model import Limit, Robot

RING_SIDES = 16  # sides of the polygon circumscribing a swept circle [count]
REVOLVING = ("revolute", "continuous")


@dataclass(frozen=True)
class RigidGroups:
    """``anchor``: each link's group, named by its link nearest the root; ``pose``: each link's
    frame in its anchor's frame, ``(rotation (3, 3), translation (3,))``."""

    anchor: Mapping[str, str]
    pose: Mapping[str, tuple[np.ndarray, np.ndarray]]

    def members(self, anchor: str) -> list[str]:
        """The links of the group anchored at ``anchor``, in document order of discovery."""
        return [link for link, a in self.anchor.items() if a == anchor]


def rigid_groups(robot: Robot) -> RigidGroups:
    """The rigid groups of ``robot``'s tree (links it cannot reach from a root are left out)."""
    anchor: dict[str, str] = {}
    pose: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    todo = [link.name for link in robot.links if link.name not in robot.parent_joint]
    for root in todo:
        anchor[root], pose[root] = root, (np.eye(3), np.zeros(3))
    while todo:
        link = todo.pop()
        for joint in robot.child_joints.get(link, ()):
            child = joint.child
            if child in anchor or child not in robot.link_map:
                continue
            if joint.type == "fixed":
                rotation, translation = pose[link]
                r, t = joint.origin.rotation(), np.asarray(joint.origin.xyz, dtype=float)
                anchor[child], pose[child] = anchor[link], (rotation @ r, rotation @ t + translation)
            else:
                anchor[child], pose[child] = child, (np.eye(3), np.zeros(3))
            todo.append(child)
    return RigidGroups(anchor, pose)


def element_corners(element: CollisionElement) -> np.ndarray:
    """Points (k, 3) in the element's link frame whose convex hull contains the element."""
    if element.primitive is not None:
        h = half_extents(element.primitive)
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
        return (signs * h) @ np.asarray(element.rotation, dtype=float).T + np.asarray(element.translation, dtype=float)
    if element.solid is None:
        return np.zeros((0, 3))
    return element.solid.vertices if element.solid.hull is None else element.solid.hull.vertices


def _unit(axis: tuple[float, float, float]) -> np.ndarray | None:
    a = np.asarray(axis, dtype=float)
    norm = float(np.linalg.norm(a))
    return None if norm == 0.0 else a / norm


def _travel(limit: Limit | None) -> tuple[float, float] | None:
    """A prismatic joint's ``(lower, upper)`` travel [m], or ``None`` when unbounded."""
    if limit is None or limit.lower is None or limit.upper is None:
        return None
    return float(limit.lower), float(limit.upper)


def revolved(points: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Vertices (2 * RING_SIDES, 3) of a prism containing ``points`` (n, 3) turned a full turn
    about ``axis`` (unit, (3,)) through the origin: the solid of revolution's bounding cylinder."""
    along = points @ axis
    radial = float(np.linalg.norm(points - np.outer(along, axis), axis=1).max())
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    angles = np.linspace(0.0, 2.0 * np.pi, RING_SIDES, endpoint=False)
    ring = (radial / np.cos(np.pi / RING_SIDES)) * (np.outer(np.cos(angles), u) + np.outer(np.sin(angles), v))
    return np.concatenate([ring + along.min() * axis, ring + along.max() * axis])


def swept_bound(robot: Robot, groups: RigidGroups, anchor: str, points: np.ndarray) -> tuple[str, np.ndarray] | None:
    """``(root, bound)``: the root anchor of ``anchor``'s tree, and points (k, 3) in its frame
    whose convex hull contains ``points`` (n, 3, in ``anchor``'s frame) at every position of
    the joints between the two groups; ``None`` when one of them reaches anywhere."""
    pts = np.asarray(points, dtype=float)
    current = anchor
    while current in robot.parent_joint:
        joint = robot.parent_joint[current]
        axis = _unit(joint.axis)
        if joint.type in REVOLVING and axis is not None:
            pts = revolved(pts, axis)
        elif joint.type == "prismatic" and axis is not None and (travel := _travel(joint.limit)) is not None:
            pts = np.concatenate([pts + travel[0] * axis, pts + travel[1] * axis])
        elif joint.type != "fixed":
            return None
        pts = pts @ joint.origin.rotation().T + np.asarray(joint.origin.xyz, dtype=float)
        if joint.parent not in groups.anchor:
            return None
        rotation, translation = groups.pose[joint.parent]
        pts = pts @ rotation.T + translation
        current = groups.anchor[joint.parent]
    return current, pts


__all__ = ["RING_SIDES", "RigidGroups", "element_corners", "revolved", "rigid_groups", "swept_bound"]
