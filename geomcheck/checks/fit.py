"""GC3xx: each link's collision elements against its visual geometry, and the ``links`` section.

For later families this leaves ``ctx.analyses.fits`` (:class:`geomcheck.checks.analyses.FitTables`):
``links`` (``{link name: LinkFit}``, with each element's suggested primitive), ``visuals``
(``{link name: VisualCloud, or the reason it is unavailable, or None without visuals}``) and
``elements`` (``{link name: [CollisionElement] or a reason}``), all in link frames.
Links whose meshes are missing are skipped with a :class:`SkippedCheck` naming the mesh.
A neighbour's collision element that is the same at every position of the joint between
them (fixed joint; sphere or cylinder on a revolute axis) counts for the link too.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import PurePosixPath
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.closures import closure_neighbours
from geomcheck.checks.coverage_cache import stored_resting_coverage
from geomcheck.checks.fit_oversize import Oversize, standing_off, wrong_kind
from geomcheck.checks.meshes import MeshStats, mesh_solid, mesh_stats
from geomcheck.diagnostics import Diagnostic, Severity, SkippedCheck
from geomcheck.geometry.elements import CollisionElement, VisualCloud, at_nanometre, mm, ratio
from geomcheck.geometry.fit import ElementFit, LinkFit, fit_link
from geomcheck.geometry.frames import pose_frame, rotation_angle
from geomcheck.geometry.neighbours import Neighbour, invariant, moved, neighbours
from geomcheck.geometry.reach import RigidGroups, element_corners, rigid_groups, swept_bound
from geomcheck.geometry.shapes import primitive_mesh, primitive_solid
from geomcheck.geometry.suggest import fmt, suggest
from geomcheck.geometry.surface import ConvexRegion, Solid
from geomcheck.kinematics import rotation_matrices
from geomcheck.load.meshes import MeshProblem
from geomcheck.model import Box, Capsule, Cylinder, Joint, Link, Mesh, Robot, Shape, Sphere
from geomcheck.rules import Rule
from geomcheck.rules import fit as rules
from geomcheck.thresholds import FitThresholds

AXIS_NAMES = "xyz"
TYRE_AXIS_COS = 0.999  # a wheel's cylinder lies along its joint's axis within 2.6 degrees [cos]


def length(value: float) -> str:
    """A length [m] for a message: millimetres below 0.1 m, metres above."""
    v = round(float(value), 6)
    if abs(v) < 0.1:
        return f"{v * 1000:.0f} mm" if abs(v) >= 0.01 else f"{v * 1000:.1f} mm"
    return f"{v:.3g} m"


def vector(v: np.ndarray) -> str:
    return "(" + ", ".join(fmt(float(c), 3) for c in v) + ") m"


def direction(v: np.ndarray) -> str:
    """``the link's x axis`` when ``v`` (3,) is one, else its components."""
    u = np.asarray(v, dtype=float) / np.linalg.norm(v)
    i = int(np.argmax(np.abs(u)))
    if abs(u[i]) > 0.999:
        return f"the link's {AXIS_NAMES[i]} axis"
    return "(" + ", ".join(f"{c:.2f}" for c in u) + ")"


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


def _element_diagnostic(
    rule: Rule,
    link: Link,
    shape: Shape,
    message: str,
    data: dict[str, Any],
    help: str | None = None,
    severity: Severity | None = None,
) -> Diagnostic:
    return rule.diagnose(
        message, help=help, link=link.name, about=shape.label, location=shape.location, data=data, severity=severity
    )


def _moved_origin(shape: Shape, shift: np.ndarray) -> str:
    xyz = " ".join(fmt(float(v)) for v in np.asarray(shape.origin.xyz) + shift)
    rpy = " ".join(fmt(float(v), 4) for v in shape.origin.rpy)
    return f'<origin xyz="{xyz}" rpy="{rpy}"/>'


def _worst_axis(shape: Shape, f: ElementFit) -> tuple[str, str]:
    """The axis the element spans the least share of: ``(share phrase, extents phrase)``."""
    assert f.extent is not None
    extent = f.extent
    key = min(extent, key=lambda k: extent[k][0])
    share, prim, span, lo, hi = extent[key]
    kind = type(shape.geometry).__name__.lower()
    if key == "radial":
        about = "axis" if isinstance(shape.geometry, Cylinder) else "centre"  # a capsule or cone too
        rule = rules.COLLISION_DOES_NOT_COVER
        return (
            rule.message("radial_share", share=share, about=about),
            rule.message("radial_extent", kind=kind, extent=prim, reach=hi, about=about),
        )
    i = AXIS_NAMES.index(key)
    axis = f.element.rotation[:, i]
    where = direction(axis)
    height = where == "the link's z axis"
    noun = "height" if height else f"extent along {where}"
    # intervals along the axis, measured from the link origin
    base = float(axis @ f.element.translation)
    half = 0.5 * prim
    coord = "z" if height else ("" if where.startswith("(") else where.split()[-2])
    box_at = f"{coord} {at_nanometre(base - half):.3g} to {at_nanometre(base + half):.3g} m".strip()
    mesh_at = f"{coord} {at_nanometre(base + lo):.3g} to {at_nanometre(base + hi):.3g} m".strip()
    size = "tall" if height else "long"
    rule = rules.COLLISION_DOES_NOT_COVER
    return (
        rule.message("axis_share", share=share, noun=noun),
        rule.message("axis_extent", kind=kind, extent=prim, size=size, element_at=box_at, span=span, mesh_at=mesh_at),
    )


def _grown_note(f: ElementFit, kind: str, tolerance: float) -> str:
    """Why the fitted primitive reaches past the part of the mesh the message measures (a
    caster's box fitted to the fork also takes the fork's points its wheels cover), with its
    interval along the message's axis; empty when it stays within that part's span (plus
    ``tolerance`` [m]) or is fitted to that part alone."""
    s = f.suggested
    if s is None or not f.suggestion_grown or f.extent is None:
        return ""
    extent = f.extent
    key = min(extent, key=lambda k: extent[k][0])
    if key == "radial":
        return ""  # the message gives the part's radius, not an interval
    _, _, _, lo, hi = extent[key]
    axis = f.element.rotation[:, AXIS_NAMES.index(key)]
    base = float(axis @ f.element.translation)
    along = (primitive_mesh(s.primitive).vertices @ s.rotation.T + s.translation) @ axis
    if along.min() >= base + lo - tolerance and along.max() <= base + hi + tolerance:
        return ""
    where = direction(axis)
    coord = "z" if where == "the link's z axis" else ("" if where.startswith("(") else where.split()[-2])
    span = f"{coord} {along.min():.3g} to {along.max():.3g} m".strip()
    return (
        f" ({span}, past the part of the mesh measured above: put in place of this {kind} it is nearer than "
        "the other collision geometry to more of the mesh, which it then answers for and encloses)"
    )


