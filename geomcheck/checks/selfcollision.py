"""GC401-GC404: the continuous-joint sweep (when ``options.sweep``) and default-pose collisions.

The self-collision products shared with the matrix family are ``ctx.analyses`` products
(:mod:`geomcheck.checks.analyses`); :func:`kinematics`, :func:`collision_scene` (per backend),
:func:`adjacency`, :func:`not_pairs`, :func:`srdf` and :func:`default_configuration` read them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.drawn_pose import at_bound, drawn_verdict
from geomcheck.checks.wording import listed, millimetres
from geomcheck.collision import CollisionScene
from geomcheck.diagnostics import Diagnostic, Severity, SkippedCheck
from geomcheck.kinematics import Kinematics
from geomcheck.load.srdf import Srdf
from geomcheck.model import SourceLocation
from geomcheck.progress import Progress
from geomcheck.rules.selfcollision import DEFAULT_POSE_COLLISION, SWEEP_CLEARANCE, SWEEP_COLLISION, SWEEP_UNPROVEN
from geomcheck.selfcollision.default_pose import (
    PairContact,
    contacts_at,
    has_mesh,
    only_touching,
    pair_occupancy,
    separation_depth,
)
from geomcheck.selfcollision.sweep import JointSweep, PairSweep, SweepSettings, sweep_continuous_joints, wrap
from geomcheck.selfcollision.sweep_plan import sweep_groups


# ---------------------------------------------------------------------- shared objects
def kinematics(ctx: CheckContext) -> Kinematics:
    """The run's :class:`Kinematics` (built once)."""
    return ctx.analyses.kinematics


def collision_scene(ctx: CheckContext, backend: str | None = None) -> CollisionScene:
    """The run's :class:`CollisionScene` for ``backend`` (default: the one the options name), built once."""
    return ctx.analyses.collision_scene(backend)


def adjacency(ctx: CheckContext) -> set[tuple[str, str]]:
    """MoveIt's Adjacent pairs among the links with usable collision geometry (sorted tuples),
    less those that are no pair under the run's semantics."""
    return ctx.analyses.adjacency


def not_pairs(ctx: CheckContext) -> set[tuple[str, str]]:
    """Link pairs (sorted tuples) that the run's semantics does not check: under ``pinocchio``,
    links that only fixed joints join (:func:`geomcheck.collision.excluded_pairs`)."""
    return ctx.analyses.not_pairs


def srdf(ctx: CheckContext) -> Srdf | None:
    """The SRDF given with ``--srdf``, read once; ``None`` without one. Raises
    :class:`geomcheck.errors.InputError` when it cannot be read."""
    return ctx.analyses.srdf


def default_configuration(ctx: CheckContext) -> np.ndarray:
    """A copy of the run's default pose (n_joints,):
    :attr:`geomcheck.checks.analyses.Analyses.default_configuration`."""
    return ctx.analyses.default_configuration.copy()


# ---------------------------------------------------------------------- formatting
def _deg(radians: float) -> str:
    return f"{np.degrees(radians):.1f}°"


def _r(value: float, digits: int) -> float:
    return round(float(value), digits) + 0.0  # + 0.0 turns -0.0 into 0.0: stable bytes


def ranges_text(ranges: Sequence[tuple[float, float]]) -> str:
    """Colliding angle ranges in words: ``over the whole turn`` or ``from 30.0° to 50.0°, ...``;
    a range cut at +-180° is joined back (``from 170.0° to -170.0° (through 180°)``)."""
    if len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= 2 * np.pi - 1e-9:
        return "over the whole turn"
    items = list(ranges)
    joined = None
    if len(items) > 1 and items[0][0] <= -np.pi + 1e-9 and items[-1][1] >= np.pi - 1e-9:
        joined = (items[-1][0], items[0][1])
        items = items[1:-1]
    parts = [f"from {_deg(lo)} to {_deg(hi)}" for lo, hi in items]
    if joined is not None:
        parts.append(f"from {_deg(joined[0])} to {_deg(joined[1])} (through 180°)")
    return ", ".join(parts)


