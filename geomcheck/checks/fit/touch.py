"""GC305: what can touch a part without collision geometry of its own (the body it is bolted to, the
links around it at rest, the moving bodies that reach it), by which its severity is chosen."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from geomcheck.checks import CheckContext
from geomcheck.checks.fit.shapes import link_elements, link_visual, resting_neighbours
from geomcheck.checks.wording import length
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.geometry.elements import CollisionElement, VisualCloud
from geomcheck.geometry.frames import pose_frame
from geomcheck.geometry.neighbours import Neighbour, invariant, moved
from geomcheck.geometry.reach import RigidGroups, element_corners, swept_bound
from geomcheck.geometry.suggest import suggest
from geomcheck.geometry.surface import ConvexRegion
from geomcheck.kinematics import rotation_matrices
from geomcheck.model import Box, Cylinder, Joint, Link, Robot, Sphere
from geomcheck.rules import fit as rules
from geomcheck.thresholds import FitThresholds


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
        corners = [element_corners(e) for e in elements] + _drawn_only(ctx, reach.groups, anchor)
        points = np.concatenate(corners) if corners else np.zeros((0, 3))
        # a wheel on the root body occupies the same space at every angle: it never comes at a part
        static = spins_in_place(ctx.robot, anchor, elements)
        swept = swept_bound(ctx.robot, reach.groups, anchor, points) if len(points) and not static else None
        if swept is None and len(points) and not static:
            reach.reaches_anywhere.add(anchor)
        reach.bounds[anchor] = None if swept is None else (swept[0], ConvexRegion.of(swept[1]))
    return reach.bounds[anchor]


def _drawn_only(ctx: CheckContext, groups: RigidGroups, anchor: str) -> list[np.ndarray]:
    """The visual geometry's hull vertices (anchor frame) of the group's links drawn without collision
    geometry: the part is there and sweeps its space though no collision element stands for it (a
    hand exported without collision: its fingers still close on the palm)."""
    out = []
    for name in groups.members(anchor):
        link = ctx.robot.link_map[name]
        if link.collisions:
            continue
        cloud = link_visual(ctx, link, ctx.thresholds.fit)
        if isinstance(cloud, VisualCloud) and cloud.hull is not None:
            rotation, translation = groups.pose[name]
            out.append(cloud.hull.vertices @ rotation.T + translation)
    return out


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
            # simulators with the ground and walls, and a part no collision geometry holds passes through them,
            # unless it stands out of its body's collision geometry by no more than that body's tolerance
            message += rule.message("unreached", anchor=anchor)
            standing = _standing_out(ctx, link, visual, reach.groups, anchor, th)
            if standing is not None and standing[0] <= standing[1]:
                message += rule.message("flush", out=length(standing[0]), allowed=length(standing[1]))
                severity = Severity.INFO
        else:
            message += rule.message("reached", other=reached_by)
    elif anchor is not None:
        message += rule.message("moving", joint=ctx.robot.parent_joint[anchor].name)
    if severity is None and ctx.loaded.format == "mjcf":
        # MuJoCo collides every geom unless its author says otherwise: a body whose geoms collide with
        # nothing (contype and conaffinity 0) was left out of collision on purpose
        message += rule.message("visual_only")
        severity = Severity.INFO
    data: dict[str, Any] = {"suggested": entry["suggested"], "covered_by": covered_by, "reached_by": reached_by}
    if held_by is not None:
        data["held_at_rest_by"] = held_by
    return rule.diagnose(
        message, help=fix, link=link.name, about="collision", location=link.location, data=data, severity=severity
    )


def _standing_out(
    ctx: CheckContext, link: Link, visual: VisualCloud, groups: RigidGroups, anchor: str, th: FitThresholds
) -> tuple[float, float] | None:
    """``(out, allowed)`` [m]: how far ``link``'s visual surface stands out of the collision geometry
    of the rigid body it belongs to, and the tolerance at that body's size (``protrusion_size_fraction``
    of its largest extent, at most ``protrusion_size_cap_m``); ``None`` when the body has none."""
    elements = _group_elements(ctx, groups, anchor, skip=link.name)
    if not elements or not len(visual.samples):
        return None
    rotation, translation = groups.pose[link.name]
    samples = visual.samples @ rotation.T + translation
    out = float(np.max(np.min([e.signed_distance(samples) for e in elements], axis=0)))
    corners = np.concatenate([element_corners(e) for e in elements])
    allowed = min(th.protrusion_size_fraction * float(np.ptp(corners, axis=0).max()), th.protrusion_size_cap_m)
    return max(out, 0.0), allowed
