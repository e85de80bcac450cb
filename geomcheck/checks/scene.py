"""The ``scene`` section: the robot as the HTML report's 3D view draws it.

Computed at check time (the meshes and the kinematics are at hand) so that a stored report
renders without them. The robot at the default pose: every placed link's world pose, its
visual and collision elements (origin in the link frame, primitive dimensions or a mesh of
the ``meshes`` table), the frame tree that poses it for any other configuration (the view's
joint sliders, the sweeps' closest poses), and each mesh file once, decimated for display
only, quantised and packed (:mod:`geomcheck.geometry.display_mesh`) within
``thresholds.views.scene_triangles`` for the whole robot. Findings, suggested primitives and
sweeps are not repeated here: the report holds them, and the view reads them there.
``view_3d = false`` leaves the section out.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.errors import GeomcheckError
from geomcheck.geometry.display_mesh import FORMAT, DisplayMesh, display_arrays, display_from_arrays, display_mesh
from geomcheck.load.meshes import LoadedMesh, MeshProblem
from geomcheck.model import Box, Cylinder, Geometry, Link, Mesh, Pose, Shape, Sphere
from geomcheck.thresholds import ViewThresholds

MeshKey = tuple[str, tuple[float, float, float]]


def pose_dict(pose: Pose) -> dict[str, list[float]]:
    return {"xyz": [float(v) for v in pose.xyz], "rpy": [float(v) for v in pose.rpy]}


def world_pose(transform: np.ndarray) -> dict[str, list[float]]:
    """A world-from-link transform (4, 4) as ``{xyz, rpy}``, its float noise rounded away."""
    return pose_dict(Pose.composed(transform[:3, 3], transform[:3, :3]))


def mesh_targets(sizes: Mapping[MeshKey, int], params: ViewThresholds) -> dict[MeshKey, int]:
    """Triangles each mesh keeps: all of them while the robot's meshes together fit
    ``scene_triangles``, else a share of it in proportion to their size (never fewer than
    ``scene_mesh_triangles``)."""
    total = sum(sizes.values())
    if total <= params.scene_triangles:
        return dict(sizes)
    share = params.scene_triangles / total
    return {key: min(n, max(params.scene_mesh_triangles, math.floor(n * share))) for key, n in sizes.items()}


class MeshTable:
    """The section's ``meshes``: each file and scale once, in order of first use."""

    def __init__(self, ctx: CheckContext, links: list[Link]) -> None:
        self.ctx = ctx
        self.index: dict[MeshKey, int | MeshProblem] = {}
        self.entries: list[dict[str, Any]] = []
        loaded: dict[MeshKey, LoadedMesh | MeshProblem] = {}
        for link in links:
            for shape in (*link.visuals, *link.collisions):
                if isinstance(shape.geometry, Mesh):
                    key = (shape.geometry.filename, shape.geometry.scale)
                    if key not in loaded:
                        loaded[key] = ctx.meshes.get(shape.geometry)
        sizes = {key: len(m.faces) for key, m in loaded.items() if isinstance(m, LoadedMesh)}
        targets = mesh_targets(sizes, ctx.thresholds.views)
        for key, mesh in loaded.items():
            if isinstance(mesh, MeshProblem):
                self.index[key] = mesh
                continue
            shown = stored_display_mesh(mesh, key[1], targets[key])
            if shown.triangles == 0:
                self.index[key] = MeshProblem(key[0], "empty", f"mesh {mesh.path} has no triangle to draw", mesh.path)
                continue
            self.index[key] = len(self.entries)
            self.entries.append({"file": key[0], "scale": list(key[1]), **shown.to_dict()})

    def geometry(self, geometry: Geometry) -> dict[str, Any]:
        if isinstance(geometry, Box):
            return {"type": "box", "size": list(geometry.size)}
        if isinstance(geometry, Cylinder):
            return {"type": "cylinder", "radius": geometry.radius, "length": geometry.length}
        if isinstance(geometry, Sphere):
            return {"type": "sphere", "radius": geometry.radius}
        found = self.index[(geometry.filename, geometry.scale)]
        if isinstance(found, MeshProblem):
            return {"type": "mesh", "mesh": None, "problem": found.message}
        return {"type": "mesh", "mesh": found}


def stored_display_mesh(mesh: LoadedMesh, scale: tuple[float, float, float], target: int) -> DisplayMesh:
    """:func:`display_mesh` of a loaded mesh, kept in the active store by the file's content."""

    def compute() -> DisplayMesh:
        return display_mesh(mesh.vertices, mesh.faces, target)

    if not mesh.sha256:
        return compute()
    from geomcheck.cache import cached_arrays

    key = {"sha256": mesh.sha256, "scale": list(scale), "target": target, "format": FORMAT}
    return display_from_arrays(cached_arrays("display-mesh", key, lambda: display_arrays(compute())))


def element(shape: Shape, table: MeshTable) -> dict[str, Any]:
    return {"label": shape.label, "origin": pose_dict(shape.origin), "geometry": table.geometry(shape.geometry)}


def default_configuration(ctx: CheckContext) -> np.ndarray:
    """The run's default pose; the kinematic default when the pose the options ask for cannot
    be had (the self-collision family reports why)."""
    try:
        return ctx.analyses.default_configuration.copy()
    except GeomcheckError:
        return ctx.analyses.kinematics.default_configuration()


def scene_section(ctx: CheckContext) -> dict[str, Any] | None:
    """The ``scene`` section, ``None`` for a robot with no geometry to draw."""
    robot = ctx.robot
    if not any(link.has_geometry for link in robot.links):
        return None
    kin = ctx.analyses.kinematics
    q0 = default_configuration(ctx)
    world = dict(zip(kin.link_names, kin.link_transforms(q0[None])[0], strict=True)) if kin.link_names else {}
    placed = [link for link in robot.links if link.has_geometry and link.name in world]
    table = MeshTable(ctx, placed)
    frames = [
        {
            "frame": f.frame,
            "parent": f.parent,
            "joint": f.joint.name,
            "origin": pose_dict(f.joint.origin),
            "motion": f.motion,
            "axis": [float(v) for v in f.axis],
            "variable": f.variable,
            "multiplier": f.multiplier,
            "offset": f.offset,
        }
        for f in kin.frame_tree()
    ]
    variables = [
        {"joint": j.name, "type": j.type, "lower": float(lo), "upper": float(hi), "value": float(v)}
        for j, lo, hi, v in zip(kin.joints, kin.lower, kin.upper, q0, strict=True)
    ]
    links = [
        {
            "link": link.name,
            "pose": world_pose(world[link.name]),
            "visuals": [element(s, table) for s in link.visuals],
            "collisions": [element(s, table) for s in link.collisions],
        }
        for link in placed
    ]
    unplaced = [link.name for link in robot.links if link.has_geometry and link.name not in world]
    return {
        "root": kin.root,
        "frames": frames,
        "variables": variables,
        "links": links,
        "meshes": table.entries,
        "unplaced": unplaced,
    }


def run(ctx: CheckContext) -> FamilyResult:
    if not ctx.options.view_3d:
        return FamilyResult()
    section = scene_section(ctx)
    return FamilyResult(sections={"scene": section} if section is not None else {})
