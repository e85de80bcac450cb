"""What the parts as drawn say of two links in collision at the default pose (GC403).

Collision geometry is the description's own approximation; the visual geometry draws the parts.
Their overlap at the pose tells a pose the robot cannot take (an arm folded onto itself), or a
limit past the parts' stop, from padded collision geometry meeting at a joint's stop, which
the parts themselves clear.
"""

from __future__ import annotations

import numpy as np

from geomcheck.checks import CheckContext
from geomcheck.checks.wording import millimetres
from geomcheck.diagnostics import Severity
from geomcheck.geometry.elements import VisualCloud
from geomcheck.geometry.neighbours import PARALLEL_COS
from geomcheck.kinematics import Kinematics
from geomcheck.selfcollision.default_pose import separation_depth

LIMIT_ATOL = 1e-9  # a joint value this near a bound [m or rad] is at that limit


def at_bound(value: float, bound: float) -> bool:
    """Whether a joint value is at the (finite) limit ``bound``."""
    return bool(np.isfinite(bound) and np.isclose(value, bound, rtol=0, atol=LIMIT_ATOL))


def drawn_overlap(ctx: CheckContext, a: str, b: str, q: np.ndarray, drawn: tuple[str, ...]) -> float | None:
    """How deep links ``a`` and ``b`` as drawn (their visual geometry: the parts' own meshes)
    overlap at ``q`` (n_joints,), measured as their collision depth is: the shift [m] that parts
    their triangles, at most their convex hulls' depth; 0 when they do not meet, ``None`` when a
    link draws nothing. The scene holds the visual geometry of the links ``drawn`` (``a``, ``b``
    and the other pairs' links, built once for all)."""
    scene = ctx.analyses.visual_scene(drawn)
    if a not in scene.links or b not in scene.links:
        return None
    frames = ctx.analyses.kinematics.link_transforms(np.asarray(q, dtype=float)[None], [a, b])[0]
    hit, hull_depth = scene.pair_collide(a, frames[0], b, frames[1])
    if not hit:
        return 0.0
    resolution = ctx.thresholds.self_collision.sweep_clearance_resolution_m
    return min(hull_depth, separation_depth(scene, a, frames[0], b, frames[1], hull_depth, resolution))


def parted_off_stops(ctx: CheckContext, a: str, b: str, q: np.ndarray) -> bool:
    """Whether links ``a`` and ``b``, in collision at ``q`` (n_joints,) with joints between them at
    a limit, part once each of those joints moves ``stop_probe_fraction`` of its range off it."""
    kin = ctx.analyses.kinematics
    fraction = ctx.thresholds.self_collision.stop_probe_fraction
    off = np.asarray(q, dtype=float).copy()
    for name in kin.path_joints(a, b):
        i = kin.index(name)
        lower, upper = float(kin.lower[i]), float(kin.upper[i])
        if not (np.isfinite(lower) and np.isfinite(upper)):
            continue
        step = fraction * (upper - lower)
        if at_bound(off[i], lower):
            off[i] = lower + step
        elif at_bound(off[i], upper):
            off[i] = upper - step
    frames = kin.link_transforms(off[None], [a, b])[0]
    return not ctx.analyses.collision_scene().pair_collide(a, frames[0], b, frames[1])[0]


def telescoping(ctx: CheckContext, a: str, b: str, q: np.ndarray) -> bool:
    """Whether links ``a`` and ``b`` are sections of a telescope at ``q`` (an arm's nested tubes,
    a mast's stages): only prismatic joints along one direction move them relative to each other,
    and one is drawn nested in the other (:func:`drawn_nested`), not beside it as a lift's
    carriage above its base."""
    kin = ctx.analyses.kinematics
    names = kin.path_joints(a, b)
    if not names or any(kin.joints[kin.index(n)].type != "prismatic" for n in names):
        return False
    axes = kin.tree_axes(np.asarray(q, dtype=float))
    directions = [axes[n][1] for n in names if n in axes]
    if len(directions) != len(names):
        return False
    if not all(abs(float(d @ directions[0])) >= PARALLEL_COS for d in directions):
        return False
    return drawn_nested(ctx, a, b, q)


