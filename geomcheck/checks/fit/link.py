"""Fitting one link: its collision elements against its visual geometry, its findings and report entry."""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.fit.at_rest import stored_resting_coverage_of, tyre_coverage
from geomcheck.checks.fit.lending import _lent, caps_a_capsule, lent_to
from geomcheck.checks.fit.oversize import standing_off, wrong_kind
from geomcheck.checks.fit.shapes import (
    alike_fit,
    borrowed_elements,
    collision_entry,
    link_elements,
    link_visual,
    resting_elements,
    visual_mesh_entries,
)
from geomcheck.checks.fit.tolerance import element_tolerance, part_tolerance
from geomcheck.checks.fit.touch import Reach, _covering_link, _without_collision, distal
from geomcheck.checks.fit.verdicts import classify, contact_plate, stands_beside
from geomcheck.checks.wording import length, listed
from geomcheck.diagnostics import Diagnostic, Severity, SkippedCheck
from geomcheck.geometry.elements import CollisionElement, VisualCloud, mm, ratio
from geomcheck.geometry.fit import ElementFit, LinkFit, fit_link
from geomcheck.geometry.reach import rigid_groups
from geomcheck.model import Link, Mesh, Shape, Sphere, kind_name
from geomcheck.rules.fit import COLLISION_DOES_NOT_COVER, COLLISION_OFFSET, VISUAL_WITHOUT_COLLISION
from geomcheck.thresholds import FitThresholds


def _skip(entry: dict[str, Any], result: FamilyResult, link: Link, reason: str) -> dict[str, Any]:
    entry["skipped"].append(f"fit: {reason}")
    result.skipped.append(SkippedCheck("fit", link.name, reason))
    return entry


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
    union = fit_union(ctx, link, visual, elements, th, reach, extent, entry)
    uncovered: list[Diagnostic] = []
    found_here: list[Diagnostic] = []
    for shape, fitted, col in zip(link.collisions, union.fit.elements, entry["collisions"], strict=True):
        found = judge_element(union, shape, fitted, col, result)
        if found is not None and found.code == COLLISION_DOES_NOT_COVER.code:
            # an element repeating one of the link's visual elements holds that element exactly: the
            # parts of the mesh nearest to it belong to the others (a caster's sphere on a body)
            if not repeats_a_visual(link, shape):
                uncovered.append(found)
        elif found is not None:
            found_here.append(found)
    judged = [*found_here, *one_gap(uncovered, union.at_rest)]
    if all(e.size <= th.marker_element_m for e in elements):
        judged = enclosed(ctx, link, visual, th, reach, judged)
    result.diagnostics.extend(judged)
    return entry


def enclosed(
    ctx: CheckContext, link: Link, visual: VisualCloud, th: FitThresholds, reach: Reach, found: list[Diagnostic]
) -> list[Diagnostic]:
    """``found``, the findings of a link whose collision elements are placeholders (none larger
    than ``marker_element_m``), with those that leave the link's mesh uncovered (GC301, GC303)
    lowered to info when the mesh lies within another link's collision geometry, rigidly or at
    every position of the joint between them (Baxter's head and screen, each with a 2 mm sphere,
    held by two spheres on links fixed to the base over the head's whole pan): contacts reach the
    part through that geometry. An element of a real size is judged whatever holds the mesh: away
    from its part it makes contacts where the part is not (Robotiq's finger bases, whose mesh the
    palm's collision holds, had their collision meshes 58 mm off; the maintainers moved them)."""
    rules = {COLLISION_DOES_NOT_COVER.code: COLLISION_DOES_NOT_COVER, COLLISION_OFFSET.code: COLLISION_OFFSET}

    def uncovering(d: Diagnostic) -> bool:
        return d.code in rules and d.severity is not Severity.INFO and not d.data.get("covers_neighbour")

    if not any(uncovering(d) for d in found):
        return found
    covering = _covering_link(ctx, link, visual, reach.groups, th)
    if covering is None or covering[1] != "collision geometry":
        return found
    cover, _, joint = covering
    variant = "held" if joint is None else "held_moving"
    return [
        replace(
            d,
            message=d.message + rules[d.code].message(variant, cover=cover, joint=joint),
            severity=Severity.INFO,
            data={**d.data, "held_by": cover},
        )
        if uncovering(d)
        else d
        for d in found
    ]


