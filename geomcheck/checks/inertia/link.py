"""One link's GC5xx checks, its ``inertia`` section entry, and the family's ``run``."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.inertia.bodies import Body
from geomcheck.checks.inertia.bounds import geometry_diagnostic, implied_inertia, part_centroid
from geomcheck.checks.inertia.com import com_diagnostic, misplaced_com, template_origins
from geomcheck.checks.inertia.counterparts import check_counterparts
from geomcheck.checks.inertia.mass import (
    density_diagnostic,
    kinematics_only_diagnostic,
    mass_diagnostics,
    missing_diagnostic,
    missing_once,
)
from geomcheck.checks.inertia.points import HullMemo, LinkPoints
from geomcheck.checks.inertia.shared import grouped, shared_tensors
from geomcheck.checks.inertia.tensor import copied_diagnostic, find_copies, tensor_diagnostics
from geomcheck.checks.inertia.values import (
    distinct_axes,
    metres_list,
    moving_joint,
    rounded,
    rounded_list,
    tensor_values,
    unique_links,
    vector_text,
)
from geomcheck.checks.inertia.weigher import Weigher
from geomcheck.diagnostics import Diagnostic, SkippedCheck
from geomcheck.geometry.hull_cache import stored_distance_outside
from geomcheck.geometry.inertia import (
    MassProperties,
    geometry_bounds,
    mass_properties,
)
from geomcheck.model import Inertial, Joint, Link
from geomcheck.rules.inertia import (
    NOT_POSITIVE_DEFINITE,
)
from geomcheck.thresholds import InertiaThresholds

GEOMETRY_CHECK = "inertia-geometry"


@dataclass
class LinkFindings:
    """What the checks of one link produced."""

    entry: dict[str, Any]
    diagnostics: list[Diagnostic] = field(default_factory=list)
    skipped: list[SkippedCheck] = field(default_factory=list)


def empty_entry(link: Link, inertial: Inertial) -> dict[str, Any]:
    """Section entry with every field present, geometry-dependent ones unknown (``None``)."""
    return {
        "link": link.name,
        "mass": rounded(inertial.mass),
        "com": rounded_list(inertial.origin.xyz),
        "principal_moments": None,
        "principal_axes": None,
        "geometry_bound": None,
        "radius_of_gyration": None,
        "reach": None,
        "positive_definite": None,
        "triangle_ok": None,
        "within_geometry": None,
        "com_inside_bounds": None,
        "spread": None,
        "extent": None,
        "moments_xyz": None,
        "geometry_bound_xyz": None,
        "com_distance_outside": None,
        "bounds": None,
        "hull_volume": None,
        "density": None,
        "copied_from": None,
    }


def check_link(
    link: Link,
    joint: Joint | None,
    body: Body,
    points_of: Callable[[str], np.ndarray | str],
    th: InertiaThresholds,
    hulls: HullMemo,
) -> LinkFindings:
    """Every GC5xx check of one link with an ``<inertial>`` but GC501 and GC507."""
    inertial = link.inertial
    assert inertial is not None
    loc = inertial.location or link.location
    out = LinkFindings(empty_entry(link, inertial))
    out.diagnostics.extend(mass_diagnostics(link, joint, body, th, loc))
    if not all(math.isfinite(v) for v in (*tensor_values(inertial), *inertial.origin.xyz, *inertial.origin.rpy)):
        out.entry["positive_definite"] = False
        out.diagnostics.append(
            NOT_POSITIVE_DEFINITE.diagnose(
                NOT_POSITIVE_DEFINITE.message("not_finite", tensor=vector_text(tensor_values(inertial))),
                link=link.name,
                about="inertia",
                location=loc,
                data={"tensor": [str(v) for v in tensor_values(inertial)]},
            )
        )
        return out
    props = mass_properties(inertial)
    entry = out.entry
    entry["principal_moments"] = rounded_list(props.moments)
    entry["principal_axes"] = distinct_axes(props.moments, props.axes)
    entry["positive_definite"] = props.positive_definite
    if not (props.mass > 0.0 and math.isfinite(props.mass)):
        # A massless link's tensor says nothing; GC502 reports the mass where it matters.
        return out
    tensor_findings, triangle_ok = tensor_diagnostics(link, props, joint is not None, th, loc)
    out.diagnostics.extend(tensor_findings)
    entry["triangle_ok"] = triangle_ok
    entry["radius_of_gyration"] = [rounded(math.sqrt(m / props.mass)) if m >= 0 else None for m in props.moments]
    points = points_of(link.name)
    if isinstance(points, str):
        out.skipped.append(SkippedCheck(GEOMETRY_CHECK, link.name, points))
        return out
    check_geometry(link, props, points, triangle_ok, th, out, hulls)
    return out


def check_geometry(
    link: Link,
    props: MassProperties,
    points: np.ndarray,
    triangle_ok: bool,
    th: InertiaThresholds,
    out: LinkFindings,
    hulls: HullMemo,
) -> None:
    """GC505, GC506, GC508 and the geometry fields of the section entry.

    GC505 is only reported for a tensor that some body could have (GC503 and GC504 pass):
    one that breaks them is impossible whatever the geometry, and is reported as such.
    """
    loc = (link.inertial.location if link.inertial else None) or link.location
    hull = hulls.of(points)
    distance = stored_distance_outside(hull, props.com)
    entry = out.entry
    entry["com_inside_bounds"] = distance <= th.com_margin_m
    entry["com_distance_outside"] = rounded(distance)
    entry["bounds"] = [metres_list(hull.lower), metres_list(hull.upper)]
    entry["hull_volume"] = rounded(hull.volume)
    entry["density"] = rounded(props.mass / hull.volume) if hull.volume > 0.0 else None
    if distance > th.com_margin_m:
        out.diagnostics.append(com_diagnostic(link, props, hull, distance, loc))
    elif (misplaced := misplaced_com(link, props, points, th, loc)) is not None:
        out.diagnostics.append(misplaced)
    if hull.volume > 0.0 and props.mass / hull.volume > th.max_density_kg_m3:
        out.diagnostics.append(density_diagnostic(link, props.mass, hull.volume, th, loc))
    if not props.positive_semidefinite:
        return
    bounds = geometry_bounds(props, points)
    entry["geometry_bound"] = rounded_list(bounds.moment_bound[:3])
    entry["reach"] = rounded_list(bounds.axis_reach[:3])
    entry["spread"] = rounded_list(np.sqrt(np.clip(bounds.spread[:3], 0.0, None) / props.mass))
    entry["extent"] = rounded_list(bounds.plane_reach[:3])
    entry["moments_xyz"] = rounded_list(bounds.moments[3:])
    entry["geometry_bound_xyz"] = rounded_list(bounds.moment_bound[3:])
    finding = geometry_diagnostic(link, props, bounds, th, loc)
    entry["within_geometry"] = finding is None
    if finding is not None and triangle_ok:
        implied = implied_inertia(link, props, points)
        if implied is not None:
            data = {**finding.data, "implied_inertia": implied}
            help = implied_help(implied, props)
            off_part = any(d.code in COM_OFF_PART for d in out.diagnostics)
            if off_part and (centroid := part_centroid(points)) is not None:
                help += centroid_caveat(link, props, points, centroid)
            finding = replace(finding, data=data, help=help)
        out.diagnostics.append(finding)


def run(ctx: CheckContext) -> FamilyResult:
    robot = ctx.robot
    th = ctx.thresholds.inertia
    result = FamilyResult()
    copies = find_copies(robot, th)
    hulls = HullMemo()
    points_of = LinkPoints(robot, ctx.meshes, ctx.thresholds.analysis)
    weigher = Weigher(robot, th, points_of, hulls)
    entries = []
    kinematics_only = kinematics_only_diagnostic(robot)
    if kinematics_only is not None:
        result.diagnostics.append(kinematics_only)
    for link in unique_links(robot):
        joint = moving_joint(robot, link)
        body = weigher.bodies[link.name]
        if link.inertial is None:
            # pinocchio and Gazebo give a moving link the mass of the links fixed below it
            moving = joint is not None and not link.synthetic  # a frame between joints of one MJCF body
            if moving and joint is not None and kinematics_only is None and body.mass <= th.min_mass_kg:
                result.diagnostics.append(missing_diagnostic(link, joint, body))
            continue
        findings = check_link(link, joint, body, points_of, th, hulls)
        reference = copies.get(link.name)
        if reference is not None:
            findings.entry["copied_from"] = reference.name
            loc = link.inertial.location or link.location
            findings.diagnostics.append(copied_diagnostic(link, reference, loc))
        entries.append(findings.entry)
        result.diagnostics.extend(weigher.weigh(d) for d in findings.diagnostics)
        result.skipped.extend(findings.skipped)
    result.sections["inertia"] = entries
    result.diagnostics = missing_once(grouped(result.diagnostics, shared_tensors(robot, copies, th)))
    result.diagnostics = template_origins(result.diagnostics, th.com_template_links)
    result.diagnostics.extend(check_counterparts(robot, ctx.analyses.kinematics, points_of, th))
    return result


def implied_help(implied: dict[str, float | None], props: MassProperties) -> str:
    """GC505's help for a part whose geometry gives a tensor: that tensor, which the fix writes."""
    values = ", ".join(f"{key} {value:.4g}" for key, value in implied.items() if value)
    return (
        f"Recompute the tensor for this part from CAD; a uniform solid filling its geometry (the convex hull of "
        f"its visual and collision shapes) with its {props.mass:.6g} kg has {values} kg m^2 about the centre of "
        "mass the <inertial> states, in its axes: the offered fix writes it."
    )


# the link's own findings that its centre of mass is off its part: outside it, or left at the origin
COM_OFF_PART = ("GC506", "GC511")


def centroid_caveat(link: Link, props: MassProperties, points: np.ndarray, centroid: np.ndarray) -> str:
    """What GC505's help adds when GC506 or GC511 found the link's centre of mass off its part
    (before any lowering or grouping): the tensor above carries the offset's m d^2, and about the
    part's own centroid, where a corrected centre of mass goes, the solid's tensor is another
    (ADAM's wrist links: a template's centre of mass 77 mm off; moved, that tensor is ten times
    too large)."""
    at_part = implied_inertia(link, replace(props, com=centroid), points) or {}
    values = ", ".join(f"{key} {value:.4g}" for key, value in at_part.items() if value)
    where = ", ".join(f"{v:.4g}" for v in np.round(centroid, 6) + 0.0)  # to the micrometre: no 1e-18 of round-off
    offset = float(np.linalg.norm(np.asarray(props.com, dtype=float) - centroid))
    return (
        f" The centre of mass it states is off the part ({offset * 1000:.0f} mm from its centroid), "
        f"and that tensor carries the offset: with the centre of mass corrected to the centroid ({where}) m, write "
        f"{values} kg m^2 instead."
    )
