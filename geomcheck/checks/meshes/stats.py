"""Each mesh's statistics, computed once per file and scale, and the sizes of a link's elements."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np

from geomcheck.checks import CheckContext
from geomcheck.checks.analyses import MeshStats
from geomcheck.diagnostics import Diagnostic
from geomcheck.geometry.shapes import mesh_solid_in
from geomcheck.geometry.surface import Solid
from geomcheck.load.meshes import MeshProblem
from geomcheck.model import Box, Cylinder, Link, Mesh, Shape, Sphere
from geomcheck.rules import Rule


def mesh_solid(ctx: CheckContext, mesh: Mesh) -> Solid | MeshProblem:
    """The mesh in its own frame (``scale`` applied) with its unique vertices and hull,
    computed once per file and scale; or why it is unavailable. Non-finite vertices are
    replaced by zeros here (GC207 reports them; the geometry is then unusable)."""
    return mesh_solid_in(ctx.meshes, mesh, ctx.thresholds.analysis)


def mesh_stats(ctx: CheckContext, mesh: Mesh) -> MeshStats | MeshProblem:
    """Statistics of ``mesh`` (computed once per file and scale), or why it is unavailable."""
    cache = ctx.analyses.mesh_stats
    key = (mesh.filename, mesh.scale)
    if key not in cache:
        solid = mesh_solid(ctx, mesh)
        if isinstance(solid, MeshProblem):
            cache[key] = solid
        else:
            loaded = ctx.meshes.get(mesh)
            assert not isinstance(loaded, MeshProblem)
            finite = bool(np.isfinite(loaded.vertices).all())
            unique = solid.vertices
            usable = bool(len(unique)) and finite
            extents = np.ptp(unique, axis=0) if usable else np.zeros(3)
            centre = (unique.min(axis=0) + unique.max(axis=0)) / 2.0 if usable else np.zeros(3)
            cache[key] = MeshStats(
                extents=(float(extents[0]), float(extents[1]), float(extents[2])),
                area=solid.surface.area if finite else 0.0,
                hull_volume=solid.hull.volume if solid.hull is not None else 0.0,
                finite=finite,
                flat=solid.hull is None,
                offset=float(np.linalg.norm(centre)),
            )
    return cache[key]


def shapes(link: Link) -> Iterator[Shape]:
    yield from link.visuals
    yield from link.collisions


def shape_size(ctx: CheckContext, shape: Shape) -> float | None:
    """Largest extent [m] of a shape's geometry; ``None`` when a mesh is unavailable or unsound."""
    g = shape.geometry
    if isinstance(g, Box):
        return float(max(g.size))
    if isinstance(g, Cylinder):
        return float(max(2.0 * g.radius, g.length))
    if isinstance(g, Sphere):
        return 2.0 * float(g.radius)
    stats = mesh_stats(ctx, g)
    return stats.size if isinstance(stats, MeshStats) and stats.finite and stats.size > 0 else None


def element_diagnostic(
    rule: Rule, link: Link, shape: Shape, message: str, data: dict[str, Any], help: str | None = None
) -> Diagnostic:
    """A finding of ``rule`` about one element of ``link``, located at the element."""
    return rule.diagnose(message, help=help, link=link.name, about=shape.label, location=shape.location, data=data)
