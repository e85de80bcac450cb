"""GC118-GC123, GC125, GC130: joint types, axes and limits, mimics and their ranges."""

from __future__ import annotations

import math
from collections.abc import Iterator

from geomcheck.checks.structure.formats import FORMAT_JOINT_TYPES, REFERENCE_PARSER
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load.urdf_spec import closest, did_you_mean
from geomcheck.model import JOINT_TYPES, Joint, Robot
from geomcheck.rules.joints import MIMIC_OUTSIDE_LIMITS
from geomcheck.rules.structure import (
    INVERTED_LIMITS,
    MIMIC_CYCLE,
    MIMIC_MISSING_JOINT,
    MISSING_LIMITS,
    NON_UNIT_AXIS,
    UNKNOWN_JOINT_TYPE,
    ZERO_AXIS,
)
from geomcheck.thresholds import StructureThresholds

AXIS_JOINT_TYPES = ("revolute", "continuous", "prismatic", "planar")
LIMITED_JOINT_TYPES = ("revolute", "prismatic")
SECOND_AXIS = "::axis2"  # the suffix of the joint an SDFormat universal or revolute2 joint's second axis is


def joint_subject(joint: Joint) -> tuple[str, str]:
    """The joint a finding names and the part of it (``""``, or ``axis2.`` for the second axis of
    an SDFormat two-axis joint): the file's joint, never one the loader made."""
    if joint.synthetic and joint.name.endswith(SECOND_AXIS):
        return joint.written_name, "axis2."
    return joint.written_name, ""


def joint_definitions(robot: Robot, thresholds: StructureThresholds, fmt: str = "urdf") -> Iterator[Diagnostic]:
    """GC118-GC122: joint type, axis, limits, each judged by the description's format."""
    types = FORMAT_JOINT_TYPES.get(fmt, JOINT_TYPES)
    accepted = {"accepted_by": REFERENCE_PARSER[fmt]} if fmt in ("urdf", "sdf") else {}
    for joint in robot.joints:
        name, part = joint_subject(joint)
        if joint.type and joint.type not in types and not joint.synthetic:
            written = joint.written_type
            yield UNKNOWN_JOINT_TYPE.diagnose(
                f"joint type {written!r} is not one of {', '.join(types)}{did_you_mean(written, types)}",
                joint=name,
                about="type",
                location=joint.location,
                data={"type": written, "suggestion": closest(written, types)},
            )
        if joint.type in AXIS_JOINT_TYPES:
            norm = math.sqrt(sum(c * c for c in joint.axis))
            axis = " ".join(f"{c:g}" for c in joint.axis)
            if norm < thresholds.min_axis_norm:
                zero_data: dict[str, object] = {"axis": list(joint.axis), "norm": norm}
                message = f'{joint.type} joint has a zero-length axis (xyz="{axis}")'
                if fmt == "urdf":  # libsdformat and MuJoCo refuse it before
                    message += "; urdfdom loads it as written, and KDL and pinocchio turn it into NaN"
                    zero_data.update(accepted)
                yield ZERO_AXIS.diagnose(
                    message, joint=name, about=f"{part}axis", location=joint.location, data=zero_data
                )
            elif abs(norm - 1.0) > thresholds.axis_norm_tolerance:
                yield NON_UNIT_AXIS.diagnose(
                    f'axis xyz="{axis}" has length {norm:.6g}, not 1',
                    joint=name,
                    about=f"{part}axis",
                    location=joint.location,
                    data={"axis": list(joint.axis), "norm": norm},
                )
        if joint.type in LIMITED_JOINT_TYPES:
            yield from _limits(joint, name, part, accepted)


def _limits(joint: Joint, name: str, part: str, accepted: dict[str, str]) -> Iterator[Diagnostic]:
    limit = joint.limit
    about = f"{part}limit"
    if limit is None:
        yield MISSING_LIMITS.diagnose(
            f"{joint.type} joint has no <limit>",
            joint=name,
            about=about,
            location=joint.location,
        )
        return
    if limit.lower is None and limit.upper is None and not limit.unlimited:
        yield MISSING_LIMITS.diagnose(
            f"{joint.type} joint's <limit> has no lower or upper: urdfdom reads its range as [0, 0], so "
            "MoveIt and Gazebo hold it at 0, while MuJoCo and PyBullet leave it unlimited",
            joint=name,
            about=about,
            location=joint.location,
            severity=Severity.WARNING,
        )
        return
    # an absent bound is 0 in urdfdom; one written as SDFormat's "no limit" is open on its side
    lower = (-math.inf if limit.unlimited else 0.0) if limit.lower is None else limit.lower
    upper = (math.inf if limit.unlimited else 0.0) if limit.upper is None else limit.upper
    if lower > upper:
        unit = "m" if joint.type == "prismatic" else "rad"
        message = f"lower limit {lower:g} {unit} is above upper limit {upper:g} {unit}"
        if accepted:
            message += f"; {accepted['accepted_by']} loads it as written, and planners find no valid position"
        yield INVERTED_LIMITS.diagnose(
            message,
            joint=name,
            about=about,
            location=joint.location,
            data={"lower": lower, "upper": upper, **accepted},
        )