@dataclass(frozen=True)
class Union:
    """One link's fitted collision elements and what each of them is judged with."""

    ctx: CheckContext
    link: Link
    visual: VisualCloud
    fit: LinkFit
    th: FitThresholds
    reach: Reach
    extent: float  # the visual geometry's largest extent [m]
    at_rest: float  # the union's coverage, with the neighbours' elements at rest [1]
    tyre: float | None  # a wheel's coverage by its tyre, when the union's falls short [1]
    multi: bool  # more than one element of the link's own
    note: str | None  # what each element's metrics say of the union

    @property
    def own_elements(self) -> list[CollisionElement]:
        return [f.element for f in self.fit.elements]


def fit_union(
    ctx: CheckContext,
    link: Link,
    visual: VisualCloud,
    elements: list[CollisionElement],
    th: FitThresholds,
    reach: Reach,
    extent: float,
    entry: dict[str, Any],
) -> Union:
    """Fit ``link``'s collision elements (and those it borrows) to its visual geometry, shared as
    ``ctx.analyses.fits``; the union's figures in ``entry``."""
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
    note = "; ".join(notes) or None
    return Union(ctx, link, visual, link_fit, th, reach, extent, at_rest, tyre, len(elements) > 1, note)


def judge_element(
    union: Union, shape: Shape, fitted: ElementFit, col: dict[str, Any], result: FamilyResult
) -> Diagnostic | None:
    """One fitted element's verdict (its fit written in ``col``); an element lying on a neighbour's
    mesh is reported to ``result`` at once, and a capsule's cap past the mesh is judged with its capsule."""
    th = union.th
    col["fit"] = fitted.to_dict()
    cap = caps_a_capsule(fitted.element, union.own_elements, th.capsule_cap_tolerance_m)
    col["fit"]["capsule_cap"] = cap
    if cap and fitted.disjoint(th):
        col["fit"]["covers_neighbour"] = None
        return None  # the capsule's rounded end past the mesh: judged with the capsule, by its cylinder
    lends = lent_to(union.ctx, union.link, fitted.element, th) if fitted.disjoint(th) else None
    col["fit"]["covers_neighbour"] = lends
    if lends is not None:
        result.diagnostics.append(_lent(union.link, shape, fitted, lends, union.fit, th))
        return None
    return verdict(union, shape, fitted, {**col["fit"], "part_note": union.note}, cap)


def verdict(union: Union, shape: Shape, fitted: ElementFit, metrics: dict[str, Any], cap: bool) -> Diagnostic | None:
    """GC301-GC304, GC306 for one element of the union that lends itself to no neighbour."""
    ctx, link, th = union.ctx, union.link, union.th
    centre = union.visual.bounds().mean(axis=0)
    own = replace(th, protrusion_tolerance_m=element_tolerance(fitted, th))
    end = distal(ctx.robot, union.reach.groups, link.name)
    contact = end and isinstance(shape.geometry, Sphere)
    plate = end and contact_plate(fitted, th)
    oversize = None
    # a small share of a union's mesh is the slice nearest an element that may stand for what
    # the visual does not draw (a cable, a mount): its standoff from that slice means nothing
    share = fitted.part_points / max(len(union.visual.points), 1)
    # a lone element too answers for a sliver when a neighbour's geometry (borrowed) holds the rest
    judged = share >= th.oversize_min_part_share
    if fitted.element.primitive is not None and judged and not cap and fitted.covers(own):
        others = [e for e in union.own_elements if e is not fitted.element] + resting_elements(ctx, link)
        oversize = standing_off(fitted, others, own.protrusion_tolerance_m, own)
        if oversize is None and not union.multi:
            oversize = wrong_kind(fitted, own)
    hull = union.visual.hull
    beside = union.multi and stands_beside(fitted, th, hull.volume if hull is not None else 0.0)
    if not judged:  # its slack (volume against its part's hull) means nothing when its part is a sliver
        own = replace(own, max_slack=np.inf)
    judge = partial(
        classify, link, shape, fitted, own, union.multi, metrics, centre, union.at_rest, contact, plate, oversize,
        union.extent, union.tyre, beside=beside,
    )  # fmt: skip
    found = judge()
    neighbour = (
        lent_to(ctx, link, fitted.element, th) if found is not None and found.code == COLLISION_OFFSET.code else None
    )
    if neighbour is not None:
        # reaching across a joint onto the neighbour's mesh, where it stays: deliberate, not misplaced
        found = judge(straddles=True)
        if found is not None:
            kind = kind_name(shape.geometry)
            keep = (
                f"Enlarge the {kind} over the part of link {link.name}'s mesh it leaves out, keeping the part that "
                f"covers neighbour {neighbour}'s mesh across the joint (it stays there at every joint position): a "
                "fitted replacement would leave that uncovered."
            )
            found = replace(found, help=keep)
    return found