def uncovered_severity(union_coverage: float, th: FitThresholds) -> Severity:
    """How much it matters that part of a link's visual geometry is outside its collision
    geometry, by the share of the link's surface left out (``union_coverage``: the share the
    link's collision elements together cover): an error when most of it is out, a warning when
    more than ``1 - min_coverage`` is, else info: a tab, a trim ring or a shaft stub outside
    the primitive misses contacts over a sliver of the part, not the part."""
    if union_coverage < th.gross_coverage:
        return Severity.ERROR
    if union_coverage < th.min_coverage:
        return Severity.WARNING
    return Severity.INFO


def contact_plate(f: ElementFit, th: FitThresholds) -> bool:
    """Whether ``f``'s element is a thin box (its thinnest side under ``contact_plate_ratio``
    of the next) whose outer face lies on the mesh's extreme along that side (within
    ``protrusion_floor_m``): a sole plate, the contact surface of a foot, deliberately unlike the
    foot's mesh."""
    box = f.element.primitive
    if not isinstance(box, Box) or f.gaps is None:
        return False
    sides = sorted(range(3), key=lambda i: box.size[i])
    thin = sides[0]
    if box.size[thin] > th.contact_plate_ratio * box.size[sides[1]]:
        return False
    name = AXIS_NAMES[thin]
    return max(f.gaps[f"{name}-"], f.gaps[f"{name}+"]) >= -th.protrusion_floor_m


def _not_covered(
    link: Link,
    shape: Shape,
    f: ElementFit,
    th: FitThresholds,
    data: dict[str, Any],
    union_coverage: float,
    plate: bool = False,
    tyre: float | None = None,
) -> Diagnostic:
    assert f.coverage is not None and f.protrusion_max is not None and f.protrusion_p95 is not None
    kind = type(shape.geometry).__name__.lower()
    axis_share, axis_text = _worst_axis(shape, f)
    message = rules.COLLISION_DOES_NOT_COVER.message(
        label=shape.label,
        kind=kind,
        axis_share=axis_share,
        coverage=f.coverage,
        axis_text=axis_text,
        protrusion_max=length(f.protrusion_max),
        protrusion_p95=length(f.protrusion_p95),
    )
    if data.get("part_note"):
        message += f" ({data['part_note']})"
    fix = f"Enlarge or move the {kind} to enclose the mesh"
    if f.suggested is not None:
        fix += f"; a fitted {kind}{_grown_note(f, kind, th.protrusion_tolerance_m)}:\n{f.suggested.urdf()}"
    severity = uncovered_severity(union_coverage, th)
    if plate:
        message += "; it is a contact plate on the mesh's face at the end of a chain of moving joints (a sole)"
        severity = Severity.INFO
    elif severity is not Severity.INFO and tyre is not None and tyre >= th.min_coverage:
        message += rules.COLLISION_DOES_NOT_COVER.message("tyre", tyre=tyre)
        severity = Severity.INFO
    elif severity is Severity.INFO:
        message += (
            f"; with the adjacent links' collision geometry (joints at zero) {union_coverage:.0%} of the link's "
            "surface is covered: a small part sticks out"
        )
    return _element_diagnostic(rules.COLLISION_DOES_NOT_COVER, link, shape, message, data, fix, severity)


def _offset(
    link: Link, shape: Shape, f: ElementFit, visual_centre: np.ndarray, data: dict[str, Any], disjoint: bool
) -> Diagnostic:
    kind = type(shape.geometry).__name__.lower()
    # centring on its part of the mesh when it has one, else on the whole visual geometry
    shift = f.shift if f.shift is not None else visual_centre - f.element.centre
    data = data | {"offset": [round(float(v), 6) + 0.0 for v in shift], "disjoint": disjoint}
    rule = rules.COLLISION_OFFSET
    distance = length(float(np.linalg.norm(shift)))
    if disjoint:
        inside = rule.message("disjoint_inside", mesh_inside=f.mesh_inside, tolerance=length(data["tolerance"]))
        if f.in_hull is not None:
            inside += rule.message("disjoint_in_hull", in_hull=f.in_hull)
        message = rule.message(
            "disjoint",
            label=shape.label,
            kind=kind,
            inside=inside,
            nearest=length(max(f.nearest, 0.0)),
            distance=distance,
            offset=vector(shift),
        )
    else:
        assert f.coverage is not None and f.protrusion_max is not None
        message = rule.message(
            "misplaced",
            label=shape.label,
            kind=kind,
            distance=distance,
            coverage=f.coverage,
            protrusion_max=length(f.protrusion_max),
            offset=vector(shift),
        )
    fix = f"Move {shape.label} by {vector(shift)}: {_moved_origin(shape, shift)}"
    if disjoint and data.get("multi"):
        fix = f"Move {shape.label} onto the part of the link it should cover, or remove it."
    return _element_diagnostic(rules.COLLISION_OFFSET, link, shape, message, data, fix)


def _axis(link: Link, shape: Shape, f: ElementFit, data: dict[str, Any]) -> Diagnostic:
    alt = f.axis_alternative
    assert alt is not None and f.coverage is not None
    turn_axis = np.array(
        [alt.turn[2, 1] - alt.turn[1, 2], alt.turn[0, 2] - alt.turn[2, 0], alt.turn[1, 0] - alt.turn[0, 1]]
    )
    angle = np.degrees(rotation_angle(alt.turn))
    rpy = " ".join(fmt(v, 4) for v in data["axis_alternative"]["rpy"])
    message = rules.CYLINDER_AXIS_MISALIGNED.message(
        label=shape.label,
        along=direction(f.element.rotation[:, 2]),
        axis=direction(alt.axis),
        angle=angle,
        turn_axis=direction(turn_axis),
        turned_coverage=alt.coverage,
        coverage=f.coverage,
    )
    xyz = " ".join(fmt(float(v)) for v in shape.origin.xyz)
    fix = f'Set rpy="{rpy}" on the cylinder\'s origin: <origin xyz="{xyz}" rpy="{rpy}"/>'
    return _element_diagnostic(rules.CYLINDER_AXIS_MISALIGNED, link, shape, message, data, fix)


