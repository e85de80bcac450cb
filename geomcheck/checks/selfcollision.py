"""GC401-GC404: the continuous-joint sweep (when ``options.sweep``) and default-pose collisions.

The self-collision products shared with the matrix family are ``ctx.analyses`` products
(:mod:`geomcheck.checks.analyses`); :func:`kinematics`, :func:`collision_scene` (per backend),
:func:`adjacency`, :func:`not_pairs`, :func:`srdf` and :func:`default_configuration` read them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.collision import CollisionScene
from geomcheck.diagnostics import Diagnostic, SkippedCheck
from geomcheck.kinematics import Kinematics
from geomcheck.load.srdf import Srdf
from geomcheck.model import SourceLocation
from geomcheck.progress import Progress
from geomcheck.rules.selfcollision import DEFAULT_POSE_COLLISION, SWEEP_CLEARANCE, SWEEP_COLLISION, SWEEP_UNPROVEN
from geomcheck.selfcollision.default_pose import PairContact, contacts_at
from geomcheck.selfcollision.sweep import JointSweep, PairSweep, SweepSettings, sweep_joint
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
def _mm(metres: float) -> str:
    return f"{metres * 1000:.1f} mm"


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
def default_pose_findings(ctx: CheckContext, contacts: Sequence[PairContact]) -> list[Diagnostic]:
    scene = collision_scene(ctx)
    where = f"pose {ctx.options.pose_name!r}" if ctx.options.pose_name else "the default pose"
    if ctx.options.pose:
        where += " with " + ", ".join(f"{k}={v:g}" for k, v in sorted(ctx.options.pose.items()))
    out = []
    for c in contacts:
        a, b = c.links
        out.append(
            DEFAULT_POSE_COLLISION.diagnose(
                f"{a} and {b} are in collision at {where}: {_mm(c.depth)} deep",
                links=c.links,
                location=_shape_location(ctx, scene, a, c.shapes[0]),
                data={"depth": _r(c.depth, 6), "depth_mm": _r(c.depth * 1000, 3), "pose": where},
            )
        )
    return out


def rigidly_attached(ctx: CheckContext, a: str, b: str) -> bool:
    """Whether no joint variable changes the relative pose of links ``a`` and ``b`` (only fixed
    joints on the tree path between them): a contact between them is the same in every
    configuration, the collision matrix's Default (or Adjacent) class, not a default-pose defect."""
    return not kinematics(ctx).path_joints(a, b)


def sweep_findings(ctx: CheckContext, result: JointSweep) -> list[Diagnostic]:
    scene = collision_scene(ctx)
    sc = ctx.thresholds.self_collision
    joint = result.group.joint.name
    out = []
    for p in result.pairs:
        moving, other = p.links
        location = _shape_location(ctx, scene, moving, p.shapes[0])
        data = {
            "joint": joint,
            "moving_link": moving,
            "min_clearance": _r(p.min_clearance, 6),
            "min_clearance_mm": _r(p.min_clearance * 1000, 3),
            "angle_deg": _r(np.degrees(p.min_angle), 2),
        }
        if p.adjacent and p.whole_turn:
            pass  # a joint's parent and child overlapping at every angle: the joint's own overlap
        elif p.colliding:
            out.append(
                SWEEP_COLLISION.diagnose(
                    f"{moving} touches {other} while {joint} turns: in contact {ranges_text(p.colliding_ranges)}, "
                    f"deepest {_mm(p.max_depth)} at {_deg(p.min_angle)}",
                    joint=joint,
                    links=p.links,
                    location=location,
                    data={
                        **data,
                        "max_depth": _r(p.max_depth, 6),
                        "max_depth_mm": _r(p.max_depth * 1000, 3),
                        "ranges_deg": [[_r(np.degrees(lo), 2), _r(np.degrees(hi), 2)] for lo, hi in p.colliding_ranges],
                    },
                )
            )
        elif p.min_clearance < sc.clearance_margin_m and (not p.adjacent or p.max_clearance >= sc.clearance_margin_m):
            # adjacent links sit close by design: only a clearance that shrinks at some angles is a finding
            out.append(
                SWEEP_CLEARANCE.diagnose(
                    f"{moving} passes {other} with {_mm(p.min_clearance)} clearance at {_deg(p.min_angle)} "
                    f"while {joint} turns (margin {_mm(sc.clearance_margin_m)})",
                    joint=joint,
                    links=p.links,
                    location=location,
                    data={**data, "margin_mm": _r(sc.clearance_margin_m * 1000, 3)},
                )
            )
        if not p.proven:
            out.append(
                SWEEP_UNPROVEN.diagnose(
                    f"the sweep of {joint} could not decide {moving} / {other} over the whole turn within "
                    f"{p.queries} distance queries; smallest clearance found {_mm(p.min_clearance)} "
                    f"at {_deg(p.min_angle)}",
                    joint=joint,
                    links=p.links,
                    location=location,
                    data={**data, "queries": p.queries},
                )
            )
    return out


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
        with Progress(len(groups), "sweep", enabled=ctx.options.progress, unit="joint") as bar:
            for group in groups:
                swept = sweep_joint(kin, scene, q0, adjacent, settings, group)
                result.diagnostics += [d for d in sweep_findings(ctx, swept) if not declared_off(ctx, d)]
                sections.append(sweep_section(swept))
                bar.advance(note=group.joint.name)
        result.sections["sweeps"] = sections
    return result