def _shape_location(ctx: CheckContext, scene: CollisionScene, link: str, index: int) -> SourceLocation | None:
    shapes = scene.scene_shapes(link)
    if 0 <= index < len(shapes) and shapes[index].shape.location is not None:
        return shapes[index].shape.location
    item = ctx.robot.link_map.get(link)
    return item.location if item is not None else None


# ---------------------------------------------------------------------- findings
def disable_line(links: tuple[str, str], reason: str) -> str:
    """The SRDF element MoveIt's Setup Assistant writes to disable the pair."""
    return f'<disable_collisions link1="{links[0]}" link2="{links[1]}" reason="{reason}"/>'


def contact_help(description_format: str, links: tuple[str, str], srdf_line: str, by_design: bool) -> str | None:
    """GC403's help in the terms of the description's own tools: a URDF's pairs are disabled in
    the SRDF (``None``: the rule's own help), an MJCF model's by a ``<contact><exclude>`` (MuJoCo
    reads no SRDF), an SDFormat model's by collide bitmasks that share no bit."""
    if description_format == "mjcf":
        exclude = f'<contact><exclude body1="{links[0]}" body2="{links[1]}"/></contact>'
        if by_design:
            return f"MuJoCo collides this pair unless the model excludes it: `{exclude}`."
        return (
            "Fix the collision geometry or the body's position; if the contact is intended (parts that "
            f"touch by design), exclude the pair in the model: `{exclude}`."
        )
    if description_format == "sdf":
        bitmask = "<surface><contact><collide_bitmask>"
        if by_design:
            return f"Gazebo collides this pair unless the two links' collisions get {bitmask} values sharing no bit."
        return (
            "Fix the collision geometry or the joint pose; if the contact is intended (parts that touch by "
            f"design), give the two links' collisions {bitmask} values sharing no bit."
        )
    return f"MoveIt's Setup Assistant disables this pair; add it to the SRDF: `{srdf_line}`." if by_design else None


def flush(ctx: CheckContext, a: str, b: str, q: np.ndarray) -> bool:
    """Whether links ``a`` and ``b``, in collision at ``q`` (n_joints,), only touch: a shift of
    ``contact_tolerance_m`` along a world axis parts them (:func:`only_touching`)."""
    frames = kinematics(ctx).link_transforms(np.asarray(q, dtype=float)[None], [a, b])[0]
    shift = ctx.thresholds.self_collision.contact_tolerance_m
    return only_touching(collision_scene(ctx), a, frames[0], b, frames[1], shift)


def default_pose_findings(ctx: CheckContext, contacts: Sequence[PairContact]) -> list[Diagnostic]:
    """GC403: an error for a pair that collides at the default pose and not in other poses of
    the joints between its links (the robot starts in collision, and the Setup Assistant's
    Default entry would hide the pair's collisions elsewhere); info, with the SRDF line, for a
    pair that only touches (parts meeting at a stop: closed gripper fingers) or collides in
    nearly every sampled pose (a designed overlap: a four-bar linkage at its pin, a shell
    around a joint), which MoveIt's Setup Assistant disables and no planner can avoid."""
    where = f"pose {ctx.options.pose_name!r}" if ctx.options.pose_name else "the default pose"
    if ctx.options.pose:
        where += " with " + ", ".join(f"{k}={v:g}" for k, v in sorted(ctx.options.pose.items()))
    # the parts as drawn of every link in contact, one scene: a link in several pairs is built once
    drawn = tuple(sorted({link for c in contacts for link in c.links}))
    return [default_pose_finding(ctx, c, where, drawn) for c in contacts]