def _mesh_mismatch(
    link: Link,
    shape: Shape,
    f: ElementFit,
    th: FitThresholds,
    data: dict[str, Any],
    union_coverage: float,
    size: float,
) -> Diagnostic | None:
    c = f.comparison
    assert c is not None and f.coverage is not None and f.protrusion_max is not None
    rule = rules.COLLISION_MESH_MISMATCH
    reasons = []
    sticks_out = not f.covers(th)
    if sticks_out:
        reasons.append(rule.message("sticks_out", protrusion_max=length(f.protrusion_max), coverage=f.coverage))
    if c.overshoot_max > th.mesh_overshoot_tolerance_m:
        reasons.append(rule.message("overshoot", overshoot=length(c.overshoot_max)))
    if not reasons:
        return None
    # reaching past the visual errs on the safe side (false contacts, never missed ones) until it is
    # gross: a collision mesh reaching out a quarter of the part's size is another shape or another place;
    # the visual sticking out is judged with the link's other collision meshes, as a union
    gross = c.overshoot_max >= max(th.mesh_overshoot_tolerance_m, th.mesh_gross_overshoot_fraction * size)
    severity = uncovered_severity(union_coverage, th) if sticks_out else Severity.INFO
    if gross and severity is Severity.INFO:
        severity = Severity.WARNING
    assert isinstance(shape.geometry, Mesh)
    name = PurePosixPath(shape.geometry.filename).name
    message = rule.message(
        label=shape.label, name=name, reasons="; ".join(reasons), surface_distance=length(c.surface_distance_max)
    )
    if severity is Severity.INFO:
        message += rule.message("lowered", union_coverage=union_coverage)
    return _element_diagnostic(rules.COLLISION_MESH_MISMATCH, link, shape, message, data, severity=severity)


SIDE_NAMES = {
    "radial": "radius",
    "x-": "-x face",
    "x+": "+x face",
    "y-": "-y face",
    "y+": "+y face",
    "z-": "-z face",
    "z+": "+z face",
}


def _oversized(
    link: Link,
    shape: Shape,
    f: ElementFit,
    th: FitThresholds,
    data: dict[str, Any],
    contact: bool,
    oversize: Oversize | None,
) -> Diagnostic | None:
    """GC302 for an element that covers its part: a side standing off it or the wrong kind of
    shape (``oversize``, :mod:`geomcheck.checks.fit_oversize`), or the lone element's slack."""
    s = f.suggested
    kind = type(shape.geometry).__name__.lower()
    rule = rules.COLLISION_OVERSIZED
    slack = f.slack is not None and s is not None and s.slack is not None and f.slack > th.max_slack
    slack = (
        slack
        and f.slack is not None
        and s is not None
        and s.slack is not None
        and f.slack >= th.min_slack_gain * s.slack
    )
    if oversize is None and not slack:
        return None
    if oversize is not None and oversize.better is not None:
        better = oversize.better
        message = rule.message(
            "kind",
            label=shape.label,
            kind=kind,
            kind_ratio=oversize.kind_ratio,
            better=better.type,
            coverage=better.coverage,
        )
        fix = f"Use the fitted {better.type}:\n{better.urdf()}"
        data = data | {"kind_ratio": round(float(oversize.kind_ratio or 0.0), 3), "better_kind": better.to_dict()}
    elif oversize is not None:
        assert oversize.side is not None and s is not None
        message = rule.message(
            "standoff",
            label=shape.label,
            kind=kind,
            side=SIDE_NAMES[oversize.side],
            gap=length(oversize.gap),
            span=length(oversize.span),
            allowed=length(oversize.allowed),
            volume_ratio=oversize.volume_ratio,
        )
        fix = f"Use the fitted {kind}:\n{s.urdf()}"
        data = data | {
            "standoff_side": oversize.side,
            "standoff_mm": mm(oversize.gap),
            "standoff_allowed_mm": mm(oversize.allowed),
            "volume_ratio": round(float(oversize.volume_ratio or 0.0), 3),
        }
    else:
        assert s is not None
        message = rule.message(label=shape.label, kind=kind, slack=f.slack, fitted_slack=s.slack)
        fix = f"Use the fitted {kind}:\n{s.urdf()}"
    severity = None
    if contact:
        message += rule.message("contact")
        severity = Severity.INFO
    return _element_diagnostic(rule, link, shape, message, data, fix, severity)