def repeats_a_visual(link: Link, shape: Shape) -> bool:
    """Whether collision element ``shape`` stands for one of several visual elements of ``link``: a
    primitive of the same kind at the same origin (of its own size or not), or the same mesh there."""
    return len(link.visuals) > 1 and any(
        type(v.geometry) is type(shape.geometry)
        and v.origin == shape.origin
        and (not isinstance(shape.geometry, Mesh) or v.geometry == shape.geometry)
        for v in link.visuals
    )


def one_gap(uncovered: list[Diagnostic], union_coverage: float) -> list[Diagnostic]:
    """The GC301 findings of one link's elements as one: a union's elements are judged together,
    and a gap is the union's, not each element's (a misplaced element leaves its part of the mesh
    nearest to a correctly placed neighbour, which would be reported for it too). The element that
    answers for most of the mesh stands for the link, naming the others."""
    if len(uncovered) < 2:
        return uncovered
    worst = max(uncovered, key=lambda d: (d.data.get("part_points") or 0, d.data.get("protrusion_max_mm") or 0.0))
    others = sorted(d.about for d in uncovered if d is not worst)
    message = (
        f"the link's collision elements together cover {union_coverage:.0%} of its surface, and {worst.message} "
        f"({', '.join(others)} leave parts of the mesh out too)"
    )
    return [replace(worst, message=message, data={**worst.data, "also_elements": others})]


def run(ctx: CheckContext) -> FamilyResult:
    result = FamilyResult()
    th = ctx.thresholds.fit
    # thousands of tiny (n, 3) products: BLAS threads only add synchronisation
    with threadpool_limits(limits=1, user_api="blas"):
        reach = Reach(rigid_groups(ctx.robot))
        # the frames a loader adds to model its format (no geometry of their own) are no link of the file
        links = [link for link in ctx.robot.links if not link.synthetic]
        result.sections["links"] = [check_link(ctx, link, th, result, reach) for link in links]
    if not any(link.collisions for link in links):
        result.diagnostics = without_any_collision(ctx, links, result.diagnostics)
    return result


def without_any_collision(ctx: CheckContext, links: list[Link], found: list[Diagnostic]) -> list[Diagnostic]:
    """``found`` for a description without a single collision element: its links' GC305 findings,
    one cause, become info and one warning on the root link says it (an Onshape export of a hand:
    79 findings, one per part, where the maintainer adds collision geometry once, per rigid body)."""
    rule = VISUAL_WITHOUT_COLLISION
    bare = [d for d in found if d.code == rule.code and d.severity is not Severity.INFO]
    roots = [link for link in links if link.name not in ctx.robot.parent_joint]
    if len(bare) < 2 or not roots:
        return found
    root = roots[0]
    drawn = [d for d in found if d.code == rule.code]  # those inside another part's visual hull too
    names = listed([d.link or "" for d in drawn], 3)
    summary = rule.diagnose(
        rule.message("none_at_all", links=len(links), count=len(drawn), names=names),
        help=(
            "Add <collision> elements: a box, cylinder or capsule per rigid body, or a mesh (the report's links "
            "section suggests a box enclosing each link's visual)."
        ),
        link=root.name,
        about="every link",
        location=root.location,
        data={"suggested": None, "covered_by": None, "reached_by": None, "links_without": [d.link for d in drawn]},
    )
    note = rule.message("in_none", count=len(drawn), root=root.name)
    ids = {id(d) for d in bare}
    lowered = [d.grouped_under(summary, note) if id(d) in ids else d for d in found]
    return [summary, *lowered]