def parting_depth(ctx: CheckContext, a: str, b: str, q: np.ndarray, depth: float) -> float:
    """The depth [m] of links ``a`` and ``b`` in contact at ``q`` (n_joints,), ``depth`` deep as
    convex shapes: for meshes, the depth at which their triangles part (at most ``depth``: the
    hulls' depth overstates the overlap of hollow or concave parts); ``depth`` for primitives."""
    scene = collision_scene(ctx)
    if not (has_mesh(scene, a) or has_mesh(scene, b)):
        return depth
    frames = kinematics(ctx).link_transforms(np.asarray(q, dtype=float)[None], [a, b])[0]
    resolution = ctx.thresholds.self_collision.sweep_clearance_resolution_m
    return min(depth, separation_depth(scene, a, frames[0], b, frames[1], depth, resolution))


def mesh_contact(ctx: CheckContext, c: PairContact) -> PairContact:
    """``c`` with the depth at which the pair's meshes part when it has any (:func:`parting_depth`)."""
    return replace(c, depth=parting_depth(ctx, *c.links, ctx.analyses.default_configuration, c.depth))


def pose_between(kin: Kinematics, q: np.ndarray, a: str, b: str) -> str:
    """The values of ``q`` worth saying on the joints between links ``a`` and ``b``: those at a
    limit and those off zero (mid-range, where zero is outside a joint's limits), in words
    (``, with FL_knee at its lower limit (0 rad)``), or ``""`` when every one is at zero inside
    its range: a reader then knows the pose without guessing how the default was chosen."""
    said = []
    for name in sorted(kin.path_joints(a, b)):  # by name: the same whatever the document's order
        i = kin.index(name)
        value, lower, upper = float(q[i]), float(kin.lower[i]), float(kin.upper[i])
        unit = "m" if kin.joints[i].type == "prismatic" else "rad"
        limit = "upper" if at_bound(value, upper) else "lower" if at_bound(value, lower) else None
        if limit is not None and np.isfinite(lower) and np.isfinite(upper):
            said.append(f"{name} at its {limit} limit ({value:g} {unit})")
        elif value != 0.0:
            why = " (mid-range: 0 is outside its limits)" if not lower <= 0.0 <= upper else ""
            said.append(f"{name} at {value:.4g} {unit}{why}")
    if not said:
        return ""
    return ", with " + (said[0] if len(said) == 1 else ", ".join(said[:-1]) + " and " + said[-1])


def default_pose_finding(ctx: CheckContext, contact: PairContact, where: str, drawn: tuple[str, ...]) -> Diagnostic:
    """GC403 for one pair in contact at the pose ``where`` names (see :func:`default_pose_findings`);
    ``drawn`` the links whose visual geometry the verdict's scene holds (those of every contact)."""
    scene, kin = collision_scene(ctx), kinematics(ctx)
    sc = ctx.thresholds.self_collision
    q0 = ctx.analyses.default_configuration
    a, b = contact.links
    where += pose_between(kin, q0, a, b)
    hull_depth = contact.depth
    c = mesh_contact(ctx, contact)
    graze = hull_depth > c.depth and c.depth <= sc.mesh_graze_m  # meshes touching at the scale of their facets
    seen = pair_occupancy(kin, scene, q0, c.links, sc.default_pose_samples, sc.seed)
    line = disable_line(c.links, "Default")
    sampled = f"in {seen.collisions} of {seen.tested} sampled poses of the joints between them"
    severity, help = None, None
    if c.depth <= sc.contact_tolerance_m or flush(ctx, a, b, q0):
        severity = Severity.INFO
        text = (
            f"{a} and {b} touch at {where} (apart after a {millimetres(sc.contact_tolerance_m)} shift; in contact "
            f"{sampled}): faces meeting by design, such as closed gripper fingers"
        )
    elif graze:
        severity = Severity.INFO
        text = (
            f"{a} and {b} graze at {where}: their meshes part after a {millimetres(c.depth)} shift (their convex hulls "
            f"overlap {millimetres(hull_depth)}; in contact {sampled}): facets of neighbouring parts touching"
        )
    elif seen.fraction >= sc.always_fraction:
        severity = Severity.INFO
        text = (
            f"{a} and {b} are in collision at {where}: {millimetres(c.depth)} deep, and {sampled}: "
            "an overlap by design, which no pose removes"
        )
    else:
        text = f"{a} and {b} are in collision at {where}: {millimetres(c.depth)} deep, and {sampled}"
        severity, said, help = drawn_verdict(ctx, a, b, q0, drawn)
        text += said
    if hull_depth > c.depth + sc.sweep_clearance_resolution_m and not graze:
        text += f" (the depth at which the meshes part; their convex hulls overlap {millimetres(hull_depth)})"
    return DEFAULT_POSE_COLLISION.diagnose(
        text,
        help=help or contact_help(ctx.loaded.format, c.links, line, severity is Severity.INFO),
        links=c.links,
        location=_shape_location(ctx, scene, a, c.shapes[0]),
        severity=severity,
        data={
            "depth": _r(c.depth, 6),
            "depth_mm": _r(c.depth * 1000, 3),
            "hull_depth_mm": _r(hull_depth * 1000, 3),
            "pose": where,
            "collisions": seen.collisions,
            "tested": seen.tested,
            "srdf_line": line,
        },
    )


