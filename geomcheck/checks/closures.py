"""The links a loop-closing constraint holds against a link, as neighbours at rest.

A closed linkage (MJCF ``<equality><connect>``: a gripper's inner knuckle pinned to its finger,
a leg's push rod pinned to the foot it drives) keeps its two links together as a joint does: the
collision geometry of one stands next to the other at every position the linkage takes, so the
fit family counts it among the link's neighbours at rest (joint positions zero, the pose the
description is written in). Frames: the partner's frame in the link's frame [m].
"""

from __future__ import annotations

import numpy as np

from geomcheck.geometry.neighbours import Neighbour
from geomcheck.model import Robot

CLOSURE = "closure"  # the joint name a closure neighbour carries: no joint joins the two


def rest_pose(robot: Robot, link: str) -> tuple[np.ndarray, np.ndarray]:
    """``link``'s frame in its tree root's frame at joint positions zero: rotation (3, 3),
    translation (3,)."""
    rotation, translation = np.eye(3), np.zeros(3)
    seen = {link}
    while link in robot.parent_joint:
        joint = robot.parent_joint[link]
        r, t = joint.origin.rotation(), np.asarray(joint.origin.xyz, dtype=float)
        rotation, translation = r @ rotation, r @ translation + t
        link = joint.parent
        if link in seen:  # a cycle (GC116): no root to stand on
            break
        seen.add(link)
    return rotation, translation


def closure_neighbours(robot: Robot, link: str) -> list[Neighbour]:
    """The links ``robot.closures`` pairs with ``link``, each with its frame in ``link``'s at rest;
    ``axis`` ``None``: the constraint lends no element invariant under a motion."""
    partners = [b if a == link else a for a, b in robot.closures if link in (a, b)]
    if not partners:
        return []
    here_r, here_t = rest_pose(robot, link)
    out = []
    for other in dict.fromkeys(partners):
        if other == link or other not in robot.link_map:
            continue
        r, t = rest_pose(robot, other)
        out.append(Neighbour(other, CLOSURE, here_r.T @ r, here_r.T @ (t - here_t), None, np.zeros(3)))
    return out
