"""The fit family's verdict on one fitted element: GC301-GC304 and GC306, most specific rule first."""

from __future__ import annotations

from dataclasses import replace
from pathlib import PurePosixPath
from typing import Any

import numpy as np

from geomcheck.checks.fit.oversize import Oversize
from geomcheck.checks.wording import AXIS_NAMES, direction, length, vector
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.geometry.elements import at_nanometre, mm
from geomcheck.geometry.fit import ElementFit
from geomcheck.geometry.frames import rotation_angle
from geomcheck.geometry.primitives import half_extents
from geomcheck.geometry.shapes import primitive_mesh
from geomcheck.geometry.suggest import fmt
from geomcheck.model import Box, Cylinder, Link, Mesh, Shape, kind_name
from geomcheck.rules import Rule
from geomcheck.rules import fit as rules
from geomcheck.thresholds import FitThresholds


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
    kind = kind_name(shape.geometry)
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
    kind = kind_name(shape.geometry)
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
        fitted = f.suggested.type  # a capsule's or an ellipsoid's fit is the cylinder or box it fits
        fix += f"; a fitted {fitted}{_grown_note(f, fitted, th.protrusion_tolerance_m)}:\n{f.suggested.urdf()}"
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
    kind = kind_name(shape.geometry)
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
    if oversize is None and not _slack_exceeds(f, th):
        return None
    rule = rules.COLLISION_OVERSIZED
    if oversize is not None and oversize.better is not None:
        message, fix, data = _wrong_kind(shape, oversize, data)
    elif oversize is not None:
        message, fix, data = _standing_off(shape, f, oversize, data)
    else:
        s = f.suggested
        assert s is not None
        kind = kind_name(shape.geometry)
        message = rule.message(label=shape.label, kind=kind, slack=f.slack, fitted_slack=f.fitted_slack)
        fix = f"Use the fitted {s.type}:\n{s.urdf()}"
    severity = None
    if contact:
        message += rule.message("contact")
        severity = Severity.INFO
    return _element_diagnostic(rule, link, shape, message, data, fix, severity)


def _slack_exceeds(f: ElementFit, th: FitThresholds) -> bool:
    """Whether the element's slack (its volume against its part's hull) is too much, and its fitted
    shape's would be much less."""
    fitted = f.fitted_slack
    if f.suggested is None or f.slack is None or fitted is None:
        return False
    return f.slack > th.max_slack and f.slack >= th.min_slack_gain * fitted


def _wrong_kind(shape: Shape, oversize: Oversize, data: dict[str, Any]) -> tuple[str, str, dict[str, Any]]:
    """GC302's message, fix and data for an element of the wrong kind of shape."""
    better = oversize.better
    assert better is not None
    message = rules.COLLISION_OVERSIZED.message(
        "kind",
        label=shape.label,
        kind=kind_name(shape.geometry),
        kind_ratio=oversize.kind_ratio,
        better=better.type,
        coverage=better.coverage,
    )
    extra: dict[str, Any] = {}
    if oversize.own_kind_ratio is not None:
        message += rules.COLLISION_OVERSIZED.message(
            "own_kind", kind=kind_name(shape.geometry), own_kind_ratio=oversize.own_kind_ratio
        )
        extra["own_kind_ratio"] = round(float(oversize.own_kind_ratio), 3)
    fix = f"Use the fitted {better.type}:\n{better.urdf()}"
    kind_ratio = round(float(oversize.kind_ratio or 0.0), 3)
    return message, fix, data | {"kind_ratio": kind_ratio, **extra, "better_kind": better.to_dict()}


