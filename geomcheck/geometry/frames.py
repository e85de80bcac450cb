"""Rigid frames: URDF roll-pitch-yaw, rotations between axes, and moving points between frames.

Rotations are (3, 3) matrices whose columns are the frame's axes in the parent frame;
points are (n, 3) arrays [m]; angles [rad].
"""

from __future__ import annotations

import itertools

import numpy as np

from geomcheck.model import Pose  # re-exported: the pose module's inverse


def rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation (3, 3) turning unit vector ``a`` (3,) onto unit vector ``b`` (3,)."""
    a = np.asarray(a, dtype=float) / np.linalg.norm(a)
    b = np.asarray(b, dtype=float) / np.linalg.norm(b)
    cross = np.cross(a, b)
    s, c = float(np.linalg.norm(cross)), float(np.dot(a, b))
    if s < 1e-12:
        if c > 0.0:
            return np.eye(3)
        # half turn about any axis perpendicular to a
        helper = np.eye(3)[int(np.argmin(np.abs(a)))]
        axis = np.cross(a, helper)
        axis /= np.linalg.norm(axis)
        return 2.0 * np.outer(axis, axis) - np.eye(3)
    k = cross / s
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * kx + (1.0 - c) * (kx @ kx)


def rotation_angle(rotation: np.ndarray) -> float:
    """Angle [rad] of ``rotation`` (3, 3) about its axis, in [0, pi]."""
    return float(np.arccos(np.clip((np.trace(rotation) - 1.0) / 2.0, -1.0, 1.0)))


def times(points: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """``points @ matrix`` for points (n, 3) and a (3, m) matrix, summed in one fixed order
    element by element: a BLAS kernel sums the three products in an order of its own, and a
    point on a pixel's edge or a part's boundary must fall on the same side on every CPU."""
    p = np.asarray(points, dtype=float)
    m = np.asarray(matrix, dtype=float)
    return p[:, 0:1] * m[0] + p[:, 1:2] * m[1] + p[:, 2:3] * m[2]


def to_frame(points: np.ndarray, rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """``points`` (n, 3) given in a parent frame, expressed in the child frame at
    ``translation`` (3,) with axes ``rotation`` (3, 3): ``R^T (p - t)``."""
    return times(np.asarray(points, dtype=float) - translation, rotation)


def from_frame(points: np.ndarray, rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """``points`` (n, 3) given in a child frame, expressed in the parent: ``R p + t``."""
    return times(points, np.asarray(rotation, dtype=float).T) + translation


def pose_frame(pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """``(rotation (3, 3), translation (3,))`` of a URDF ``<origin>``."""
    return pose.rotation(), np.asarray(pose.xyz, dtype=float)


def _proper_signed_permutations() -> np.ndarray:
    mats = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1.0, -1.0), repeat=3):
            m = np.zeros((3, 3))
            m[list(perm), [0, 1, 2]] = signs
            if np.linalg.det(m) > 0:
                mats.append(m)
    return np.array(mats)


SIGNED_PERMUTATIONS = _proper_signed_permutations()  # (24, 3, 3): a box's symmetries up to relabelling


def canonical_box_frame(rotation: np.ndarray, size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The same box (``rotation`` (3, 3), edge lengths ``size`` (3,)) with its axes relabelled
    and flipped so the rotation is the one closest to identity: the simplest ``rpy``."""
    candidates = rotation @ SIGNED_PERMUTATIONS  # (24, 3, 3)
    best = int(np.argmax(np.trace(candidates, axis1=1, axis2=2)))
    perm = SIGNED_PERMUTATIONS[best]
    new_size = np.abs(perm.T) @ np.asarray(size, dtype=float)
    return candidates[best], new_size


def snap_rotation(rotation: np.ndarray, tolerance: float = 1e-6) -> np.ndarray:
    """``rotation`` with entries within ``tolerance`` of 0 or +-1 snapped, so axis-aligned
    frames print as exact multiples of pi/2."""
    r = np.asarray(rotation, dtype=float).copy()
    for target in (0.0, 1.0, -1.0):
        r[np.abs(r - target) < tolerance] = target
    return r
