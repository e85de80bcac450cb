"""Random rigid placements for the collision tests."""

from __future__ import annotations

import numpy as np
import trimesh


def random_pose(rng: np.random.Generator, reach: float) -> np.ndarray:
    """A (4, 4) homogeneous transform: a uniformly random rotation and a translation in [-reach, reach]^3 [m]."""
    m = np.eye(4)
    q = rng.normal(size=4)
    m[:3, :3] = trimesh.transformations.quaternion_matrix(q / np.linalg.norm(q))[:3, :3]
    m[:3, 3] = rng.uniform(-reach, reach, size=3)
    return m
