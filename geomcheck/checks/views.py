"""The ``views`` section: front, side and top pictures of every link with geometry.

Computed at check time (the meshes are at hand) so that a stored report renders to HTML
without them. Per link and view: the filled silhouette of the visual geometry, the
outlines of the collision shapes and the outlines of the primitives the fit family
suggests, in the link frame [m], simplified and rounded (see ``ViewThresholds``). Links
with the same shapes (four casters, eight wheels) are drawn once.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.views_cache import stored_link_views
from geomcheck.geometry.shapes import geometry_mesh
from geomcheck.geometry.silhouette import (
    AXIS_NAMES,
    VIEWS,
    canonical_outline,
    mesh_silhouettes,
    primitive_outline,
    primitive_points,
    round_rings,
    simplify_rings,
    transform,
)
from geomcheck.load.meshes import MeshProblem
from geomcheck.model import Box, Cylinder, Geometry, Link, Mesh, Pose, Sphere

Primitive = tuple[Box | Cylinder | Sphere, Pose]


def _pose(data: Mapping[str, Any] | None) -> Pose:
    data = data or {}
    xyz = tuple(float(v) for v in data.get("xyz", (0.0, 0.0, 0.0)))
    rpy = tuple(float(v) for v in data.get("rpy", (0.0, 0.0, 0.0)))
    return Pose(xyz=xyz, rpy=rpy)  # type: ignore[arg-type]


def primitive_from_dict(data: Mapping[str, Any]) -> Primitive | None:
    """A suggested primitive of the ``links`` section (``{type, origin, geometry}``), or
    ``None`` when it is not a box, cylinder or sphere with valid dimensions."""
    kind, geometry = data.get("type"), data.get("geometry") or {}
    try:
        shape: Box | Cylinder | Sphere
        if kind == "box":
            size = tuple(float(v) for v in geometry["size"])
            if len(size) != 3:
                return None
            shape = Box(size=size)  # type: ignore[arg-type]
        elif kind == "cylinder":
            shape = Cylinder(radius=float(geometry["radius"]), length=float(geometry["length"]))
        elif kind == "sphere":
            shape = Sphere(radius=float(geometry["radius"]))
        else:
            return None
        return shape, _pose(data.get("origin"))
    except (KeyError, TypeError, ValueError):
        return None


def fit_suggestions(ctx: CheckContext, link: str) -> tuple[Primitive, ...]:
    """The primitives the fit family suggested for ``link``'s collision elements (from its
    cache), placed as their URDF snippets place them; none when the link was not fitted."""
    link_fit = ctx.analyses.fits.links.get(link)
    if link_fit is None:
        return ()
    out = []
    for element in link_fit.elements:
        primitive = primitive_from_dict(element.suggested.to_dict()) if element.suggested is not None else None
        if primitive is not None:
            out.append(primitive)
    return tuple(out)


def _compact_mesh(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The mesh reduced to the vertices its faces use, without faces on non-finite vertices
    (a degenerate mesh is a GC2xx finding, not a crash here)."""
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    finite = np.isfinite(vertices).all(axis=1)
    faces = faces[finite[faces].all(axis=1)]
    used = np.zeros(len(vertices), dtype=bool)
    used[faces] = True
    remap = np.cumsum(used) - 1
    return vertices[used], remap[faces]


def _rings_json(rings: Sequence[np.ndarray]) -> list[list[list[float]]]:
    return [ring.tolist() for ring in rings]


def _bounds(groups: Iterable[Sequence[np.ndarray]]) -> list[float] | None:
    points = [ring for rings in groups for ring in rings]
    if not points:
        return None
    stacked = np.concatenate(points)
    lo, hi = stacked.min(axis=0), stacked.max(axis=0)
    return [float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])]


ShapeKey = tuple[tuple[Geometry, Pose], ...]
MeshArrays = tuple[np.ndarray, np.ndarray]


