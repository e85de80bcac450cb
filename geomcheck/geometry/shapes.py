"""Shapes of a link as triangle meshes in the link frame.

Primitives are tessellated (cylinders and spheres finely enough for bounds, not for exact
distances: exact distances to primitives live in :mod:`geomcheck.geometry.primitives`).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import trimesh

from geomcheck.load.meshes import MeshProblem, MeshStore
from geomcheck.model import Box, Cylinder, Geometry, Link, Mesh, Shape, Sphere

CYLINDER_SECTIONS = 64  # tessellation of primitive cylinders [segments per turn]
SPHERE_SUBDIVISIONS = 3  # icosphere subdivisions for primitive spheres


def primitive_mesh(geometry: Box | Cylinder | Sphere) -> trimesh.Trimesh:
    """A primitive as a mesh in its own frame (centred, cylinder along z), lengths [m]."""
    if isinstance(geometry, Box):
        return trimesh.creation.box(extents=np.asarray(geometry.size, dtype=float))
    if isinstance(geometry, Cylinder):
        return trimesh.creation.cylinder(radius=geometry.radius, height=geometry.length, sections=CYLINDER_SECTIONS)
    return trimesh.creation.icosphere(subdivisions=SPHERE_SUBDIVISIONS, radius=geometry.radius)


def geometry_mesh(geometry: Geometry, meshes: MeshStore) -> trimesh.Trimesh | MeshProblem:
    """The geometry as a mesh in its own frame (mesh ``scale`` applied), or why it is unavailable."""
    if isinstance(geometry, Mesh):
        result = meshes.get(geometry)
        return result if isinstance(result, MeshProblem) else result.mesh
    return primitive_mesh(geometry)


def shape_mesh(shape: Shape, meshes: MeshStore) -> trimesh.Trimesh | MeshProblem:
    """The shape as a new mesh in the link frame (its ``<origin>`` applied)."""
    mesh = geometry_mesh(shape.geometry, meshes)
    if isinstance(mesh, MeshProblem):
        return mesh
    out = mesh.copy()
    out.apply_transform(shape.origin.matrix())
    return out


def link_points(link: Link, meshes: MeshStore, kinds: Iterable[str] = ("visual", "collision")) -> np.ndarray:
    """Vertices of every available shape of ``link`` of the given kinds, in the link frame, shape (n, 3) [m]."""
    chunks = []
    wanted = set(kinds)
    for shape in (*link.visuals, *link.collisions):
        if shape.kind not in wanted:
            continue
        mesh = geometry_mesh(shape.geometry, meshes)
        if not isinstance(mesh, MeshProblem):
            # transform the vertices alone: copying the mesh to move it costs more than all the rest
            transform = shape.origin.matrix()
            chunks.append(np.asarray(mesh.vertices, dtype=float) @ transform[:3, :3].T + transform[:3, 3])
    return np.concatenate(chunks) if chunks else np.zeros((0, 3))
