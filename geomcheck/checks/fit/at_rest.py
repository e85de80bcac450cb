"""Coverage at rest: the share of a link's visual surface its own and its neighbours' collision
geometry holds at zero joint positions, and a wheel's by its tyre."""

from __future__ import annotations

import numpy as np

from geomcheck.checks import CheckContext
from geomcheck.checks.coverage_cache import stored_resting_coverage
from geomcheck.checks.fit.shapes import link_elements, resting_neighbours
from geomcheck.geometry.elements import CollisionElement, VisualCloud
from geomcheck.geometry.neighbours import moved
from geomcheck.model import Capsule, Cylinder, Link
from geomcheck.thresholds import FitThresholds

TYRE_AXIS_COS = 0.999  # a wheel's cylinder lies along its joint's axis within 2.6 degrees [cos]


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
