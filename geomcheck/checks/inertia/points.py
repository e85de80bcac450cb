"""Each link's geometry as the family compares its inertial with it: extreme points, read once, and
their convex hulls, computed once per distinct point set.
"""

from __future__ import annotations

import hashlib

import numpy as np

from geomcheck.geometry.hull_cache import stored_hull
from geomcheck.geometry.inertia import (
    Hull,
)
from geomcheck.geometry.shapes import link_points
from geomcheck.load.meshes import MeshProblem, MeshStore
from geomcheck.model import Link, Mesh, Robot
from geomcheck.thresholds import AnalysisThresholds


def link_geometry(link: Link, meshes: MeshStore, analysis: AnalysisThresholds) -> np.ndarray | str:
    """Extreme points of every shape of ``link`` in the link frame (each mesh's hull vertices,
    each primitive's tessellation), shape (n, 3) [m], or why they cannot be used.

    One unavailable mesh makes the whole link unusable: the rest would understate its extent.
    """
    if not link.has_geometry:
        return "link has no visual or collision geometry"
    for shape in (*link.visuals, *link.collisions):
        if isinstance(shape.geometry, Mesh):
            mesh = meshes.get(shape.geometry)
            if isinstance(mesh, MeshProblem):
                return f"{shape.label} mesh unavailable: {mesh.message}"
    points = link_points(link, meshes, analysis=analysis)
    if len(points) == 0:
        return "link geometry has no vertices"
    if not np.isfinite(points).all():
        return "link geometry has non-finite vertices"
    return points


class LinkPoints:
    """Each link's geometry points (:func:`link_geometry`), read once by whichever check needs them first."""

    def __init__(self, robot: Robot, meshes: MeshStore, analysis: AnalysisThresholds) -> None:
        self._robot = robot
        self._meshes = meshes
        self._analysis = analysis
        self._points: dict[str, np.ndarray | str] = {}

    def __call__(self, name: str) -> np.ndarray | str:
        if name not in self._points:
            self._points[name] = link_geometry(self._robot.link_map[name], self._meshes, self._analysis)
        return self._points[name]


class HullMemo:
    """Convex hulls by the exact bytes of their points: links drawn alike get one hull."""

    def __init__(self) -> None:
        self._hulls: dict[bytes, Hull] = {}

    def of(self, points: np.ndarray) -> Hull:
        """The convex hull of ``points`` (n, 3) [m], computed once per distinct point set
        (and kept in the active store, :mod:`geomcheck.geometry.hull_cache`)."""
        key = hashlib.sha256(np.ascontiguousarray(points, dtype=float).tobytes()).digest()
        if key not in self._hulls:
            self._hulls[key] = stored_hull(points)
        return self._hulls[key]
