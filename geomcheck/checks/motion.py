"""GC42x: how joints move their parts, judged on the parts' own geometry.

GC420 compares the axis of a joint that turns fully (a continuous joint, or a revolute one with a
range of a full turn or more) with the axis its child link's visual geometry is round about
(:mod:`geomcheck.geometry.revolution`): a wheel's axle, a flange's axis. Visual geometry comes from
the fit family's product (:func:`geomcheck.checks.fit.link_visual`), read once per link.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.fit import link_visual
from geomcheck.checks.wording import length
from geomcheck.diagnostics import Diagnostic
from geomcheck.geometry.elements import VisualCloud
from geomcheck.geometry.revolution import about, revolution
from geomcheck.model import Joint
from geomcheck.rules.motion import JOINT_AXIS_OFF_PART_AXIS
from geomcheck.thresholds import MotionThresholds

FULL_TURN = 2.0 * math.pi
AXIS_DECIMALS = 4  # components of an axis in a message and the report: a tenth of a milliradian


def turns_fully(joint: Joint) -> bool:
    """Whether ``joint`` can turn its child a full turn: continuous, or revolute over 360 degrees or more."""
    if joint.type == "continuous":
        return True
    limit = joint.limit
    if joint.type != "revolute" or limit is None or limit.lower is None or limit.upper is None:
        return joint.type == "revolute" and limit is not None and limit.unlimited
    return limit.upper - limit.lower >= FULL_TURN * (1.0 - 1e-6)


def snapped(axis: np.ndarray, within_deg: float) -> np.ndarray:
    """``axis`` (unit) as the frame axis it is within ``within_deg`` of (a part's axis measured on
    its mesh, a few milliradians off the axis its author drew it about), else as it is."""
    k = int(np.argmax(np.abs(axis)))
    if math.degrees(math.acos(min(1.0, abs(float(axis[k]))))) <= within_deg:
        out = np.zeros(3)
        out[k] = math.copysign(1.0, float(axis[k]))
        return out
    return axis


def axis_text(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{round(float(c), AXIS_DECIMALS) + 0.0:g}" for c in v) + ")"


def off_axis(ctx: CheckContext, th: MotionThresholds) -> Iterator[Diagnostic]:
    """GC420 for every joint that turns fully a round part about another axis than its own."""
    fit_th = ctx.thresholds.fit
    for joint in ctx.robot.joints:
        link = ctx.robot.link_map.get(joint.child)
        norm = float(np.linalg.norm(joint.axis))
        if link is None or norm == 0.0 or not turns_fully(joint):
            continue
        visual = link_visual(ctx, link, fit_th)
        if not isinstance(visual, VisualCloud) or visual.hull is None:
            continue
        part = revolution(visual.samples, visual.vertices, th.revolution_equal_moments)
        if part is None or part.roundness > th.revolution_roundness:
            continue
        if part.length > th.revolution_max_length_ratio * 2.0 * part.radius:
            continue
        axis = np.asarray(joint.axis, dtype=float) / norm
        # the joint frame is the child link's frame: the joint sits at the link origin, which must lie on
        # the part's own axis and within its length (a wheel on its axle, a flange on its wrist)
        if not part.holds(np.zeros(3), th.revolution_centre_fraction * part.radius):
            continue
        own = snapped(part.axis if float(axis @ part.axis) >= 0.0 else -part.axis, th.revolution_snap_deg)
        angle = math.degrees(math.acos(min(1.0, abs(float(axis @ own)))))
        if angle <= th.revolution_axis_tolerance_deg:
            continue
        part = about(part, own, visual.samples, visual.vertices)
        xyz = " ".join(f"{c:g}" for c in np.round(own, 6) + 0.0)
        yield JOINT_AXIS_OFF_PART_AXIS.diagnose(
            JOINT_AXIS_OFF_PART_AXIS.message(
                joint=joint.name,
                link=link.name,
                axis=axis_text(axis),
                part_axis=axis_text(own),
                roundness=part.roundness,
                diameter=length(2.0 * part.radius),
                length=length(part.length),
                angle=angle,
            ),
            help=f'Turn the joint about the part\'s own axis: <axis xyz="{xyz}"/> (or its opposite).',
            joint=joint.name,
            about="axis",
            location=joint.location,
            data={
                "axis": [round(float(c), AXIS_DECIMALS) + 0.0 for c in axis],
                "part_axis": [round(float(c), AXIS_DECIMALS) + 0.0 for c in own],
                "angle_deg": round(angle, 2),
                "radius": round(part.radius, 6),
                "length": round(part.length, 6),
                "roundness": round(part.roundness, 4),
            },
        )


def run(ctx: CheckContext) -> FamilyResult:
    return FamilyResult(diagnostics=list(off_axis(ctx, ctx.thresholds.motion)))