class Drawer:
    """Draws links for the ``views`` section; every mesh and silhouette is computed once per run."""

    def __init__(self, ctx: CheckContext) -> None:
        self.ctx = ctx
        self.params = ctx.thresholds.views
        self._meshes: dict[tuple[Geometry, Pose], MeshArrays | MeshProblem] = {}
        self._silhouettes: dict[tuple[ShapeKey, float, float], Mapping[str, list[np.ndarray]]] = {}

    def mesh(self, geometry: Geometry, origin: Pose) -> MeshArrays | MeshProblem:
        """The shape as a compact mesh: vertices (n, 3) [m] in the link frame, faces (m, 3)."""
        key = (geometry, origin)
        if key not in self._meshes:
            mesh = geometry_mesh(geometry, self.ctx.meshes)
            if isinstance(mesh, MeshProblem):
                self._meshes[key] = mesh
            else:
                vertices, faces = _compact_mesh(mesh.vertices, mesh.faces)
                self._meshes[key] = (transform(vertices, origin), faces)
        return self._meshes[key]

    def meshes(self, shapes: ShapeKey) -> list[MeshArrays]:
        """The available, non-empty meshes of ``shapes``."""
        found = (self.mesh(g, o) for g, o in shapes)
        return [m for m in found if not isinstance(m, MeshProblem) and len(m[1])]

    def silhouettes(self, shapes: ShapeKey, pixel: float, tolerance: float) -> Mapping[str, list[np.ndarray]]:
        """Simplified rings of the union of the meshes of ``shapes``, per view."""
        key = (shapes, pixel, tolerance)
        if key not in self._silhouettes:
            meshes = self.meshes(shapes)
            views: dict[str, list[np.ndarray]] = {view: [] for view in VIEWS}
            if meshes:
                vertices = np.concatenate([v for v, _ in meshes])
                offsets = np.cumsum([0, *(len(v) for v, _ in meshes[:-1])])
                faces = np.concatenate([f + o for (_, f), o in zip(meshes, offsets, strict=True)])
                traced = mesh_silhouettes(vertices, faces, pixel)
                simple = iter(simplify_rings([r for view in VIEWS for r in traced[view]], tolerance))
                views = {view: [next(simple) for _ in traced[view]] for view in VIEWS}
            self._silhouettes[key] = views
        return self._silhouettes[key]

    def extent(self, visual: ShapeKey, collision: ShapeKey, primitives: Sequence[Primitive]) -> float:
        """The link's size [m]: largest extent of its visual geometry, else of its collision geometry."""
        meshes = self.meshes(visual)
        if meshes:
            points = np.concatenate([v for v, _ in meshes])
        else:
            segments = self.params.circle_segments
            chunks = [v for v, _ in self.meshes(collision)]
            chunks += [primitive_points(g, p, segments) for g, p in primitives]
            chunks += [
                np.asarray([p.xyz]) + np.array([[-g.radius] * 3, [g.radius] * 3])
                for g, p in primitives
                if isinstance(g, Sphere)
            ]
            if not chunks:
                return 0.0
            points = np.concatenate(chunks)
        return float(np.max(np.ptp(points, axis=0)))

    def link_views(self, link: Link, suggested: Sequence[Primitive]) -> dict[str, Any]:
        """The ``views`` entry of ``link`` without its name: ``scale_m`` and the three views."""
        params = self.params
        visual: ShapeKey = tuple((s.geometry, s.origin) for s in link.visuals)
        collision_meshes: ShapeKey = tuple(
            (s.geometry, s.origin) for s in link.collisions if isinstance(s.geometry, Mesh)
        )
        primitives: list[Primitive] = [
            (s.geometry, s.origin) for s in link.collisions if isinstance(s.geometry, Box | Cylinder | Sphere)
        ]
        scale = self.extent(visual, collision_meshes, [*primitives, *suggested])
        entry: dict[str, Any] = {"scale_m": round(scale, 4)}
        scale = scale if scale > 0.0 else 1.0  # a point-like link: any resolution draws it
        pixel = scale / params.raster_pixels
        tolerance = scale * params.simplify_tolerance
        step = params.coordinate_step_m
        visual_rings = self.silhouettes(visual, pixel, tolerance)
        collision_rings = self.silhouettes(collision_meshes, pixel, tolerance)

        def outlines(shapes: Sequence[Primitive], view: str) -> list[np.ndarray]:
            found = (canonical_outline(primitive_outline(g, p, view, params.circle_segments), step) for g, p in shapes)
            return [ring for ring in found if len(ring) >= 2]  # as round_rings: a point draws nothing

        for view, (u, v) in VIEWS.items():
            mesh = round_rings(visual_rings[view], step)
            collision = round_rings(collision_rings[view], step) + outlines(primitives, view)
            outline = outlines(suggested, view)
            entry[view] = {
                "axes": [AXIS_NAMES[u], AXIS_NAMES[v]],
                "bounds": _bounds((mesh, collision, outline)),
                "mesh": _rings_json(mesh),
                "collision": _rings_json(collision),
                "suggested": _rings_json(outline),
            }
        unavailable = [
            f"{s.label}: {problem.message}"
            for s in (*link.visuals, *link.collisions)
            if isinstance(problem := self.mesh(s.geometry, s.origin), MeshProblem)
        ]
        if unavailable:
            entry["unavailable"] = unavailable
        return entry


def run(ctx: CheckContext) -> FamilyResult:
    drawer = Drawer(ctx)
    drawn: dict[tuple[Any, ...], dict[str, Any]] = {}
    entries = []
    for link in ctx.robot.links:
        if not link.has_geometry:
            continue
        suggested = fit_suggestions(ctx, link.name)
        key = (
            tuple((s.geometry, s.origin) for s in link.visuals),
            tuple((s.geometry, s.origin) for s in link.collisions),
            suggested,
        )
        if key not in drawn:
            drawn[key] = stored_link_views(
                link,
                suggested,
                functools.partial(drawer.link_views, link, suggested),
                ctx.analyses.mesh_digest,
                ctx.thresholds,
            )
        entries.append({"link": link.name, **drawn[key]})
    return FamilyResult(sections={"views": entries} if entries else {})
