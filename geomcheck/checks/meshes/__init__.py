"""GC2xx: every mesh a link refers to is found, readable, sound, and in metres.

Runs before the fit family and leaves, per mesh file and scale, statistics in
``ctx.analyses.mesh_stats`` (``MeshStats``); the geometry (:class:`Solid`: unique vertices,
bounded convex hull) is kept by the mesh store, computed once per file and scale. One
finding per problem file per referencing element: subject the link, ``about`` the element
(``visual[0]``, ``collision[1]``).

The family's modules, one job each:

- :mod:`~geomcheck.checks.meshes.element`: one element's checks in order, and ``run``;
- :mod:`~geomcheck.checks.meshes.stats`: each mesh's statistics, once per file and scale;
- :mod:`~geomcheck.checks.meshes.files`: GC201-GC204, GC207, files missing, unreadable, empty, or oddly named;
- :mod:`~geomcheck.checks.meshes.packages`: GC201 and GC202 once per package (unknown, not built);
- :mod:`~geomcheck.checks.meshes.soundness`: GC207, GC208, GC210 (no surface, flat, winding);
- :mod:`~geomcheck.checks.meshes.units`: GC205, GC206, GC209 (units and sizes);
- :mod:`~geomcheck.checks.meshes.visuals`: GC211, a visual drawing the collision mesh.
"""

from __future__ import annotations

from geomcheck.checks.analyses import MeshStats
from geomcheck.checks.meshes.element import run
from geomcheck.checks.meshes.stats import mesh_solid, mesh_stats

__all__ = ["MeshStats", "mesh_solid", "mesh_stats", "run"]