def rigidly_attached(ctx: CheckContext, a: str, b: str) -> bool:
    """Whether no joint variable changes the relative pose of links ``a`` and ``b`` (only fixed
    joints on the tree path between them): a contact between them is the same in every
    configuration, the collision matrix's Default (or Adjacent) class, not a default-pose defect."""
    return not kinematics(ctx).path_joints(a, b)


def planned_joints(kin: Kinematics, result: JointSweep, links: tuple[str, str]) -> list[str]:
    """The limited joints (revolute, prismatic) between the two links, which the sweep holds at
    the default pose: the actuated joints of an arm or a leg, which a planner moves to take the
    pair apart. Continuous joints are left out: casters and wheels turn freely, unplanned."""
    swept = {result.group.joint.name, *(c.name for c in result.group.children)}
    return [
        name
        for name in kin.path_joints(*links)
        if name not in swept and kin.joints[kin.index(name)].type != "continuous"
    ]


def deepest_pose(ctx: CheckContext, result: JointSweep, p: PairSweep) -> np.ndarray:
    """The configuration (n_joints,) of the pair's deepest contact in the sweep: the default
    pose with the swept dimensions at their values there."""
    kin = kinematics(ctx)
    q = default_configuration(ctx)
    for name, value in zip(result.group.dimensions, p.deepest, strict=True):
        q[kin.index(name)] = value
    return q


def swept_with(result: JointSweep) -> str:
    """``, with X turning too`` for a sweep that turns joints below its own, else ``""``."""
    below = sorted(result.group.dimensions[1:])
    return f", {' and '.join(below)} turning too" if below else ""


def turning_text(result: JointSweep) -> str:
    """What turns in the sweep, in words: the joint, and the joints below it swept with it (a
    non-round wheel, a leg's next joint), through every combination of their angles."""
    names = (result.group.dimensions[0], *sorted(result.group.dimensions[1:]))  # by name below the joint
    if len(names) == 1:
        return f"{names[0]} turns"
    return f"{', '.join(names[:-1])} and {names[-1]} turn (every combination of their angles)"


def at_text(result: JointSweep, angle: float, values: tuple[float, ...]) -> str:
    """``angle`` of the swept joint in words, with every swept joint's value where the pair comes
    closest (``values``, when known) for a sweep that turns joints below its own."""
    names = result.group.dimensions
    if len(names) == 1 or len(values) != len(names):
        return _deg(angle)
    pairs = list(zip(names, values, strict=True))
    pairs[1:] = sorted(pairs[1:])  # by name below the joint, whatever the document's order
    return ", ".join(f"{n} {_deg(float(wrap(v)))}" for n, v in pairs)


