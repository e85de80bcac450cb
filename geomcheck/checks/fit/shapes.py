"""The fit family's shapes, once per link: visual geometry as a cloud, collision elements, and the
neighbours' elements a link borrows (``ctx.analyses.fits``), with their report entries."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from geomcheck.checks import CheckContext
from geomcheck.checks.closures import closure_neighbours
from geomcheck.checks.meshes import MeshStats, mesh_solid, mesh_stats
from geomcheck.geometry.elements import CollisionElement, VisualCloud
from geomcheck.geometry.fit import LinkFit
from geomcheck.geometry.frames import pose_frame
from geomcheck.geometry.neighbours import Neighbour, invariant, moved, neighbours, sharing_neighbours
from geomcheck.geometry.shapes import primitive_solid
from geomcheck.geometry.surface import Solid
from geomcheck.load.meshes import MeshProblem
from geomcheck.model import Box, Capsule, Cylinder, Link, Mesh, Robot, Shape
from geomcheck.thresholds import FitThresholds


def shape_solid(ctx: CheckContext, shape: Shape) -> Solid | str:
    """The shape in the link frame, or why it is unavailable."""
    g = shape.geometry
    rotation, translation = pose_frame(shape.origin)
    if isinstance(g, Mesh):
        stats = mesh_stats(ctx, g)
        if isinstance(stats, MeshProblem):
            return f"mesh not loaded: {stats.message}"
        if not stats.finite:
            return "mesh has non-finite vertices"
        solid = mesh_solid(ctx, g)
        assert not isinstance(solid, MeshProblem)
        return solid.moved(rotation, translation)
    tessellated = ctx.analyses.fits.primitive_solids  # visual primitives tessellated once per geometry
    if g not in tessellated:
        tessellated[g] = primitive_solid(g)
    return tessellated[g].moved(rotation, translation)


def geometry_entry(shape: Shape) -> dict[str, Any]:
    g = shape.geometry
    if isinstance(g, Box):
        return {"size": list(g.size)}
    if isinstance(g, Mesh):
        return {"filename": g.filename, "scale": list(g.scale)}
    if isinstance(g, Capsule):  # as the file writes it; the fit measures the cylinder enclosing it
        return {"radius": g.radius, "length": g.straight_length}
    if isinstance(g, Cylinder):
        return {"radius": g.radius, "length": g.length}
    return {"radius": g.radius}


def collision_entry(shape: Shape) -> dict[str, Any]:
    return {
        "index": shape.index,
        "type": type(shape.geometry).__name__.lower(),
        "origin": {"xyz": list(shape.origin.xyz), "rpy": list(shape.origin.rpy)},
        "geometry": geometry_entry(shape),
        "fit": None,
    }


def visual_mesh_entries(ctx: CheckContext, link: Link) -> list[dict[str, Any]]:
    out = []
    for shape in link.visuals:
        if not isinstance(shape.geometry, Mesh):
            continue
        stats = mesh_stats(ctx, shape.geometry)
        loaded = ctx.meshes.get(shape.geometry)
        entry: dict[str, Any] = {
            "index": shape.index,
            "filename": shape.geometry.filename,
            "path": loaded.path,
            "loaded": isinstance(stats, MeshStats),
            "extents": None,
            "hull_volume": None,
            "area": None,
        }
        if isinstance(stats, MeshStats):
            entry |= {
                "extents": [round(e, 6) for e in stats.extents],
                "hull_volume": float(f"{stats.hull_volume:.6g}"),
                "area": float(f"{stats.area:.6g}"),
            }
        out.append(entry)
    return out


def link_visual(ctx: CheckContext, link: Link, th: FitThresholds) -> VisualCloud | str | None:
    """The link's visual geometry as a cloud (once per link), why it is unavailable, or
    ``None`` when the link has no visual element."""
    cache = ctx.analyses.fits.visuals
    # links drawn alike (four casters, eight wheels, a thousand chain links) share one cloud
    alike = ctx.analyses.fits.visuals_alike
    shapes_key = tuple((s.geometry, s.origin) for s in link.visuals)
    if link.name not in cache and shapes_key in alike:
        cache[link.name] = alike[shapes_key]
    if link.name not in cache:
        value: VisualCloud | str | None = None
        solids = []
        for shape in link.visuals:
            got = shape_solid(ctx, shape)
            if isinstance(got, str):
                value = f"{shape.label} {got}"
                break
            solids.append(got)
        else:
            if solids:
                cloud = VisualCloud.of(solids, th.surface_samples, th.seed)
                value = cloud if len(cloud.samples) else "the visual geometry has no surface"
        cache[link.name] = alike[shapes_key] = value
    return cache[link.name]


def same_as_visual(link: Link, shape: Shape) -> bool:
    """Whether a collision mesh repeats the link's only visual: same file, scale and origin."""
    if len(link.visuals) != 1:
        return False
    visual = link.visuals[0]
    return isinstance(shape.geometry, Mesh) and visual.geometry == shape.geometry and visual.origin == shape.origin


