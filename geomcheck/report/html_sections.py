"""View models of the report's figure sections: links (views and fit), sweeps, the
collision matrix and inertia. Each reads its section in the documented shape
(docs/report-schema.md) and tolerates missing fields."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

from geomcheck.diagnostics import Severity
from geomcheck.report.html_common import (
    Anchors,
    count_label,
    degrees,
    mm,
    mm_value,
    percent,
    plural,
    sig,
    subjects_of,
    worst,
)
from geomcheck.report.model import Report
from geomcheck.report.section_inertia import InertiaEntry, inertia_section
from geomcheck.report.section_links import CollisionElement, ElementFit, LinkFit, links_section
from geomcheck.report.section_matrix import matrix_section
from geomcheck.report.section_sweeps import SweepPair, sweeps_section
from geomcheck.report.section_views import LinkViews, views_section
from geomcheck.report.svg_inertia import moment_bar, moment_ratio
from geomcheck.report.svg_matrix import CLASSES, class_counts, matrix_grid
from geomcheck.report.svg_polar import sweep_chart
from geomcheck.report.svg_views import link_figure

MAX_CHARTS_PER_JOINT = 8  # polar charts per swept joint; further pairs are listed in the table
GAP_SIDES = ("x-", "x+", "y-", "y+", "z-", "z+", "radial")


def geometry_text(collision: CollisionElement) -> str:
    """``box 0.650 × 0.650 × 0.040 m``, ``cylinder r 0.079 m, length 0.034 m``..."""
    kind = collision.type
    g = collision.geometry or {}
    try:
        if kind == "box":
            return "box " + " × ".join(f"{float(v):.3f}" for v in g["size"]) + " m"
        if kind == "cylinder":
            return f"cylinder r {float(g['radius']):.3f} m, length {float(g['length']):.3f} m"
        if kind == "sphere":
            return f"sphere r {float(g['radius']):.3f} m"
        if kind == "mesh":
            return f"mesh {g.get('filename', '')}"
    except (KeyError, TypeError, ValueError):
        pass
    return kind


def fit_extras(fit: ElementFit) -> list[str]:
    """Further facts of a fit worth a line: a better cylinder axis, the offset that centres
    the element, how a collision mesh compares with the visual one."""
    out = []
    alt = fit.axis_alternative
    if alt:
        rpy = " ".join(f"{float(v):.4g}" for v in alt.rpy)
        out.append(
            f"along the {alt.axis_name} axis (rpy {rpy}) the cylinder would cover "
            f"{percent(alt.coverage)}, protruding {mm_value(alt.protrusion_max_mm)}"
        )
    offset = fit.offset_mm
    if offset and any(abs(float(v)) >= 1.0 for v in offset):
        shift = ", ".join(f"{float(v):+.1f}" for v in offset)
        moved = "covers the mesh" if fit.fits_when_moved else "still does not cover the mesh"
        out.append(f"moved by ({shift}) mm to centre it on its part, it {moved}")
    mesh = fit.comparison
    if mesh is not None and mesh.reverse_coverage is not None:
        out.append(
            f"{percent(mesh.reverse_coverage)} of this collision mesh lies within the visual mesh's hull, "
            f"reaching out of it by up to {mm_value(mesh.overshoot_max_mm)}; the two surfaces are up to "
            f"{mm_value(mesh.surface_distance_max_mm)} apart"
        )
    return out


def _slack(slack: float | None) -> str:
    return "–" if slack is None else f"{float(slack):.2f}×"


def collision_model(collision: CollisionElement, flagged: Iterable[str] = ()) -> dict[str, Any]:
    """One collision element's fit; ``flagged`` names the elements (``collision[0]``) that
    have a fit finding, whose coverage is then shown as a problem."""
    fit = collision.fit
    model: dict[str, Any] = {"label": collision.label, "geometry": geometry_text(collision), "fit": None}
    if not fit:
        return model
    gaps = fit.gaps_mm or {}
    suggested = fit.suggested
    model["fit"] = {
        "coverage": percent(fit.coverage),
        "flagged": collision.label in set(flagged),
        "protrusion_max": mm_value(fit.protrusion_max_mm),
        "protrusion_p95": mm_value(fit.protrusion_p95_mm),
        "slack": _slack(fit.slack),
        "gaps": [
            {"side": side, "value": f"{float(gap):+.1f} mm", "short": float(gap) < 0}
            for side in GAP_SIDES
            if (gap := gaps.get(side)) is not None
        ],
        "extras": fit_extras(fit),
        "suggested": None
        if not suggested
        else {
            "type": suggested.type,
            "urdf": suggested.urdf,
            "coverage": percent(suggested.coverage),
            "slack": _slack(suggested.slack),
        },
    }
    return model


def listed_links(report: Report) -> list[str]:
    """Links that get an entry in the links section, in document order: those with a
    picture, with collision elements, or with findings."""
    views = [v.link for v in views_section(report.sections)]
    fitted = links_section(report.sections)
    fits = [e.link for e in fitted]
    with_collisions = {e.link for e in fitted if e.collisions}
    with_findings = {name for d in report.diagnostics for name in subjects_of(d)}
    return [
        name
        for name in dict.fromkeys([*fits, *views])
        if name in views or name in with_collisions or name in with_findings
    ]


def link_hint(collisions: int, fitted: bool, coverages: Sequence[float]) -> str:
    """The line beside a link's name: its collision elements and their worst coverage."""
    if collisions:
        hint = plural(collisions, "collision element")
        return f"{hint}, coverage {percent(min(coverages))}" if coverages else hint
    return "no collision geometry" if fitted else ""


