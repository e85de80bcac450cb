"""Collision queries over two engines (coal, python-fcl) and the robot's collision scene."""

from geomcheck.collision.base import BACKEND_NAMES, CollisionBackend, get_backend
from geomcheck.collision.scene import CollisionScene, SceneShape, UnusableShape, adjacent_pairs

__all__ = [
    "BACKEND_NAMES",
    "CollisionBackend",
    "CollisionScene",
    "SceneShape",
    "UnusableShape",
    "adjacent_pairs",
    "get_backend",
]
