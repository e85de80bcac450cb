"""Collision queries over two engines (coal, python-fcl) and the robot's collision scene."""

from geomcheck.collision.backends import BACKEND_NAMES, get_backend
from geomcheck.collision.base import CollisionBackend
from geomcheck.collision.scene import CollisionScene, SceneShape, UnusableShape
from geomcheck.collision.topology import (
    SEMANTICS,
    adjacent_pairs,
    excluded_pairs,
    fixed_joints_between,
    rigid_pairs,
)

__all__ = [
    "BACKEND_NAMES",
    "SEMANTICS",
    "CollisionBackend",
    "CollisionScene",
    "SceneShape",
    "UnusableShape",
    "adjacent_pairs",
    "excluded_pairs",
    "fixed_joints_between",
    "get_backend",
    "rigid_pairs",
]
