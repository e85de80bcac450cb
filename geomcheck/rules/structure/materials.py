"""GC124, GC128: materials named and never defined, or defined twice."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register
from geomcheck.rules.structure.metrics import ALSO, FIRST

UNDEFINED_MATERIAL = register(
    Rule(
        code="GC124",
        name="undefined-material",
        severity=Severity.INFO,
        summary="A visual refers to a material by name that is defined nowhere with a color or texture.",
        what="Checks named <material> references in visuals against the materials the robot defines.",
        why=(
            "urdfdom keeps the name-only material of the visual and loads the robot; RViz draws the visual in the "
            "default colour instead of the one the name suggests."
        ),
        example='<material name="Wheel_l"/>   <!-- GC124: no <material name="Wheel_l"> with a color -->',
        fix='Define <material name="..."><color rgba="..."/></material> at the top level, or inline a <color>.',
        metrics=(Metric("material", "text", description="The material name."), ALSO),
        severity_reason=(
            "Info: urdfdom keeps a name-only material in place (parseVisual leaves it set) and loads the robot; "
            "RViz draws the visual in the default colour. Cosmetic only, nothing any consumer refuses."
        ),
    )
)

DUPLICATE_MATERIAL = register(
    Rule(
        code="GC128",
        name="duplicate-material-name",
        severity=Severity.ERROR,
        summary="Two top-level <material> elements have the same name.",
        what=(
            "Reports every top-level <material> whose name an earlier top-level <material> already defined (a "
            "material defined inside a visual is not concerned)."
        ),
        why="urdfdom refuses the robot: 'material NAME is not unique'.",
        example='<material name="red">...</material>\n<material name="red">...</material>   <!-- GC128 -->',
        fix="Define each material once (a xacro file of materials included twice is the usual cause).",
        metrics=(Metric("material", "text", description="The material name."), FIRST, ALSO),
        severity_reason=(
            "Error: urdfdom refuses the whole robot ('material NAME is not unique'), even when both definitions "
            "agree. Never lowered."
        ),
    )
)