def drawn_nested(ctx: CheckContext, a: str, b: str, q: np.ndarray) -> bool:
    """Whether, at ``q``, most of one link's visual surface lies within the convex hull of the
    other's (the inner tube within the outer one's envelope), ``nested_share`` of its samples."""
    from geomcheck.checks.fit.shapes import link_visual

    found = [link_visual(ctx, ctx.robot.link_map[name], ctx.thresholds.fit) for name in (a, b)]
    clouds = [c for c in found if isinstance(c, VisualCloud)]
    if len(clouds) != 2:
        return False
    frames = ctx.analyses.kinematics.link_transforms(np.asarray(q, dtype=float)[None], [a, b])[0]
    share = ctx.thresholds.self_collision.nested_share
    for inner, outer in ((0, 1), (1, 0)):
        inside, around = clouds[inner], clouds[outer]
        if around.hull is None or not len(inside.samples):
            continue
        # the inner link's samples in the outer link's frame
        relative = np.linalg.inv(frames[outer]) @ frames[inner]
        points = inside.samples @ relative[:3, :3].T + relative[:3, 3]
        if float(np.mean(around.hull.signed_distance(points) <= 0.0)) >= share:
            return True
    return False


def limits_between(kin: Kinematics, q: np.ndarray, a: str, b: str) -> list[str]:
    """The joints between links ``a`` and ``b`` at a limit in ``q`` (n_joints,), in words
    (``l_shoulder_roll's lower limit``), by name."""
    out = []
    for name in sorted(kin.path_joints(a, b)):
        i = kin.index(name)
        for side, bound in (("lower", float(kin.lower[i])), ("upper", float(kin.upper[i]))):
            if at_bound(float(q[i]), bound):
                out.append(f"{name}'s {side} limit")
    return out


def drawn_verdict(
    ctx: CheckContext, a: str, b: str, q0: np.ndarray, drawn_links: tuple[str, ...]
) -> tuple[Severity | None, str, str | None]:
    """What the parts as drawn say of links ``a`` and ``b`` in collision at ``q0``: ``(severity,
    words to add to the message, help)``. Their visual geometry overlapping there too with a joint
    between them at a limit: the limit lets the parts meet (an error, said so); with every joint
    inside its range: a pose the robot cannot take (info, with how to check another pose).
    ``drawn_links`` are the links the drawn scene holds (:func:`drawn_overlap`)."""
    sc = ctx.thresholds.self_collision
    drawn = drawn_overlap(ctx, a, b, q0, drawn_links)
    apart = drawn is not None and drawn <= sc.mesh_graze_m  # drawn, and clear of each other (or grazing)
    stops = limits_between(ctx.analyses.kinematics, q0, a, b)
    if apart and stops and parted_off_stops(ctx, a, b, q0):
        # the parts themselves clear at the stop, and off it the collision geometry does too
        joints, their = ("that joint", "its") if len(stops) == 1 else ("those joints", "their")
        said = (
            f"; the parts as drawn are apart there, and with {joints} moved {sc.stop_probe_fraction:.0%} of {their} "
            "range off the limit the collision geometry parts too: its margins meet at the stop"
        )
        help = (
            "Nothing to change if the margins are meant; trim the collision geometry where it meets at the stop "
            "if contacts there matter."
        )
        return Severity.INFO, said, help
    if apart and telescoping(ctx, a, b, q0):
        # solid shapes of hollow sections: each fills the hollow the next slides in
        said = (
            "; the parts as drawn are apart there, and only prismatic joints along one direction move them: "
            "nested sections, whose solid collision shapes fill the hollow the other slides in"
        )
        return Severity.INFO, said, None
    if drawn is None or apart:
        return None, "", None
    if stops:
        # a joint at its limit lets the parts themselves meet: the limit is past the part's stop
        verb = "lets" if len(stops) == 1 else "let"
        return (
            None,
            f"; their visual geometry overlaps there too ({millimetres(drawn)} deep): "
            f"{' and '.join(stops)} {verb} the parts themselves meet",
            None,
        )
    # inside every joint's range: a pose the robot cannot take, as an arm folded onto itself
    said = (
        f"; their visual geometry overlaps there too ({millimetres(drawn)} deep): the parts themselves collide, "
        "so the pose is one the robot cannot take, not a fault of the collision geometry"
    )
    help = (
        "Check the robot in a pose it can take: a named SRDF group_state (`--pose-name NAME`) or "
        "joint values (`--pose JOINT=VALUE`). Disabling the pair would hide its collisions in every pose."
    )
    return Severity.INFO, said, help


__all__ = [
    "at_bound",
    "drawn_nested",
    "drawn_overlap",
    "drawn_verdict",
    "limits_between",
    "parted_off_stops",
    "telescoping",
]