def link_elements(ctx: CheckContext, link: Link) -> list[CollisionElement] | str:
    """The link's collision elements in the link frame (once per link), or why one is unavailable."""
    cache = ctx.analyses.fits.elements
    if link.name not in cache:
        elements: list[CollisionElement] = []
        problem: str | None = None
        for shape in link.collisions:
            rotation, translation = pose_frame(shape.origin)
            if not isinstance(shape.geometry, Mesh):
                elements.append(CollisionElement(shape.index, rotation, translation, primitive=shape.geometry))
                continue
            got = shape_solid(ctx, shape)
            if isinstance(got, str):
                problem = f"{shape.label} {got}"
                break
            same = same_as_visual(link, shape)
            elements.append(CollisionElement(shape.index, rotation, translation, solid=got, same_as_visual=same))
        cache[link.name] = elements if problem is None else problem
    return cache[link.name]


def borrowed_elements(ctx: CheckContext, link: Link) -> list[tuple[CollisionElement, Neighbour]]:
    """Neighbours' collision elements that hold for ``link`` at every joint position, in its frame."""
    out = []
    for n in sharing_neighbours(ctx.robot, link.name):
        theirs = link_elements(ctx, ctx.robot.link_map[n.link])
        if isinstance(theirs, str):
            continue
        for element in theirs:
            here = moved(element, n.rotation, n.translation)
            if invariant(here, n):
                out.append((here, n))
    return out


def alike_fit(
    ctx: CheckContext, link: Link, borrowed: list[tuple[CollisionElement, Neighbour]], compute: Callable[[], LinkFit]
) -> LinkFit:
    """The fit of ``link`` from ``compute``, or that of an earlier link with the same visual
    and collision shapes and the same borrowed elements in the same places: the fit is a
    function of those alone, so links drawn alike are fitted once."""
    cache = ctx.analyses.fits.links_alike
    lent = tuple(
        (
            e.index,
            tuple((s.geometry, s.origin) for s in ctx.robot.link_map[n.link].collisions),
            tuple((s.geometry, s.origin) for s in ctx.robot.link_map[n.link].visuals),
            n.rotation.tobytes(),
            n.translation.tobytes(),
        )
        for e, n in borrowed
    )
    key = (
        tuple((s.geometry, s.origin) for s in link.visuals),
        tuple((s.geometry, s.origin) for s in link.collisions),
        tuple(same_as_visual(link, s) for s in link.collisions),
        lent,
    )
    if key not in cache:
        cache[key] = compute()
    return cache[key]


def resting_neighbours(robot: Robot, link: str) -> list[Neighbour]:
    """The links next to ``link`` at rest: across a fixed, revolute or continuous joint, and those
    a loop-closing constraint holds against it (:mod:`geomcheck.checks.closures`)."""
    return [*neighbours(robot, link), *closure_neighbours(robot, link)]


def resting_elements(ctx: CheckContext, link: Link) -> list[CollisionElement]:
    """The collision elements of the links next to ``link`` at rest (zero joint positions), in its frame."""
    out: list[CollisionElement] = []
    for n in resting_neighbours(ctx.robot, link.name):
        theirs = link_elements(ctx, ctx.robot.link_map[n.link])
        if not isinstance(theirs, str):
            out.extend(moved(e, n.rotation, n.translation) for e in theirs)
    return out