def sweep_findings(ctx: CheckContext, result: JointSweep) -> list[Diagnostic]:
    """GC401-GC404 of one sweep. A contact is an error when only the swept joints move the pair
    (a caster's housing and a wheel: the contact comes whenever the joint turns there, and a
    freely turning joint is not planned around); info for MoveIt's Adjacent pairs (the Setup
    Assistant, Gazebo and MuJoCo never collide a joint's parent and child: no consumer meets the
    contact); info when limited joints between the links move them apart (an ordinary
    self-collision of some poses of an arm or a leg, which MoveIt checks and plans around)."""
    scene = collision_scene(ctx)
    joint = result.group.joint.name
    out = []
    for p in result.pairs:
        moving = p.links[0]
        location = _shape_location(ctx, scene, moving, p.shapes[0])
        data = {
            "joint": joint,
            "moving_link": moving,
            "min_clearance": _r(p.min_clearance, 6),
            "min_clearance_mm": _r(p.min_clearance * 1000, 3),
            "angle_deg": _r(np.degrees(p.min_angle), 2),
        }
        found = sweep_contact(ctx, result, p, location, data)
        contact = found is not None and found.code == SWEEP_COLLISION.code
        if found is not None and contact and not p.proven:
            # one defect, one finding: the contact is the finding, its ranges may be incomplete
            found = replace(
                found,
                message=found.message + f"; the search stopped after {p.queries} distance queries, before every "
                "angle was decided: more contact may lie outside these ranges",
                data={**(found.data or {}), "proven": False, "queries": p.queries},
            )
        if found is not None:
            out.append(found)
        if not p.proven and not contact:
            margin = ctx.thresholds.self_collision.clearance_margin_m
            out.append(unproven_finding(result, p, location, data, margin))
    return one_per_turn(result, out)


def one_per_turn(result: JointSweep, found: list[Diagnostic]) -> list[Diagnostic]:
    """``found``, the findings of one sweep, with its contacts (GC401 above info) reported once: a
    turn that brings several pairs of parts into contact is one cause, most often a joint that
    cannot turn a full turn at all (a leg's hip written continuous: its leg meets the other legs and
    the body), else collision geometry that misses the parts. The deepest contact is the finding,
    naming the others, which stay as info saying so."""
    loud = [d for d in found if d.code == SWEEP_COLLISION.code and d.severity is not Severity.INFO]
    if len(loud) < 2:
        return found
    first = max(loud, key=lambda d: float(d.data.get("max_depth", 0.0)))
    others = [d for d in loud if d is not first]
    named = listed([" / ".join(d.links or ()) for d in others], 4)
    joint = result.group.joint.name
    geometry_help = first.help or ""
    grouped = replace(
        first,
        message=first.message + f"; {len(others)} more pairs of parts meet in the same turn: {named}",
        help=f"If {joint} cannot turn a full turn, declare it revolute with the range it has (its parts then "
        "meet nowhere it can go); otherwise " + geometry_help[:1].lower() + geometry_help[1:],
        data={**first.data, "also_pairs": [list(d.links or ()) for d in others]},
    )
    note = f" (reported with {' / '.join(first.links or ())}: the same turn)"
    ids = {id(d) for d in others}
    return [grouped if d is first else d.grouped_under(first, note) if id(d) in ids else d for d in found]


def unproven_finding(
    result: JointSweep, p: PairSweep, location: SourceLocation | None, data: dict[str, object], margin: float
) -> Diagnostic:
    """GC404 for a pair the sweep could not decide: a warning when the parts graze (the smallest
    clearance found is within ``margin`` [m]), info when the search ran out far from contact or
    the check's shared budget cut it: nothing in the file is shown to need a change."""
    joint = result.group.joint.name
    moving, other = p.links
    far = p.min_clearance >= margin
    note = ""
    if result.shared:
        note = " (the check's budget of sweep queries, shared by its continuous joints, cut this pair's)"
    elif far:
        note = f" (beyond the {millimetres(margin)} margin: the parts do not graze)"
    return SWEEP_UNPROVEN.diagnose(
        f"the sweep of {joint} could not decide {moving} / {other} over the whole turn within "
        f"{p.queries} distance queries; smallest clearance found {millimetres(p.min_clearance)} "
        f"at {at_text(result, p.min_angle, p.deepest)}{swept_with(result)}{note}",
        joint=joint,
        links=p.links,
        location=location,
        severity=Severity.INFO if result.shared or far else None,
        data={**data, "queries": p.queries, "budget_shared": result.shared},
    )