def mimics(robot: Robot) -> Iterator[Diagnostic]:
    """GC123/GC125: mimics of missing joints and loops of mimics."""
    joints = robot.joint_map
    for joint in robot.joints:
        if joint.mimic is None:
            continue
        target = joint.mimic.joint
        if target not in joints:
            yield MIMIC_MISSING_JOINT.diagnose(
                f"<mimic joint={target!r}> names no joint{did_you_mean(target, joints)}",
                joint=joint_subject(joint)[0],
                about="mimic",
                location=joint.location,
                data={"mimic": target, "suggestion": closest(target, joints)},
            )
    reported: set[frozenset[str]] = set()
    for joint in robot.joints:
        chain: list[str] = []
        name: str | None = joint.name
        while name is not None and name in joints and name not in chain:
            chain.append(name)
            mimic = joints[name].mimic
            name = mimic.joint if mimic is not None else None
        if name is None or name not in chain:
            continue
        loop = chain[chain.index(name) :]
        if frozenset(loop) in reported:
            continue
        reported.add(frozenset(loop))
        first = min(loop, key=[j.name for j in robot.joints].index)
        yield MIMIC_CYCLE.diagnose(
            "mimic joints follow each other in a loop: " + " -> ".join([*loop, loop[0]]),
            joint=first,
            about="mimic",
            location=joints[first].location,
            data={"joints": loop},
        )


def _bounds(joint: Joint) -> tuple[float, float] | None:
    """A revolute or prismatic joint's finite ``(lower, upper)``, else ``None``."""
    limit = joint.limit
    if joint.type not in ("revolute", "prismatic") or limit is None:
        return None
    if limit.lower is None or limit.upper is None or not (math.isfinite(limit.lower) and math.isfinite(limit.upper)):
        return None
    return (limit.lower, limit.upper) if limit.lower <= limit.upper else None


def mimic_ranges(robot: Robot, thresholds: StructureThresholds) -> Iterator[Diagnostic]:
    """GC130: mimic joints whose limits cut off the positions their leader's range gives them."""
    joints = robot.joint_map
    for joint in robot.joints:
        mimic = joint.mimic
        leader = joints.get(mimic.joint) if mimic is not None else None
        if mimic is None or leader is None or leader is joint:
            continue
        own, led = _bounds(joint), _bounds(leader)
        if own is None or led is None or led[1] <= led[0] or mimic.multiplier == 0.0:
            continue
        ends = sorted(mimic.multiplier * q + mimic.offset for q in led)
        span = ends[1] - ends[0]
        cut = max(0.0, own[0] - ends[0]) + max(0.0, ends[1] - own[1])
        share = min(1.0, cut / span)
        unit = "m" if joint.type == "prismatic" else "rad"
        rounding = thresholds.mimic_shortfall_m if unit == "m" else thresholds.mimic_shortfall_rad
        if share <= thresholds.mimic_range_tolerance or max(own[0] - ends[0], ends[1] - own[1]) <= rounding:
            continue
        offset_text = f" and offset {mimic.offset:g} {unit}" if mimic.offset else ""
        yield MIMIC_OUTSIDE_LIMITS.diagnose(
            MIMIC_OUTSIDE_LIMITS.message(
                leader=leader.name,
                leader_lower=led[0],
                leader_upper=led[1],
                unit=unit,
                multiplier=mimic.multiplier,
                offset_text=offset_text,
                needed_lower=ends[0],
                needed_upper=ends[1],
                lower=own[0],
                upper=own[1],
                share=share,
            ),
            joint=joint.name,
            about="limit",
            location=joint.location,
            severity=Severity.ERROR if share >= thresholds.mimic_gross_share else Severity.WARNING,
            data={
                "leader": leader.name,
                "multiplier": mimic.multiplier,
                "offset": mimic.offset,
                "needed": [round(v, 9) + 0.0 for v in ends],
                "limits": list(own),
                "outside_share": round(share, 4),
            },
        )