def links_model(report: Report, findings: Sequence[dict[str, Any]], anchor: Anchors) -> list[dict[str, Any]]:
    """One entry per link with a picture or fit data: links with findings first (worst
    first, then document order), the rest after them, collapsed."""
    views = {v.link: v for v in views_section(report.sections)}
    fits = {e.link: e for e in links_section(report.sections)}
    by_link: dict[str, list[dict[str, Any]]] = {}
    for f in findings:
        for link in f["links"]:
            by_link.setdefault(link["name"], []).append(f)
    ranked: list[tuple[tuple[int, int], dict[str, Any]]] = []
    for position, name in enumerate(anchor.pictured):
        own = by_link.get(name, [])
        severity = worst(f["severity"] for f in own)
        rank = (-Severity(severity).rank if severity else 0, position)
        ranked.append((rank, link_model(name, own, severity, fits.get(name), views.get(name), anchor)))
    return [entry for _, entry in sorted(ranked, key=lambda r: r[0])]


def link_model(
    name: str,
    own: list[dict[str, Any]],
    severity: str | None,
    fit: LinkFit | None,
    view: LinkViews | None,
    anchor: Anchors,
) -> dict[str, Any]:
    """The entry of link ``name``: its findings ``own`` (the worst ``severity``), its fit and picture."""
    elements = fit.collisions if fit else ()
    flagged = {f["about"] for f in own if f["code"].startswith("GC3")}
    collisions = [collision_model(c, flagged) for c in elements]
    counts = {s.value: sum(1 for f in own if f["severity"] == s.value) for s in Severity}
    fitted = [c.fit.coverage for c in elements if c.fit and c.fit.coverage is not None]
    return {
        "name": name,
        "id": anchor("link", name),
        "open": bool(own),
        "severity": severity,
        "counts": [
            {"severity": s.value, "label": f"{counts[s.value]} {count_label(s, counts[s.value])}"}
            for s in Severity
            if counts[s.value]
        ],
        "figure": link_figure(view) if view else None,
        "scale": view.scale_m if view else None,
        "collisions": collisions,
        "hint": link_hint(len(collisions), fit is not None, [float(c) for c in fitted]),
        "findings": [{"id": f["id"], "code": f["code"], "severity": f["severity"]} for f in own],
        "notes": [*(view.unavailable if view else ()), *(fit.skipped if fit else ())],
    }


def contact_ranges(pair: SweepPair) -> str:
    """``40°–75°, 300°–310°``, ``all angles`` or ``none``."""
    ranges = pair.colliding_ranges
    if any(hi - lo >= 2 * math.pi - 1e-3 for lo, hi in ranges):
        return "all angles"
    return ", ".join(f"{degrees(lo)}–{degrees(hi)}" for lo, hi in ranges) or "none"


def _pair_order(pair: SweepPair) -> tuple[bool, float, tuple[str, ...]]:
    """Non-adjacent pairs first, then closest first."""
    return (pair.adjacent, math.inf if pair.min_clearance is None else pair.min_clearance, pair.links)


