"""Shapes of a link as triangle meshes in the link frame.

Primitives are tessellated (cylinders and spheres finely enough for bounds, not for exact
distances: exact distances to primitives live in :mod:`geomcheck.geometry.primitives`) as
trimesh tessellates them (:mod:`geomcheck.geometry.tessellation`, without importing it), once
per primitive: the arrays are kept in the cache when a store is active. Meshes here are numpy arrays
(:class:`MeshArrays`, :class:`geomcheck.load.meshes.LoadedMesh`).
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from geomcheck.cache import cached_arrays
from geomcheck.geometry import tessellation
from geomcheck.geometry.frames import from_frame
from geomcheck.geometry.surface import ANALYSIS, ConvexRegion, Solid, Surface, TriangleMesh
from geomcheck.load.meshes import LoadedMesh, MeshProblem, MeshStore
from geomcheck.model import Box, Cylinder, Geometry, Link, Mesh, Shape, Sphere
from geomcheck.thresholds import AnalysisThresholds

CYLINDER_SECTIONS = 64  # tessellation of primitive cylinders [segments per turn]
SPHERE_SUBDIVISIONS = 3  # icosphere subdivisions for primitive spheres
TINY_RADIUS_M = 1e-9  # spheres smaller than this are tessellated as a unit sphere scaled down [m]


PRIMITIVE_MESHES = 4096  # tessellated primitives kept in memory [count]


@dataclass(frozen=True, eq=False)
class MeshArrays:
    """A triangle mesh as arrays: ``vertices`` (n, 3) [m], ``faces`` (m, 3) indices."""

    vertices: np.ndarray
    faces: np.ndarray


def tessellate(geometry: Box | Cylinder | Sphere) -> dict[str, np.ndarray]:
    """trimesh's tessellation of a primitive (:mod:`geomcheck.geometry.tessellation`, no
    trimesh imported): ``vertices`` and ``faces``."""
    if isinstance(geometry, Box):
        vertices, faces = tessellation.box(geometry.size)
    elif isinstance(geometry, Cylinder):
        vertices, faces = tessellation.cylinder(geometry.radius, geometry.length, CYLINDER_SECTIONS)
    elif geometry.radius < TINY_RADIUS_M:  # trimesh divides by the radius: NaN below ~1e-20 m
        vertices, faces = tessellation.icosphere(SPHERE_SUBDIVISIONS, 1.0)
        vertices = vertices * geometry.radius
    else:
        vertices, faces = tessellation.icosphere(SPHERE_SUBDIVISIONS, geometry.radius)
    return {"vertices": vertices, "faces": faces}


@functools.lru_cache(maxsize=PRIMITIVE_MESHES)
def primitive_mesh(geometry: Box | Cylinder | Sphere) -> MeshArrays:
    """A primitive as a mesh in its own frame (centred, cylinder along z), lengths [m]; made
    once per primitive and shared: nobody writes into it."""
    # not kept in the cache: tessellating takes microseconds, a store lookup longer
    arrays = tessellate(geometry)
    return MeshArrays(np.asarray(arrays["vertices"], dtype=np.float64), np.asarray(arrays["faces"], dtype=np.int64))


@functools.lru_cache(maxsize=4096)
def primitive_vertices(geometry: Box | Cylinder | Sphere) -> np.ndarray:
    """The vertices (n, 3) [m] of :func:`primitive_mesh`, read-only and made once per primitive."""
    vertices = np.array(primitive_mesh(geometry).vertices, dtype=float)
    vertices.setflags(write=False)
    return vertices


def primitive_solid(geometry: Box | Cylinder | Sphere) -> Solid:
    """The :class:`Solid` of :func:`primitive_mesh` in the primitive's own frame (default
    analysis thresholds); its unique vertices and hull are kept on disk by the primitive."""
    surface = Surface.from_mesh(primitive_mesh(geometry), np.eye(3), np.zeros(3))
    key = {"geometry": type(geometry).__name__, **vars(geometry)}
    key |= {"sections": CYLINDER_SECTIONS, "subdivisions": SPHERE_SUBDIVISIONS, "analysis": ANALYSIS}
    arrays = cached_arrays("primitive-solid", key, lambda: solid_arrays(Solid.of(surface)))
    return solid_from_arrays(surface, arrays)


def geometry_mesh(geometry: Geometry, meshes: MeshStore) -> TriangleMesh | MeshProblem:
    """The geometry as a mesh in its own frame (mesh ``scale`` applied), or why it is unavailable."""
    if isinstance(geometry, Mesh):
        return meshes.get(geometry)
    return primitive_mesh(geometry)


def mesh_solid_in(meshes: MeshStore, mesh: Mesh, analysis: AnalysisThresholds) -> Solid | MeshProblem:
    """The mesh in its own frame (``scale`` applied) with its unique vertices and bounded
    hull, computed once per file and scale; or why it is unavailable. Non-finite vertices
    are replaced by zeros here (GC207 reports them; the geometry is then unusable)."""

    settings = {"hull_exact_points": analysis.hull_exact_points, "hull_tolerance": analysis.hull_tolerance_fraction}

    def solid(loaded: LoadedMesh) -> Solid:
        vertices = np.asarray(loaded.vertices, dtype=float)
        faces = np.asarray(loaded.faces, dtype=np.int64)
        surface = Surface(np.nan_to_num(vertices, nan=0.0, posinf=0.0, neginf=0.0), faces)
        distinct = loaded.distinct and bool(np.isfinite(vertices).all())
        if not loaded.sha256:
            return Solid.of(surface, analysis, distinct)
        # the unique vertices and the hull, the costly part, are kept on disk by the file's content
        key = {"sha256": loaded.sha256, "scale": list(mesh.scale), **settings}
        arrays = cached_arrays("mesh-solid", key, lambda: solid_arrays(Solid.of(surface, analysis, distinct)))
        return solid_from_arrays(surface, arrays)

    return meshes.derived(mesh, "solid:" + ":".join(str(v) for v in settings.values()), solid)


def solid_arrays(solid: Solid) -> dict[str, np.ndarray]:
    """What :func:`solid_from_arrays` rebuilds ``solid`` from, besides its surface."""
    hull = solid.hull
    if hull is None:
        return {"vertices": solid.vertices, "has_hull": np.array(False)}
    return {
        "vertices": solid.vertices,
        "has_hull": np.array(True),
        "hull_vertices": hull.vertices,
        "equations": hull.equations,
        "facet_areas": hull.facet_areas,
        "volume": np.array(hull.volume),
        "tolerance": np.array(hull.tolerance),
    }


def solid_from_arrays(surface: Surface, arrays: Mapping[str, np.ndarray]) -> Solid:
    """The :class:`Solid` of ``surface`` whose vertices and hull :func:`solid_arrays` gave."""
    hull = None
    if bool(arrays["has_hull"]):
        hull = ConvexRegion(
            arrays["hull_vertices"],
            arrays["equations"],
            arrays["facet_areas"],
            float(arrays["volume"]),
            float(arrays["tolerance"]),
        )
    return Solid(surface, arrays["vertices"], hull)


def shape_mesh(shape: Shape, meshes: MeshStore) -> MeshArrays | MeshProblem:
    """The shape as a new mesh in the link frame (its ``<origin>`` applied)."""
    mesh = geometry_mesh(shape.geometry, meshes)
    if isinstance(mesh, MeshProblem):
        return mesh
    transform = shape.origin.matrix()
    vertices = from_frame(mesh.vertices, transform[:3, :3], transform[:3, 3])
    return MeshArrays(vertices, np.array(mesh.faces, dtype=np.int64))


def link_points(
    link: Link,
    meshes: MeshStore,
    kinds: Iterable[str] = ("visual", "collision"),
    analysis: AnalysisThresholds | None = None,
) -> np.ndarray:
    """Points of every available shape of ``link`` of the given kinds, in the link frame,
    shape (n, 3) [m]: every vertex, or with ``analysis`` only each mesh's hull vertices.

    Hull vertices suffice for whatever peaks at extremes (reach from an axis or a plane,
    the hull itself): a convex function of the points peaks at a hull vertex. They keep
    the count bounded however finely a mesh is tessellated (within the hull's tolerance)."""
    chunks = []
    wanted = set(kinds)
    for shape in (*link.visuals, *link.collisions):
        if shape.kind not in wanted:
            continue
        vertices: np.ndarray | None = None
        if analysis is not None and isinstance(shape.geometry, Mesh):
            solid = mesh_solid_in(meshes, shape.geometry, analysis)
            if not isinstance(solid, MeshProblem):
                vertices = solid.vertices if solid.hull is None else solid.hull.vertices
        elif not isinstance(shape.geometry, Mesh):
            vertices = primitive_vertices(shape.geometry)
        else:
            mesh = geometry_mesh(shape.geometry, meshes)
            if not isinstance(mesh, MeshProblem):
                vertices = np.asarray(mesh.vertices, dtype=float)
        if vertices is not None:
            # transform the vertices alone: copying the mesh to move it costs more than all the rest
            transform = shape.origin.matrix()
            chunks.append(from_frame(vertices, transform[:3, :3], transform[:3, 3]))
    return np.concatenate(chunks) if chunks else np.zeros((0, 3))