def _standing_off(
    shape: Shape, f: ElementFit, oversize: Oversize, data: dict[str, Any]
) -> tuple[str, str, dict[str, Any]]:
    """GC302's message, fix and data for an element whose side stands off its part."""
    s = f.suggested
    assert oversize.side is not None and s is not None
    kind = kind_name(shape.geometry)
    message = rules.COLLISION_OVERSIZED.message(
        "standoff",
        label=shape.label,
        kind=kind,
        side=SIDE_NAMES[oversize.side],
        gap=length(oversize.gap),
        span=length(oversize.span),
        allowed=length(oversize.allowed),
        volume_ratio=oversize.volume_ratio,
    )
    fix = f"Use the fitted {s.type}:\n{s.urdf()}"
    return (
        message,
        fix,
        data
        | {
            "standoff_side": oversize.side,
            "standoff_mm": mm(oversize.gap),
            "standoff_allowed_mm": mm(oversize.allowed),
            "volume_ratio": round(float(oversize.volume_ratio or 0.0), 3),
        },
    )


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
    straddles: bool = False,
    beside: bool = False,
) -> Diagnostic | None:
    """The one finding (if any) about a fitted element, most specific rule first; ``metrics``
    is ``f.to_dict()``, carried in the finding's data; ``visual_centre`` (3,) the centre of
    the link's visual bounds [m]; ``union_coverage`` the share of the link's surface its
    collision elements cover together (the element's own coverage when not given);
    ``contact`` whether the element is a sphere at the distal end of a chain (a foot);
    ``plate`` whether it is a contact plate there (see :func:`contact_plate`); ``oversize`` how
    far it reaches past its part when it covers it (GC302); ``straddles`` whether it reaches across
    a joint onto the neighbour's mesh where it stays at every joint position (a cylinder coaxial
    with a roll joint spanning both links): then it is not misplaced, however far its centre is
    from its own link's mesh; ``beside`` whether it is a small element of a union against the
    mesh (:func:`stands_beside`): away from it, it stands for what the visual does not draw."""
    data: dict[str, Any] = {
        "element": f.element.type,
        "multi": multi,
        "tolerance": th.protrusion_tolerance_m,
        **metrics,
    }
    if f.disjoint(th):
        found = _offset(link, shape, f, visual_centre, data, disjoint=True)
        return _standing_beside(found) if beside else found
    if f.part_points == 0 or f.coverage is None or f.protrusion_max is None:
        return None
    covers = f.covers(th)
    union = f.coverage if union_coverage is None else union_coverage
    misplaced = not straddles and _misplaced(f, th, covers, union, multi)
    if f.element.primitive is None:
        if misplaced:
            return _offset(link, shape, f, visual_centre, data, disjoint=False)
        return _mesh_mismatch(link, shape, f, th, data, union, visual_size)
    if covers:
        # a union's elements overlap by design (capsules): its inner faces are not judged, and slack
        # (volume against the part's hull) only for lone elements
        if multi and oversize is None:
            return None
        return _oversized(link, shape, f, replace(th, max_slack=np.inf) if multi else th, data, contact, oversize)
    alt = f.axis_alternative
    if alt is not None and alt.coverage >= f.coverage + th.axis_coverage_gain and alt.protrusion_max < f.protrusion_max:
        return _axis(link, shape, f, data)
    if misplaced:
        return _offset(link, shape, f, visual_centre, data, disjoint=False)
    return _not_covered(link, shape, f, th, data, union, plate, tyre)


def _standing_beside(found: Diagnostic) -> Diagnostic:
    """GC303 for an element away from the mesh that stands beside it (:func:`stands_beside`): info."""
    return replace(
        found,
        message=found.message + rules.COLLISION_OFFSET.message("beside"),
        severity=Severity.INFO,
        help="Nothing to change if the element stands for a part the visual geometry does not draw; "
        "otherwise move it onto the part of the link it should cover.",
    )


def stands_beside(f: ElementFit, th: FitThresholds, visual_volume: float) -> bool:
    """Whether an element of a union away from the mesh sits against it: its surface no farther
    from the mesh than its own largest half-extent, and its volume at most
    ``beside_volume_share`` of the visual geometry's hull. Such an element stands for something the
    visual does not draw (a tooth on a jaw bone, a cable, a bumper pad); an element moved off its
    part by a wrong origin lies farther than its own size or is as large as the part."""
    primitive = f.element.primitive
    if primitive is None or visual_volume <= 0.0:
        return False
    reach = float(np.max(half_extents(primitive)))
    return f.nearest <= reach and f.element.volume <= th.beside_volume_share * visual_volume


def _misplaced(f: ElementFit, th: FitThresholds, covers: bool, union: float, multi: bool) -> bool:
    """Whether a lone element that leaves its part uncovered would cover it moved: an element that
    still covers most of the link is not somewhere else, a small part sticks out."""
    shift = float(np.linalg.norm(f.shift)) if f.shift is not None else 0.0
    return (
        not covers
        and union < th.min_coverage
        and not multi
        and f.fits_when_moved
        and shift > th.protrusion_tolerance_m
        and shift >= th.offset_min_fraction * f.element.size
    )