def sweep_pair_row(pair: SweepPair, joint: str, charted: bool, anchor: Anchors) -> dict[str, Any]:
    """One row of a joint's pair table, with its chart when ``charted``."""
    minimum = pair.min_clearance
    touches = minimum is not None and minimum <= 0.0
    return {
        "links": [anchor.link_ref(x) for x in pair.links],
        "min_clearance": mm(minimum),
        "hit": touches and not pair.adjacent,
        "adjacent": pair.adjacent,
        "min_angle": degrees(pair.min_angle) if pair.min_angle is not None else "–",
        "ranges": contact_ranges(pair),
        "contact": bool(pair.colliding_ranges),
        "pair": pair.name,
        "max_depth": mm(pair.max_depth) if pair.max_depth else "–",
        "chart": sweep_chart(pair, joint) if charted and pair.angles else None,
    }


def sweeps_model(report: Report, anchor: Anchors) -> list[dict[str, Any]]:
    """Per swept joint: the pairs, non-adjacent first and closest first, charted up to a limit."""
    out = []
    for entry in sweeps_section(report.sections):
        pairs = sorted(entry.pairs, key=_pair_order)
        rows = [sweep_pair_row(pair, entry.joint, k < MAX_CHARTS_PER_JOINT, anchor) for k, pair in enumerate(pairs)]
        out.append(
            {
                "joint": entry.joint,
                "id": anchor("sweep", entry.joint),
                "moving_links": list(entry.moving_links),
                "proven": entry.proven,
                "grid_points": entry.grid_points,
                "far_pairs": entry.far_pairs,
                "pairs": rows,
                "charted": sum(1 for r in rows if r["chart"] is not None),
                "hit": any(r["hit"] for r in rows),
            }
        )
    return out


def matrix_model(report: Report, anchor: Anchors) -> dict[str, Any] | None:
    section = matrix_section(report.sections)
    if section is None:
        return None
    links = section.links
    counts = class_counts(section)
    legend = [{"class": c, "label": label, "count": counts[c]} for c, label in CLASSES.items()]
    missing = len(links) * (len(links) - 1) // 2 - len(section.pairs)
    if section.semantics == "pinocchio" and missing > 0:  # links on one rigid body make no pair
        legend.append({"class": "none", "label": "one rigid body: no pair", "count": missing})
    return {
        "grid": matrix_grid(section, {name: href for name in links if (href := anchor.link_href(name))}),
        "legend": legend,
        "links": len(links),
        "pairs": len(section.pairs),
        "samples": section.samples,
        "seed": section.seed,
        "backend": section.backend,
        "pinocchio": section.semantics == "pinocchio",
        "always_fraction": percent(section.always_fraction),
    }


def inertia_axes(entry: InertiaEntry) -> list[dict[str, Any]]:
    """Per principal axis: moment, geometry bound, bar, radius of gyration and reach."""
    bounds = entry.geometry_bound or ()
    gyration = entry.radius_of_gyration or ()
    reach = entry.reach or ()
    out = []
    for i, moment in enumerate(entry.principal_moments or ()):
        bound = bounds[i] if i < len(bounds) else None
        k = gyration[i] if i < len(gyration) else None
        r = reach[i] if i < len(reach) else None
        over = moment is not None and bound is not None and moment_ratio(float(moment), float(bound)) > 1.0
        out.append(
            {
                "moment": sig(moment),
                "bound": sig(bound),
                "bar": moment_bar(moment, bound, f"{entry.link}: principal moment {i + 1} against its bound")
                if moment is not None and bound is not None
                else None,
                "gyration": f"{mm(k, 0)} / {mm(r, 0)}" if k is not None and r is not None else mm(k, 0),
                "over": over,
            }
        )
    return out


def inertia_flags(entry: InertiaEntry) -> list[str]:
    """What is wrong with a link's inertia, in words; empty when nothing is known wrong."""
    out = []
    if entry.positive_definite is False:
        out.append("not positive definite")
    if entry.triangle_ok is False:
        out.append("breaks the triangle inequality")
    if entry.within_geometry is False:
        out.append("needs mass outside the geometry")
    if entry.com_inside_bounds is False:
        out.append("centre of mass outside the geometry")
    if entry.copied_from:
        out.append(f"same tensor as {entry.copied_from}")
    return out


def inertia_model(report: Report, anchor: Anchors) -> list[dict[str, Any]]:
    """Rows of the inertia table: flagged links first, then document order."""
    ranked: list[tuple[tuple[int, int], dict[str, Any]]] = []
    for position, entry in enumerate(inertia_section(report.sections)):
        flags = inertia_flags(entry)
        row = {
            "link": entry.link,
            "href": anchor.link_href(entry.link),
            "mass": sig(entry.mass, 4),
            "axes": inertia_axes(entry),
            "flags": flags,
        }
        ranked.append(((0 if flags else 1, position), row))
    return [row for _, row in sorted(ranked, key=lambda r: r[0])]
