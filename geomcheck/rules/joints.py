"""GC13x: joints that cannot move as written (structure family).

Checks live in :mod:`geomcheck.checks.structure.joints`."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register

MIMIC_OUTSIDE_LIMITS = register(
    Rule(
        code="GC130",
        name="mimic-outside-limits",
        severity=Severity.ERROR,
        summary="A mimic joint's limits do not hold the positions its leader's range gives it.",
        what=(
            "A <mimic> joint is placed at multiplier * leader + offset. Where both joints are revolute or "
            "prismatic with limits, maps the leader's range through the mimic and reports the share of the "
            "leader's range whose image lies outside the mimic joint's own limits, beyond a tolerance of "
            "`mimic_range_tolerance` (1%) of that range and of `mimic_shortfall_rad` (0.5 degree) or "
            "`mimic_shortfall_m` (0.5 mm) at either end (the rounding of limits written to a few decimals): an "
            "error when that share is at least `mimic_gross_share` (50%), a warning above the tolerance."
        ),
        why=(
            "MoveIt sets a mimic joint from its leader without clamping and then finds the state out of bounds "
            "(planning from or to it fails), Gazebo's mimic constraint fights the joint's own limit, and "
            "ros2_control clamps the command: the linkage cannot follow its leader over the range written."
        ),
        example=(
            '<joint name="finger_joint"><limit lower="0" upper="0.8"/></joint>\n'
            '<joint name="left_inner_knuckle_joint"><mimic joint="finger_joint" multiplier="-1"/>\n'
            '  <limit lower="0" upper="0.8757"/>   <!-- GC130: it must reach -0.8 .. 0 -->'
        ),
        fix=(
            "Set the mimic joint's limits to hold multiplier * leader + offset over the leader's range (a "
            "negative multiplier flips them), or correct the multiplier's sign."
        ),
        severity_reason=(
            "Error when the mimic joint cannot follow over most of its leader's range: MoveIt refuses such states "
            "and simulators fight their own constraint. A warning when only the ends are cut off: the linkage "
            "stops short, which its maintainer would correct. Never lowered."
        ),
        metrics=(
            Metric("leader", "text", description="The joint it mimics."),
            Metric("multiplier", "1", description="The mimic's multiplier."),
            Metric("offset", "SI", description="The mimic's offset."),
            Metric("needed", "SI", description="The positions the leader's range gives it: lower, upper."),
            Metric("limits", "SI", description="Its own limits: lower, upper."),
            Metric("outside_share", "1", "lower", "The share of the leader's range it cannot follow."),
        ),
        messages={
            "": "mimics {leader} ({leader_lower:.4g} to {leader_upper:.4g} {unit}) with multiplier {multiplier:g}"
            "{offset_text}: it must reach {needed_lower:.4g} to {needed_upper:.4g} {unit}, but its limits are "
            "{lower:.4g} to {upper:.4g} {unit}: over {share:.0%} of {leader}'s range it cannot follow",
        },
    )
)