def classify(
    link: Link,
    shape: Shape,
    f: ElementFit,
    th: FitThresholds,
    multi: bool,
    metrics: dict[str, Any],
    visual_centre: np.ndarray,
    union_coverage: float | None = None,
    contact: bool = False,
    plate: bool = False,
    oversize: Oversize | None = None,
    visual_size: float = 0.0,
    tyre: float | None = None,
) -> Diagnostic | None:
    """The one finding (if any) about a fitted element, most specific rule first; ``metrics``
    is ``f.to_dict()``, carried in the finding's data; ``visual_centre`` (3,) the centre of
    the link's visual bounds [m]; ``union_coverage`` the share of the link's surface its
    collision elements cover together (the element's own coverage when not given);
    ``contact`` whether the element is a sphere at the distal end of a chain (a foot);
    ``plate`` whether it is a contact plate there (see :func:`contact_plate`); ``oversize`` how
    far it reaches past its part when it covers it (GC302)."""
    data: dict[str, Any] = {
        "element": f.element.type,
        "multi": multi,
        "tolerance": th.protrusion_tolerance_m,
        **metrics,
    }
    if f.disjoint(th):
        return _offset(link, shape, f, visual_centre, data, disjoint=True)
    if f.part_points == 0 or f.coverage is None or f.protrusion_max is None:
        return None
    covers = f.covers(th)
    union = f.coverage if union_coverage is None else union_coverage
    shift = float(np.linalg.norm(f.shift)) if f.shift is not None else 0.0
    # an element that still covers most of the link is not somewhere else: a small part sticks out
    misplaced = (
        not covers
        and union < th.min_coverage
        and not multi
        and f.fits_when_moved
        and shift > th.protrusion_tolerance_m
        and shift >= th.offset_min_fraction * f.element.size
    )
    if f.element.primitive is None:
        if misplaced:
            return _offset(link, shape, f, visual_centre, data, disjoint=False)
        return _mesh_mismatch(link, shape, f, th, data, union, visual_size)
    if covers:
        # a union's elements overlap by design (capsules): its inner faces are not judged, and slack
        # (volume against the part's hull) only for lone elements
        if multi:
            return (
                None
                if oversize is None
                else _oversized(link, shape, f, replace(th, max_slack=np.inf), data, contact, oversize)
            )
        return _oversized(link, shape, f, th, data, contact, oversize)
    alt = f.axis_alternative
    if alt is not None and alt.coverage >= f.coverage + th.axis_coverage_gain and alt.protrusion_max < f.protrusion_max:
        return _axis(link, shape, f, data)
    if misplaced:
        return _offset(link, shape, f, visual_centre, data, disjoint=False)
    return _not_covered(link, shape, f, th, data, union, plate, tyre)


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
    for n in neighbours(ctx.robot, link.name):
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


def lent_to(ctx: CheckContext, link: Link, element: CollisionElement, th: FitThresholds) -> str | None:
    """The neighbour whose mesh ``element`` covers instead of its own link's, if any: an
    element placed across a joint, the same at every joint position (Franka's capsules)."""
    for n in neighbours(ctx.robot, link.name):
        if not invariant(element, n):
            continue
        cloud = link_visual(ctx, ctx.robot.link_map[n.link], th)
        if not isinstance(cloud, VisualCloud):
            continue
        theirs = cloud.samples @ n.rotation.T + n.translation
        if np.mean(element.signed_distance(theirs) <= th.protrusion_tolerance_m) >= th.offset_overlap_fraction:
            return n.link
    return None


def caps_a_capsule(element: CollisionElement, elements: list[CollisionElement], tolerance: float) -> bool:
    """Whether ``element`` is a sphere that closes a capsule of its own link: centred on an end
    of the axis of one of the link's cylinders, with that cylinder's radius (within
    ``tolerance`` [m]). URDF has no capsule; it is written as a cylinder and two such spheres
    (Franka's collision model), and a cap's reach past the link's mesh is the capsule's rounded
    end, placed with the cylinder: the cap is judged with its capsule (through the cylinder's
    own fit), not as an element lying on a neighbour's mesh."""
    if not isinstance(element.primitive, Sphere):
        return False
    radius = element.primitive.radius
    for other in elements:
        cylinder = other.primitive
        if other is element or not isinstance(cylinder, Cylinder) or abs(cylinder.radius - radius) > tolerance:
            continue
        half = 0.5 * cylinder.length * np.asarray(other.rotation, dtype=float)[:, 2]
        centre = np.asarray(other.translation, dtype=float)
        ends = (centre + half, centre - half)
        if any(np.linalg.norm(np.asarray(element.translation, dtype=float) - end) <= tolerance for end in ends):
            return True
    return False


def part_tolerance(visual: VisualCloud, th: FitThresholds) -> float:
    """How far [m] this link's mesh may stick out of its collision geometry: the fixed
    ``protrusion_tolerance_m``, or ``protrusion_tolerance_fraction`` of the mesh's smallest
    extent (bounding box in the link frame) when smaller, never below ``protrusion_floor_m``:
    10 mm is nothing on a base but the whole thickness of a finger. On a large part,
    ``protrusion_size_fraction`` of its largest extent when that is more (at most
    ``protrusion_size_cap_m``): a primitive standing for a 0.5 m body is not expected to follow
    its detail closer than that."""
    spans = np.ptp(visual.bounds(), axis=0)
    relative = max(th.protrusion_tolerance_fraction * float(spans.min()), th.protrusion_floor_m)
    large = min(th.protrusion_size_fraction * float(spans.max()), th.protrusion_size_cap_m)
    return max(min(th.protrusion_tolerance_m, relative), large)


def element_tolerance(f: ElementFit, th: FitThresholds) -> float:
    """The tolerance [m] for one element: the link's, or ``protrusion_tolerance_fraction`` of
    the smallest extent of the part of the mesh the element answers for (along its own axes)
    when smaller, never below ``protrusion_floor_m``: a finger pad's box in a union of four is
    judged at the pad's size, not the finger's."""
    spans = [v[2] for v in (f.extent or {}).values() if v[2] > 0.0]
    if not spans:
        return th.protrusion_tolerance_m
    relative = max(th.protrusion_tolerance_fraction * min(spans), th.protrusion_floor_m)
    return min(th.protrusion_tolerance_m, relative)


def _lent(link: Link, shape: Shape, f: ElementFit, neighbour: str, link_fit: LinkFit, th: FitThresholds) -> Diagnostic:
    """GC303 for an element that lies on a neighbour's mesh rather than its own link's: it
    makes the link collide where the link is not, whatever covers the link's mesh."""
    kind = type(shape.geometry).__name__.lower()
    inside = f.in_hull if f.in_hull is not None else f.mesh_inside
    covered = link_fit.coverage >= th.min_coverage and link_fit.protrusion_max <= th.protrusion_tolerance_m
    message = rules.COLLISION_OFFSET.message(
        "lent",
        label=shape.label,
        kind=kind,
        link=link.name,
        outside=1.0 - inside,
        neighbour=neighbour,
        link_coverage=link_fit.coverage,
        link_protrusion_max=length(link_fit.protrusion_max),
    )
    data = {
        "element": f.element.type,
        "covers_neighbour": neighbour,
        "outside_own_mesh": round(1.0 - inside, 4),
        "link_coverage": round(link_fit.coverage, 4),
        "link_protrusion_max_mm": mm(link_fit.protrusion_max),
        "tolerance": th.protrusion_tolerance_m,
        "disjoint": True,
        "multi": True,
    }
    if covered:
        fix = (
            f"Move {shape.label} to link {neighbour} (its mesh is where the element is), or onto the part of "
            f"link {link.name} it should cover."
        )
        severity = Severity.WARNING
    else:
        fix = f"Move {shape.label} onto link {link.name}'s mesh: the link's own geometry is left uncovered."
        severity = Severity.ERROR
    return _element_diagnostic(rules.COLLISION_OFFSET, link, shape, message, data, fix, severity)