def sweep_contact(
    ctx: CheckContext, result: JointSweep, p: PairSweep, location: SourceLocation | None, data: dict[str, object]
) -> Diagnostic | None:
    """GC401 for a pair in contact during the sweep, GC402 for one passing too close; ``None`` for
    a joint's parent and child overlapping at every angle (the joint's own overlap)."""
    sc = ctx.thresholds.self_collision
    joint = result.group.joint.name
    moving, other = p.links
    if p.adjacent and p.whole_turn:
        return None
    if p.colliding:
        depth = sweep_mesh_depth(ctx, result, p)
        hulls = f" (the depth at which the meshes part; their convex hulls overlap {millimetres(p.max_depth)})"
        text = (
            f"{moving} touches {other} while {turning_text(result)}: in contact "
            f"{'at ' + joint + ' ' if result.group.dimensions[1:] else ''}{ranges_text(p.colliding_ranges)}, "
            f"deepest {millimetres(depth)} at {at_text(result, p.min_angle, p.deepest)}"
            + (hulls if depth < p.max_depth - sc.sweep_clearance_resolution_m else "")
        )
        severity, note = contact_note(ctx, result, p)
        return SWEEP_COLLISION.diagnose(
            text + note,
            help=f"Make the collision geometry match the real parts (shrink or move {moving}'s or {other}'s "
            "collision shapes so they clear over the whole turn), or correct the joint origin.",
            severity=severity,
            joint=joint,
            links=p.links,
            location=location,
            data={
                **data,
                "max_depth": _r(depth, 6),
                "max_depth_mm": _r(depth * 1000, 3),
                "hull_depth_mm": _r(p.max_depth * 1000, 3),
                "ranges_deg": [[_r(np.degrees(lo), 2), _r(np.degrees(hi), 2)] for lo, hi in p.colliding_ranges],
            },
        )
    if p.min_clearance < sc.clearance_margin_m and (not p.adjacent or p.max_clearance >= sc.clearance_margin_m):
        # adjacent links sit close by design: only a clearance that shrinks at some angles is a finding
        return SWEEP_CLEARANCE.diagnose(
            f"{moving} passes {other} with {millimetres(p.min_clearance)} clearance at {_deg(p.min_angle)} "
            f"while {turning_text(result)} (margin {millimetres(sc.clearance_margin_m)})",
            joint=joint,
            links=p.links,
            location=location,
            data={**data, "margin_mm": _r(sc.clearance_margin_m * 1000, 3)},
        )
    return None


def sweep_mesh_depth(ctx: CheckContext, result: JointSweep, p: PairSweep) -> float:
    """The depth [m] of the pair's deepest contact in the sweep (:func:`parting_depth` there: the
    sweep measures the convex hulls', and a leg's hull reaches 189 mm into a chassis shell where
    its triangles reach 15 mm)."""
    if not p.deepest:
        return p.max_depth
    return parting_depth(ctx, *p.links, deepest_pose(ctx, result, p), p.max_depth)


def contact_note(ctx: CheckContext, result: JointSweep, p: PairSweep) -> tuple[Severity | None, str]:
    """The severity of a sweep contact (``None``: the rule's) and what its message adds to say why:
    faces meeting flush, limited joints that a planner moves, or a joint's parent and child."""
    sc = ctx.thresholds.self_collision
    moving, other = p.links
    others = planned_joints(kinematics(ctx), result, p.links)
    if p.deepest and flush(ctx, moving, other, deepest_pose(ctx, result, p)):
        return Severity.INFO, (
            f" (apart after a {millimetres(sc.contact_tolerance_m)} shift there: faces meeting flush, "
            "not an overlap; the depth is that of the convex hulls)"
        )
    if others:
        named = listed(others, 3)
        return Severity.INFO, f", with {named} at the default pose: limited joints that a planner moves to part them"
    if p.adjacent:
        return Severity.INFO, (
            " (parent and child: MoveIt, Gazebo and MuJoCo do not collide them, so no consumer meets it)"
        )
    return None, ""


