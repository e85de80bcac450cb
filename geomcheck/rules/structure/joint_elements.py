"""GC118-GC123, GC125: a joint's type, axis, limits and mimic as written."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register
from geomcheck.rules.structure.metrics import ACCEPTED_BY, ALSO, AXIS, JOINTS, SUGGESTION

UNKNOWN_JOINT_TYPE = register(
    Rule(
        code="GC118",
        name="unknown-joint-type",
        severity=Severity.ERROR,
        summary=(
            "A joint type is not one its format defines (URDF: revolute, continuous, prismatic, fixed, floating, "
            "planar)."
        ),
        what=(
            "Checks the type attribute of every joint against the types of the description's format and suggests "
            "the closest valid type: URDF's six; SDFormat's revolute, continuous, prismatic, fixed, ball, "
            "universal, revolute2, screw and gearbox (geomcheck holds a ball, screw or gearbox joint at its "
            "reference, as a floating one)."
        ),
        why="urdfdom and libsdformat refuse unknown joint types.",
        example='<joint name="j" type="revolut">   <!-- GC118: did you mean revolute? -->',
        fix="Use one of revolute, continuous, prismatic, fixed, floating, planar.",
        metrics=(Metric("type", "text", description="The type as written."), SUGGESTION, ALSO),
        severity_reason=("Error: urdfdom and libsdformat refuse an unknown joint type. Never lowered."),
    )
)

ZERO_AXIS = register(
    Rule(
        code="GC119",
        name="zero-joint-axis",
        severity=Severity.ERROR,
        summary="A moving joint's axis has zero length.",
        what="Checks the <axis xyz> of revolute, continuous, prismatic and planar joints.",
        why="The joint has no direction of motion; kinematics libraries divide by the axis length.",
        example='<axis xyz="0 0 0"/>   <!-- GC119 -->',
        fix='Give the axis a unit direction, e.g. <axis xyz="0 0 1"/>.',
        metrics=(*AXIS, ACCEPTED_BY, ALSO),
        severity_reason=(
            "Error: the joint has no direction of motion; kinematics libraries divide by the axis length (KDL "
            "and pinocchio normalise it into NaN). urdfdom loads a URDF 1.0 file with it as written "
            "(accepted_by); libsdformat refuses it ('The norm of the xyz vector cannot be zero'). Never lowered."
        ),
    )
)

NON_UNIT_AXIS = register(
    Rule(
        code="GC120",
        name="non-unit-joint-axis",
        severity=Severity.WARNING,
        summary="A moving joint's axis is not a unit vector.",
        what="Checks that |axis| is 1 within StructureThresholds.axis_norm_tolerance.",
        why=(
            "Most tools normalise the axis, but some scale prismatic motion or velocity by its length, "
            "so the same joint value means different motions in different tools."
        ),
        example='<axis xyz="0 0 2"/>   <!-- GC120: length 2 -->',
        fix="Normalise the axis (divide by its length).",
        metrics=(*AXIS, ALSO),
        severity_reason=(
            "Warning: tools disagree on whether to normalise the axis, so the joint means different motions in "
            "different tools; a maintainer writes a unit vector."
        ),
    )
)

MISSING_LIMITS = register(
    Rule(
        code="GC121",
        name="missing-joint-limits",
        severity=Severity.ERROR,
        summary="A revolute or prismatic joint has no <limit>.",
        what="Checks that revolute and prismatic joints declare <limit lower upper effort velocity>.",
        why="urdfdom refuses such joints; planners need the range to sample configurations.",
        example='<joint name="elbow" type="revolute"> ... no <limit> ...   <!-- GC121 -->',
        fix='Add <limit lower="..." upper="..." effort="..." velocity="..."/>, or use type="continuous".',
        metrics=(ALSO,),
        severity_reason=(
            "Error for a revolute or prismatic joint without <limit>: urdfdom refuses it. Warning for a <limit> "
            "without lower and upper: urdfdom, MoveIt and pinocchio read the range as [0, 0], so MoveIt and "
            "Gazebo hold the joint at 0, while MuJoCo and PyBullet leave it unlimited: the consumers disagree on "
            "what the joint does, which the maintainer settles (bounds, or type continuous for a wheel); bounds "
            "written as SDFormat's 1e16 'no limit' are not missing."
        ),
    )
)

INVERTED_LIMITS = register(
    Rule(
        code="GC122",
        name="inverted-joint-limits",
        severity=Severity.ERROR,
        summary="A joint's lower limit is above its upper limit.",
        what="Compares <limit lower> and <limit upper> of revolute and prismatic joints.",
        why="The joint has no valid position; planners and controllers reject it or clamp to nonsense.",
        example='<limit lower="1.5" upper="-1.5" effort="10" velocity="1"/>   <!-- GC122 -->',
        fix="Swap the values (check the sign convention of the axis).",
        metrics=(
            Metric("lower", "SI", description="The lower limit [m or rad]."),
            Metric("upper", "SI", description="The upper limit [m or rad]."),
            ACCEPTED_BY,
            ALSO,
        ),
        severity_reason=(
            "Error: the joint has no valid position; MoveIt and controllers reject or clamp it, though urdfdom "
            "loads a URDF 1.0 file with it as written (accepted_by). A bound written as SDFormat's 1e16 'no limit' "
            "is open on its side and never inverts."
        ),
    )
)

MIMIC_MISSING_JOINT = register(
    Rule(
        code="GC123",
        name="mimic-missing-joint",
        severity=Severity.ERROR,
        summary="A <mimic> names a joint that does not exist.",
        what="Checks the joint attribute of every <mimic> against the declared joints.",
        why="The mimicking joint follows nothing: its position is undefined in every tool.",
        example='<mimic joint="fingr_joint" multiplier="1"/>   <!-- GC123 -->',
        fix="Name an existing joint (check the spelling and macro prefixes).",
        metrics=(Metric("mimic", "text", description="The joint the mimic names."), SUGGESTION, ALSO),
        severity_reason=(
            "Error: the mimicking joint follows nothing; urdfdom-based tools leave its position undefined or "
            "refuse it. Never lowered."
        ),
    )
)

MIMIC_CYCLE = register(
    Rule(
        code="GC125",
        name="mimic-cycle",
        severity=Severity.ERROR,
        summary="Mimic joints follow each other in a loop (or a joint mimics itself).",
        what="Follows <mimic> references from every joint and reports loops.",
        why="No joint of the loop has an independent position; tools recurse forever or reject the robot.",
        example='<joint name="a"><mimic joint="a"/></joint>   <!-- GC125 -->',
        fix="Make one joint of the loop independent (remove its <mimic>).",
        metrics=(JOINTS, ALSO),
        severity_reason=(
            "Error: no joint of the loop has a position; tools recurse forever or reject the robot. Never lowered."
        ),
    )
)
