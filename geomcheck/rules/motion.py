"""GC420-GC429: how joints move their parts, judged on the parts' geometry (checks: :mod:`geomcheck.checks.motion`)."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register

JOINT_AXIS_OFF_PART_AXIS = register(
    Rule(
        code="GC420",
        name="joint-axis-off-part-axis",
        severity=Severity.ERROR,
        summary="A joint spins a round part (a wheel, a flange) about another axis than the part's own.",
        what=(
            "For a continuous joint, or a revolute joint whose range is a full turn or more, whose child link's "
            "visual geometry is a body of revolution (one distinct principal axis of its surface, and its convex "
            "hull reaching equally far from that axis all around, within `revolution_roundness` (5%)) no longer "
            "along that axis than `revolution_max_length_ratio` (1) times across it (a wheel, a tyre, a flange, a "
            "pulley), and whose joint sits on the part's axis (its origin within `revolution_centre_fraction` (25%) "
            "of the part's radius of that axis, and within the part's length along it): reported when the joint "
            "axis is more than `revolution_axis_tolerance_deg` "
            "(10 degrees) away from the part's own axis. A sphere or a cube has no axis of its own and is not "
            "judged, nor a part that turns less than a full turn (a tilting sensor)."
        ),
        why=(
            "A joint that turns fully is the part's own rotation: a wheel's axle, a wrist's flange. Turned about "
            "another axis the part wobbles about one of its diameters: the wheel rolls sideways, the tool flange "
            "tumbles, and every simulator, planner and controller moves the robot that way."
        ),
        example=(
            '<joint name="joint_6" type="revolute"><axis xyz="0 0 -1"/> ...   <!-- the flange of link_6 is round '
            'about x: <axis xyz="-1 0 0"/> -->'
        ),
        fix="Set the joint's <axis> along the part's own axis (the report gives it, in the joint's frame).",
        severity_reason=(
            "Error: the robot moves wrongly in every consumer (the wheel drives sideways, the flange tumbles), "
            "and the geometry decides it. Never lowered."
        ),
        metrics=(
            Metric("axis", "1", description="The joint's axis as written (unit)."),
            Metric("part_axis", "1", description="The axis the part is round about, in the joint's frame."),
            Metric("angle_deg", "deg", "lower", "The angle between them."),
            Metric("radius", "m", description="The part's radius about its own axis."),
            Metric("length", "m", description="The part's length along its own axis."),
            Metric("roundness", "1", description="How much the part's reach differs around its axis."),
        ),
        messages={
            "": "joint {joint} turns link {link} about {axis}, but the link's geometry is round about {part_axis} "
            "(within {roundness:.0%}, {diameter} across and {length} long): {angle:.0f} degrees apart, the part "
            "wobbles about a diameter instead of spinning on its axis",
        },
    )
)