def pair_section(p: PairSweep) -> dict[str, object]:
    return {
        "links": sorted(p.links),
        "min_clearance": _r(p.min_clearance, 6),
        "min_angle": _r(p.min_angle, 4),
        "colliding_ranges": [[_r(lo, 4), _r(hi, 4)] for lo, hi in p.colliding_ranges],
        "max_depth": _r(p.max_depth, 6),
        "angles": [_r(a, 4) for a in p.chart_angles],
        "clearance": [_r(c, 4) for c in p.chart_clearance],
        "moving_link": p.links[0],
        "adjacent": p.adjacent,
        "clearance_bound": _r(p.clearance_bound, 6),
        "proven": p.proven,
        "queries": p.queries,
    }


def sweep_section(result: JointSweep) -> dict[str, object]:
    group = result.group
    return {
        "joint": group.joint.name,
        "moving_joints": [group.joint.name, *(c.name for c in group.children)],
        "moving_links": list(result.moving_links),
        "grid_points": result.grid_points,
        "proven": result.proven,
        "pairs": [pair_section(p) for p in result.pairs],
        "swept_dimensions": list(group.dimensions),
        "scope": None if group.scope is None else sorted(group.scope),
        "far_pairs": result.far_pairs,
    }


def declared_off(ctx: CheckContext, d: Diagnostic) -> bool:
    """Whether the description itself turns the finding's link pair off (MJCF: MuJoCo never
    computes a contact between a body and its parent, nor an ``<exclude>`` pair): the simulator
    the file is written for lets the parts pass through each other, so a pass-through during a
    sweep is no finding. A ``--srdf`` does not do this: MoveIt's Adjacent pairs are swept."""
    declared = ctx.loaded.declared_collision_filter
    return declared is not None and d.links is not None and declared.is_disabled(*d.links)


def run(ctx: CheckContext) -> FamilyResult:
    result = FamilyResult()
    if not ctx.robot.links:
        return result
    kin = kinematics(ctx)
    scene = collision_scene(ctx)
    for bad in scene.unusable:
        result.skipped.append(SkippedCheck("self-collision", bad.link, f"{bad.shape.label}: {bad.reason}"))
    for link in scene.links:
        if link not in kin.link_names:
            result.skipped.append(SkippedCheck("self-collision", link, f"not connected to the root link {kin.root}"))
    q0 = default_configuration(ctx)
    adjacent = adjacency(ctx)
    document = srdf(ctx)
    keep = None if document is None else (lambda a, b: not document.is_disabled(a, b))
    skip = adjacent | not_pairs(ctx)
    contacts = [c for c in contacts_at(kin, scene, q0, skip, keep) if not rigidly_attached(ctx, *c.links)]
    result.diagnostics += default_pose_findings(ctx, contacts)
    if ctx.options.sweep:
        settings = SweepSettings.from_thresholds(ctx.thresholds.self_collision)
        groups = sweep_groups(kin, scene, q0)
        sections = []
        with Progress(len(groups), "sweep", unit="joint") as bar:
            for group, swept in sweep_continuous_joints(kin, scene, q0, adjacent, settings, bar, groups):
                if swept is None:
                    why = (
                        f"not swept: the check's sweeps spent their budget of {settings.max_queries_total} distance "
                        f"queries (one between meshes counting {settings.mesh_query_weight}) on the joints before it"
                    )
                    result.skipped.append(SkippedCheck("sweep", group.joint.name, why))
                    continue
                result.diagnostics += [d for d in sweep_findings(ctx, swept) if not declared_off(ctx, d)]
                sections.append(sweep_section(swept))
        result.sections["sweeps"] = sections
    return result