def _skip(entry: dict[str, Any], result: FamilyResult, link: Link, reason: str) -> dict[str, Any]:
    entry["skipped"].append(f"fit: {reason}")
    result.skipped.append(SkippedCheck("fit", link.name, reason))
    return entry


@dataclass
class Reach:
    """The robot's rigid ``groups`` and, once computed per group anchor, the convex bound of the
    space its collision geometry sweeps in its root group's frame (``(root, hull)``; ``None``
    without collision geometry or when it reaches anywhere: see ``reaches_anywhere``)."""

    groups: RigidGroups
    bounds: dict[str, tuple[str, ConvexRegion | None] | None] = field(default_factory=dict)
    reaches_anywhere: set[str] = field(default_factory=set)


def distal(robot: Robot, groups: RigidGroups, link: str) -> bool:
    """Whether ``link`` ends a chain of moving joints: its rigid group moves and nothing moves
    below it (a foot, a fingertip); a sphere there is the chain's contact shape."""
    anchor = groups.anchor.get(link)
    if anchor is None or anchor not in robot.parent_joint:
        return False
    members = groups.members(anchor)
    return not any(j.is_moving for m in members for j in robot.child_joints.get(m, ()))


def _group_elements(ctx: CheckContext, groups: RigidGroups, anchor: str, skip: str = "") -> list[CollisionElement]:
    """The collision elements of the group anchored at ``anchor``, in the anchor's frame."""
    out: list[CollisionElement] = []
    for name in groups.members(anchor):
        if name == skip:
            continue
        elements = link_elements(ctx, ctx.robot.link_map[name])
        if isinstance(elements, str):
            continue
        rotation, translation = groups.pose[name]
        out.extend(moved(e, rotation, translation) for e in elements)
    return out


def _holder_in(
    ctx: CheckContext,
    positions: list[np.ndarray],
    anchor: str,
    skip: str,
    groups: RigidGroups,
    th: FitThresholds,
    housings: bool,
) -> tuple[float, str, str] | None:
    """``(share, link, what)``: the link of the group at ``anchor`` (but ``skip``) holding the
    largest share of the samples (n, 3, anchor frame) within the tolerance at each of the
    ``positions`` (the smallest share over them), in its collision geometry or, with
    ``housings``, its visual geometry's convex hull."""
    best: tuple[float, str, str] | None = None
    samples = np.concatenate(positions)
    count = len(positions)

    def least(sd: np.ndarray) -> float:
        return float(np.mean(sd.reshape(count, -1) <= th.protrusion_tolerance_m, axis=1).min())

    for name in groups.members(anchor):
        if name == skip:
            continue
        other = ctx.robot.link_map[name]
        r, t = groups.pose[name]
        elements = link_elements(ctx, other)
        if not isinstance(elements, str) and elements:
            share = least(np.min([moved(e, r, t).signed_distance(samples) for e in elements], axis=0))
            if best is None or share > best[0]:
                best = (share, name, "collision geometry")
        housing = link_visual(ctx, other, th) if housings else None
        if isinstance(housing, VisualCloud) and housing.hull is not None:
            share = least(housing.hull.moved(r, t).signed_distance(samples))
            if best is None or share > best[0] + 1e-9:
                best = (share, name, "visual geometry's convex hull")
    return best


def spins_with_its_group(robot: Robot, link: Link, groups: RigidGroups) -> bool:
    """Whether every visual of ``link`` is a primitive the same at every position of the joint
    its rigid group hangs from (a sphere centred on the axis, a cylinder along it): a rotor
    fixed to the link it drives but centred on that link's joint."""
    anchor = groups.anchor[link.name]
    joint = robot.parent_joint.get(anchor)
    if joint is None or joint.type not in ("revolute", "continuous") or not link.visuals:
        return False
    axis = np.asarray(joint.axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    if norm == 0.0:
        return False
    here = Neighbour(joint.parent, joint.name, np.eye(3), np.zeros(3), axis / norm, np.zeros(3))
    rotation, translation = groups.pose[link.name]
    for shape in link.visuals:
        g = shape.geometry
        if not isinstance(g, (Cylinder, Sphere)):
            return False
        r, t = pose_frame(shape.origin)
        if not invariant(CollisionElement(shape.index, rotation @ r, rotation @ t + translation, primitive=g), here):
            return False
    return True


def joint_motions(joint: Joint, th: FitThresholds) -> list[tuple[np.ndarray, np.ndarray]] | None:
    """Motions ``(rotation (3, 3), translation (3,))`` of the joint's child frame over its range:
    ``joint_samples`` positions between its limits (a full turn for a continuous joint or a
    revolute one without limits), position zero included; ``None`` for any other joint."""
    axis = np.asarray(joint.axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    if norm == 0.0:
        return None
    axis = axis / norm
    limit = joint.limit
    bounded = limit is not None and limit.lower is not None and limit.upper is not None
    if joint.type == "prismatic" and bounded:
        assert limit is not None and limit.lower is not None and limit.upper is not None
        travel = np.append(np.linspace(limit.lower, limit.upper, th.joint_samples), 0.0)
        return [(np.eye(3), float(d) * axis) for d in travel]
    if joint.type not in ("revolute", "continuous"):
        return None
    if joint.type == "revolute" and bounded:
        assert limit is not None and limit.lower is not None and limit.upper is not None
        angles = np.append(np.linspace(limit.lower, limit.upper, th.joint_samples), 0.0)
    else:
        angles = np.linspace(0.0, 2.0 * np.pi, 2 * th.joint_samples, endpoint=False)
    return [(r, np.zeros(3)) for r in rotation_matrices(axis, angles)]


def _covering_link(
    ctx: CheckContext, link: Link, visual: VisualCloud, groups: RigidGroups, th: FitThresholds
) -> tuple[str, str, str | None] | None:
    """``(link, what, joint)``: the link that holds ``link``'s visual surface (over ``min_coverage`` of
    it within the tolerance) in its collision geometry or inside its own visual geometry's
    convex hull, if any: a link of its rigid group, or of the group it hangs from, then at every
    position of the joint between them (``joint_samples`` positions over its range). A part
    inside the body it is bolted to (a rotor in its motor housing, a logo on a torso) or moving
    only within it (a rocker pivoting inside the chassis, a rotor turning about its own axis) is
    touched through that body, whose own collision geometry the fit of that body judges."""
    anchor = groups.anchor.get(link.name)
    if anchor is None:
        return None
    rotation, translation = groups.pose[link.name]
    samples = visual.samples @ rotation.T + translation
    # inside a housing's mesh, a part is touched through the housing once the housing's own
    # collision geometry is right (its fit says whether it is); not so a part ending a chain (a
    # foot, a fingertip: the chain's contact point), nor one moving other than turning in place
    housed = not distal(ctx.robot, groups, link.name)
    found: list[tuple[tuple[float, str, str] | None, str | None]] = [
        (_holder_in(ctx, [samples], anchor, link.name, groups, th, housed), None)
    ]
    joint = ctx.robot.parent_joint.get(anchor)
    motions = None if joint is None or joint.parent not in groups.anchor else joint_motions(joint, th)
    if joint is not None and motions is not None:
        r, t = groups.pose[joint.parent]
        origin_r, origin_t = joint.origin.rotation(), np.asarray(joint.origin.xyz, dtype=float)
        positions = [((samples @ m.T + d) @ origin_r.T + origin_t) @ r.T + t for m, d in motions]
        spins = housed and spins_with_its_group(ctx.robot, link, groups)
        above = groups.anchor[joint.parent]
        found.append((_holder_in(ctx, positions, above, link.name, groups, th, spins), joint.name))
    held = [(f, j) for f, j in found if f is not None]
    if not held:
        return None
    best, through = max(held, key=lambda h: h[0][0])
    return (best[1], best[2], through) if best[0] >= th.min_coverage else None


def _resting_holders(
    ctx: CheckContext, link: Link, visual: VisualCloud, groups: RigidGroups, th: FitThresholds
) -> tuple[float, list[str]]:
    """``(share, links)``: the share of ``link``'s visual surface within the tolerance of the
    collision geometry of the links around its rigid group at rest (zero joint positions), and
    those links. Around: joined to the group by a fixed, revolute or continuous joint, as GC301
    counts a link's neighbours; a neighbour without collision geometry is passed through to the
    links beyond it (a crank between a rod and the leg it lies along, a hip yaw housing between
    the pelvis and the thigh)."""
    anchor = groups.anchor.get(link.name)
    if anchor is None:
        return 0.0, []
    rotation, translation = groups.pose[link.name]
    samples = visual.samples @ rotation.T + translation
    members = groups.members(anchor)
    seen = set(members)
    frontier = [(name, *groups.pose[name]) for name in members]
    distances: list[np.ndarray] = []
    holders: list[str] = []
    while frontier:
        beyond = []
        for name, r, t in frontier:
            for n in resting_neighbours(ctx.robot, name):
                if n.link in seen:
                    continue
                seen.add(n.link)
                # the neighbour's frame in the anchor's: through the member's pose
                nr, nt = r @ n.rotation, r @ n.translation + t
                elements = link_elements(ctx, ctx.robot.link_map[n.link])
                if isinstance(elements, str) or not elements:
                    beyond.append((n.link, nr, nt))
                    continue
                distances.extend(moved(e, nr, nt).signed_distance(samples) for e in elements)
                holders.append(n.link)
        frontier = beyond
    if not distances or not len(samples):
        return 0.0, []
    return float(np.mean(np.min(distances, axis=0) <= th.protrusion_tolerance_m)), holders


def _group_bound(ctx: CheckContext, reach: Reach, anchor: str) -> tuple[str, ConvexRegion | None] | None:
    """The swept bound of the group at ``anchor`` (see :class:`Reach`), computed once."""
    if anchor not in reach.bounds:
        elements = _group_elements(ctx, reach.groups, anchor)
        corners = [element_corners(e) for e in elements]
        points = np.concatenate(corners) if corners else np.zeros((0, 3))
        # a wheel on the root body occupies the same space at every angle: it never comes at a part
        static = spins_in_place(ctx.robot, anchor, elements)
        swept = swept_bound(ctx.robot, reach.groups, anchor, points) if len(points) and not static else None
        if swept is None and len(points) and not static:
            reach.reaches_anywhere.add(anchor)
        reach.bounds[anchor] = None if swept is None else (swept[0], ConvexRegion.of(swept[1]))
    return reach.bounds[anchor]


def spins_in_place(robot: Robot, anchor: str, elements: list[CollisionElement]) -> bool:
    """Whether the group at ``anchor`` hangs from the root body by one revolute or continuous
    joint about which all its collision geometry is symmetric (spheres centred on the axis,
    cylinders along it): it occupies the same space at every joint position."""
    joint = robot.parent_joint[anchor]
    if any(j.is_moving for j in _chain(robot, joint.parent)):
        return False
    axis = np.asarray(joint.axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    if joint.type not in ("revolute", "continuous") or norm == 0.0 or not elements:
        return False
    here = Neighbour(joint.parent, joint.name, np.eye(3), np.zeros(3), axis / norm, np.zeros(3))
    return all(invariant(e, here) for e in elements)


def _chain(robot: Robot, link: str) -> list[Joint]:
    """The joints from ``link`` up to its tree's root."""
    out: list[Joint] = []
    while link in robot.parent_joint:
        joint = robot.parent_joint[link]
        out.append(joint)
        link = joint.parent
    return out


def _reaching_link(ctx: CheckContext, link: Link, visual: VisualCloud, reach: Reach) -> str | None:
    """A link of another rigid group whose swept space meets ``link``'s visual geometry, if any;
    ``link`` is in a root group (it moves with the robot, not relative to it)."""
    groups = reach.groups
    anchor = groups.anchor[link.name]
    rotation, translation = groups.pose[link.name]
    points = visual.points @ rotation.T + translation
    for other in dict.fromkeys(groups.anchor.values()):
        if other == anchor or other not in ctx.robot.parent_joint:
            continue
        bound = _group_bound(ctx, reach, other)
        if other in reach.reaches_anywhere:
            return other
        if bound is None or bound[0] != anchor or bound[1] is None:
            continue
        if bool((bound[1].signed_distance(points) <= 0.0).any()):
            return other
    return None


def _without_collision(
    ctx: CheckContext, link: Link, visual: VisualCloud, th: FitThresholds, entry: dict[str, Any], reach: Reach
) -> Diagnostic:
    tol = th.protrusion_tolerance_m
    box = suggest(Box, visual.vertices, visual.samples, visual.hull, None, th.simple_fit_margin, tol)
    entry["suggested"] = None if box is None else box.to_dict()
    count = len(link.visuals)
    rule = rules.VISUAL_WITHOUT_COLLISION
    message = rule.message(link=link.name, count=count, plural="s" if count > 1 else "")
    fix = "Add a <collision> element" + (f", for example the box enclosing the visual:\n{box.urdf()}" if box else "")
    # what a missing collision costs depends on what can touch the part: nothing reaches a part
    # inside the collision geometry of the body it is bolted to, nor a part of the robot's root
    # body that no moving body of the robot sweeps through
    covering = _covering_link(ctx, link, visual, reach.groups, th)
    covered_by = None if covering is None else covering[0]
    reached_by: str | None = None
    held_by: list[str] | None = None
    severity = None
    anchor = reach.groups.anchor.get(link.name)
    if covering is not None and covering[2] is not None:
        message += rule.message("enclosed", cover=covering[0], what=covering[1], joint=covering[2])
        severity = Severity.INFO
    elif covering is not None:
        message += rule.message("covered", cover=covering[0], what=covering[1])
        severity = Severity.INFO
    elif (resting := _resting_holders(ctx, link, visual, reach.groups, th))[0] >= th.min_coverage:
        message += rule.message("resting", share=resting[0], holders=", ".join(resting[1]))
        severity = Severity.INFO
        held_by = resting[1]
    elif anchor is not None and anchor not in ctx.robot.parent_joint:
        reached_by = _reaching_link(ctx, link, visual, reach)
        if reached_by is None:
            # no moving link reaches it, but the world does: planners collide the robot with obstacles and
            # simulators with the ground and walls, and a part no collision geometry holds passes through them
            message += rule.message("unreached", anchor=anchor)
        else:
            message += rule.message("reached", other=reached_by)
    elif anchor is not None:
        message += rule.message("moving", joint=ctx.robot.parent_joint[anchor].name)
    data: dict[str, Any] = {"suggested": entry["suggested"], "covered_by": covered_by, "reached_by": reached_by}
    if held_by is not None:
        data["held_at_rest_by"] = held_by
    return rule.diagnose(
        message, help=fix, link=link.name, about="collision", location=link.location, data=data, severity=severity
    )


def resting_neighbours(robot: Robot, link: str) -> list[Neighbour]:
    """The links next to ``link`` at rest: across a fixed, revolute or continuous joint, and those
    a loop-closing constraint holds against it (:mod:`geomcheck.checks.closures`)."""
    return [*neighbours(robot, link), *closure_neighbours(robot, link)]


def tyre_coverage(
    ctx: CheckContext, link: Link, visual: VisualCloud, elements: list[CollisionElement], th: FitThresholds
) -> float | None:
    """For a wheel, the share of its visual surface the collision geometry holds or that lies within
    its tyre's radius; ``None`` for any other link. A wheel is a link its parent joint turns fully
    (continuous) about the axis of one of its collision cylinders, which passes through the joint:
    it touches the ground and obstacles with its tyre, and a hub or a motor cover standing out of the
    cylinder's faces, within its radius, touches nothing the tyre does not reach first."""
    joint = ctx.robot.parent_joint.get(link.name)
    if joint is None or joint.type != "continuous" or not len(visual.samples):
        return None
    axis = np.asarray(joint.axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    if norm == 0.0:
        return None
    axis = axis / norm
    for element in elements:
        cylinder = element.primitive
        if not isinstance(cylinder, Cylinder) or isinstance(cylinder, Capsule):
            continue
        own = np.asarray(element.rotation, dtype=float)[:, 2]
        centre = np.asarray(element.translation, dtype=float)
        off_axis = float(np.linalg.norm(centre - (centre @ axis) * axis))
        if abs(float(own @ axis)) < TYRE_AXIS_COS or off_axis > th.protrusion_tolerance_m:
            continue
        rel = visual.samples - centre
        radial = np.linalg.norm(rel - np.outer(rel @ own, own), axis=1)
        held = np.min([e.signed_distance(visual.samples) for e in elements], axis=0) <= th.protrusion_tolerance_m
        return float(np.mean(held | (radial <= cylinder.radius + th.protrusion_tolerance_m)))
    return None


def resting_elements(ctx: CheckContext, link: Link) -> list[CollisionElement]:
    """The collision elements of the links next to ``link`` at rest (zero joint positions), in its frame."""
    out: list[CollisionElement] = []
    for n in resting_neighbours(ctx.robot, link.name):
        theirs = link_elements(ctx, ctx.robot.link_map[n.link])
        if not isinstance(theirs, str):
            out.extend(moved(e, n.rotation, n.translation) for e in theirs)
    return out


def resting_coverage(
    ctx: CheckContext, link: Link, visual: VisualCloud, elements: list[CollisionElement], th: FitThresholds
) -> float:
    """The share of ``link``'s visual surface within the tolerance of its own collision elements
    or of any adjacent link's at the zero position of the joint between them: a finger's boxes
    running joint to joint leave the knuckles that reach past each joint to the next box, so the
    chain's collision geometry is continuous even where a link's own box stops."""
    distances = [e.signed_distance(visual.samples) for e in elements]
    for n in resting_neighbours(ctx.robot, link.name):
        theirs = link_elements(ctx, ctx.robot.link_map[n.link])
        if not isinstance(theirs, str):
            distances.extend(moved(e, n.rotation, n.translation).signed_distance(visual.samples) for e in theirs)
    if not distances or not len(visual.samples):
        return 0.0
    return float(np.mean(np.min(distances, axis=0) <= th.protrusion_tolerance_m))


def stored_resting_coverage_of(
    ctx: CheckContext, link: Link, visual: VisualCloud, elements: list[CollisionElement], th: FitThresholds
) -> float:
    """:func:`resting_coverage`, kept in the active store (:mod:`geomcheck.checks.coverage_cache`)."""
    return stored_resting_coverage(
        link,
        [(ctx.robot.link_map[n.link], n) for n in resting_neighbours(ctx.robot, link.name)],
        lambda: resting_coverage(ctx, link, visual, elements, th),
        ctx.analyses.mesh_digest,
        (ctx.thresholds, th),
    )


def check_link(ctx: CheckContext, link: Link, th: FitThresholds, result: FamilyResult, reach: Reach) -> dict[str, Any]:
    """Fit ``link``, adding its findings and skipped checks to ``result``; its section entry."""
    entry: dict[str, Any] = {
        "link": link.name,
        "visual_meshes": visual_mesh_entries(ctx, link),
        "collisions": [collision_entry(s) for s in link.collisions],
        "union": None,
        "borrowed": [],
        "suggested": None,
        "skipped": [],
    }
    visual = link_visual(ctx, link, th)
    if visual is None:
        if link.collisions:
            entry["skipped"].append("fit: no visual geometry to compare with")
        return entry
    if isinstance(visual, str):
        return _skip(entry, result, link, visual)
    extent = float(np.ptp(visual.bounds(), axis=0).max())
    if extent <= th.placeholder_extent_m:
        entry["skipped"].append(f"fit: the visual geometry is a placeholder ({length(extent)} across)")
        return entry
    th = replace(th, protrusion_tolerance_m=part_tolerance(visual, th))
    if not link.collisions:
        result.diagnostics.append(_without_collision(ctx, link, visual, th, entry, reach))
        return entry
    elements = link_elements(ctx, link)
    if isinstance(elements, str):
        return _skip(entry, result, link, elements)
    borrowed = borrowed_elements(ctx, link)
    entry["borrowed"] = [
        {"link": n.link, "joint": n.joint, "about": f"collision[{e.index}]", "type": e.type} for e, n in borrowed
    ]
    link_fit = alike_fit(ctx, link, borrowed, lambda: fit_link(visual, elements, th, [e for e, _ in borrowed]))
    ctx.analyses.fits.links[link.name] = link_fit
    entry["precision"] = visual.precision()
    entry["union"] = {
        "coverage": ratio(link_fit.coverage),
        "protrusion_max_mm": mm(link_fit.protrusion_max),
        "protrusion_p95_mm": mm(link_fit.protrusion_p95),
        "borrowed_share": ratio(link_fit.borrowed_share),
    }
    multi = len(elements) > 1
    at_rest = link_fit.coverage
    if at_rest < 1.0:  # a share is at most 1: a link its own elements cover needs no neighbour's
        at_rest = max(at_rest, stored_resting_coverage_of(ctx, link, visual, elements, th))
    entry["union"]["coverage_at_rest"] = ratio(at_rest)
    tyre = tyre_coverage(ctx, link, visual, elements, th) if at_rest < th.min_coverage else None
    notes = []
    if len(elements) > 1:
        notes.append("its part of the mesh: the points nearer to it than to the link's other collision elements")
    if link_fit.borrowed_share >= 0.005:
        names = ", ".join(sorted({n.link for _, n in borrowed}))
        notes.append(f"{link_fit.borrowed_share:.0%} of the mesh is covered across a joint by {names}")
    own_elements = [f.element for f in link_fit.elements]
    for shape, fitted, col in zip(link.collisions, link_fit.elements, entry["collisions"], strict=True):
        col["fit"] = fitted.to_dict()
        cap = caps_a_capsule(fitted.element, own_elements, th.capsule_cap_tolerance_m)
        col["fit"]["capsule_cap"] = cap
        if cap and fitted.disjoint(th):
            col["fit"]["covers_neighbour"] = None
            continue  # the capsule's rounded end past the mesh: judged with the capsule, by its cylinder
        lends = lent_to(ctx, link, fitted.element, th) if fitted.disjoint(th) else None
        col["fit"]["covers_neighbour"] = lends
        if lends is not None:
            result.diagnostics.append(_lent(link, shape, fitted, lends, link_fit, th))
        else:
            centre = visual.bounds().mean(axis=0)
            metrics = {**col["fit"], "part_note": "; ".join(notes) or None}
            own = replace(th, protrusion_tolerance_m=element_tolerance(fitted, th))
            end = distal(ctx.robot, reach.groups, link.name)
            contact = end and isinstance(shape.geometry, Sphere)
            plate = end and contact_plate(fitted, th)
            oversize = None
            # a small share of a union's mesh is the slice nearest an element that may stand for what
            # the visual does not draw (a cable, a mount): its standoff from that slice means nothing
            share = fitted.part_points / max(len(visual.points), 1)
            judged = not multi or share >= th.oversize_min_part_share
            if fitted.element.primitive is not None and judged and not cap and fitted.covers(own):
                others = [e for e in own_elements if e is not fitted.element] + resting_elements(ctx, link)
                oversize = standing_off(fitted, others, own.protrusion_tolerance_m, own)
                if oversize is None and not multi:
                    oversize = wrong_kind(fitted, own)
            found = classify(
                link, shape, fitted, own, multi, metrics, centre, at_rest, contact, plate, oversize, extent, tyre
            )
            if found is not None:
                result.diagnostics.append(found)
    return entry


def run(ctx: CheckContext) -> FamilyResult:
    result = FamilyResult()
    th = ctx.thresholds.fit
    # thousands of tiny (n, 3) products: BLAS threads only add synchronisation
    with threadpool_limits(limits=1, user_api="blas"):
        reach = Reach(rigid_groups(ctx.robot))
        # the frames a loader adds to model its format (no geometry of their own) are no link of the file
        links = [link for link in ctx.robot.links if not link.synthetic]
        result.sections["links"] = [check_link(ctx, link, th, result, reach) for link in links]
    return result
