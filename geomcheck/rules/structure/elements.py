"""GC105-GC109, GC126, GC127, GC129: URDF elements, attributes and numbers as urdfdom reads them."""

from __future__ import annotations

from dataclasses import replace

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register
from geomcheck.rules.structure.metrics import ACCEPTED_BY, ALSO, ATTRIBUTE, ELEMENT, SUGGESTION

UNKNOWN_ELEMENT = register(
    Rule(
        code="GC105",
        name="unknown-urdf-element",
        severity=Severity.WARNING,
        summary="An element inside the URDF core is not part of the URDF specification (a typo such as <orgin>).",
        what=(
            "Checks the children of <link>, <joint>, <visual>, <collision>, <inertial>, <geometry>, "
            "<material> and top-level elements that resemble core ones, and suggests the closest valid "
            "name. Extension elements (<gazebo>, <transmission>, sensors, namespaced elements) are ignored. A "
            "near-miss "
            "of a valid name, or a core element whose content is lost where it stands, is a warning; extension markup "
            "no consumer reads there is info, one finding per kind for the robot naming the other places. An "
            "<inertial>, <visual> or <collision> written as a child of <robot> (after a </link> closed too early) is "
            "reported on the link it follows: urdfdom drops it, and that link loses its mass or its geometry."
        ),
        why=(
            "URDF parsers skip unknown elements silently: a misspelt <origin> leaves the element at the "
            "identity pose, a misspelt <collision> removes the collision geometry."
        ),
        example='<visual>\n  <orgin xyz="0 0 0.1"/>   <!-- GC105: did you mean <origin>? -->',
        fix="Rename the element to the URDF name suggested, or move extension data into a <gazebo> block.",
        metrics=(ELEMENT, Metric("parent", "text", description="The element it is in."), SUGGESTION, ALSO),
        messages={
            "outside_link": "<{tag}> is a child of <robot>, after link {link} closed: urdfdom reads it only inside "
            "a <link> and drops it here, so link {link} goes without it",
        },
        severity_reason=(
            "Warning when the author's intent is silently lost: the element is a near-miss of a name valid at that "
            "place (did you mean), or a core element whose pose, geometry or inertia every consumer drops where it "
            "stands. Info, once per kind for the whole robot, for markup no consumer reads and that carries "
            "nothing: extension and vendor elements (Gazebo's <surface> in a collision, <joint_properties>), "
            "<material> inside <collision> (a collision has no appearance), an identity <origin> in the wrong "
            "place."
        ),
    )
)

UNKNOWN_ATTRIBUTE = register(
    Rule(
        code="GC106",
        name="unknown-urdf-attribute",
        severity=Severity.WARNING,
        summary="An attribute of a URDF core element is not in the specification (a typo such as xzy).",
        what=(
            "Checks every attribute of the URDF core elements and suggests the closest valid name. "
            "Attributes that a well-known tool defines on a core element and reads there are extensions, "
            "not typos, and are not reported: Franka's joint friction model on `<dynamics>` (`D`, `K`, "
            "`mu_coulomb`, `mu_viscous`, written by franka_description), PyBullet's `concave` and `mask` "
            "on `<collision>` and Isaac Gym's `dont_collapse` on `<joint>`; a misspelling of one is reported with "
            "it as the suggestion. Severity: a "
            "warning for a near-miss of a valid name (the value written is lost); info, once per kind for the "
            "robot, for an extension attribute no consumer reads."
        ),
        why="Unknown attributes are ignored by URDF parsers, so the value intended is silently replaced by a default.",
        example='<origin xzy="0 0 0.1"/>   <!-- GC106: did you mean xyz? -->',
        fix="Rename the attribute to the URDF name suggested.",
        metrics=(
            ELEMENT,
            Metric("attributes", "text", description="The unknown attributes."),
            Metric("suggestions", "text", description="The closest known attribute for each, when there is one."),
            ALSO,
        ),
        severity_reason=(
            "Warning when the attribute is a near-miss of one valid on that element (did you mean): the value "
            "written is silently replaced by the default. Info, once per kind for the whole robot, for extension "
            "attributes no URDF consumer reads (<axis rpy>, vendor flags such as dont_collapse)."
        ),
    )
)

INVALID_NUMBER = register(
    Rule(
        code="GC107",
        name="invalid-number",
        severity=Severity.ERROR,
        summary="A numeric attribute does not parse, or has the wrong number of values.",
        what=(
            "Checks every numeric URDF attribute (xyz, rpy, size, radius, mass, inertia, limits, scale, "
            "rgba...) for finite numbers and the expected count. The element keeps its default value."
        ),
        why="urdfdom rejects the whole robot on an unparseable number; other tools read it as zero.",
        example='<origin xyz="0 0,1 0"/>   <!-- GC107: "0,1" is not a number -->',
        fix="Write plain decimal numbers separated by spaces (xyz, rpy, size: three; rgba: four).",
        metrics=(
            ELEMENT,
            ATTRIBUTE,
            Metric("value", "text", description="The value as written (shortened)."),
            Metric("expected", "count", description="How many numbers the attribute takes."),
            ACCEPTED_BY,
            ALSO,
        ),
        severity_reason=(
            "Error: urdfdom refuses the whole robot on a number it cannot parse in a joint, on any joint type (it "
            "parses every <limit>, even of fixed joints); in a link's visual, collision or inertial it logs the "
            "error and loads the robot without that element (accepted_by), which every consumer then lacks. "
            "Never lowered."
        ),
    )
)

MISSING_ATTRIBUTE = register(
    Rule(
        code="GC108",
        name="missing-urdf-attribute",
        severity=Severity.ERROR,
        summary="A required URDF attribute is missing or empty (link name, joint type, box size, mass value...).",
        what="Checks the attributes the URDF specification requires on core elements.",
        why=(
            "urdfdom refuses a robot or joint with a missing required attribute, and drops a visual, collision or "
            "inertial with one."
        ),
        example='<joint name="elbow">   <!-- GC108: no type -->',
        fix="Add the attribute named in the message.",
        metrics=(
            replace(ELEMENT, optional=True),
            replace(ATTRIBUTE, optional=True, description="The missing attribute, when it is not the name."),
            ACCEPTED_BY,
            ALSO,
        ),
        severity_reason=(
            "Error: urdfdom refuses a robot with a required attribute of the robot or a joint missing (a <limit> "
            "without effort or velocity on any joint type, a <dynamics> with neither damping nor friction, a "
            "<safety_controller> without k_velocity); one of a link's visual, collision or inertial makes it log "
            "an error and load the robot without that element (accepted_by), which every consumer then lacks. "
            "Never lowered."
        ),
    )
)

MISSING_ELEMENT = register(
    Rule(
        code="GC109",
        name="missing-urdf-element",
        severity=Severity.ERROR,
        summary="A required URDF child element is missing (<geometry> in a visual, <mass> in an inertial...).",
        what="Checks the child elements the URDF specification requires.",
        why=(
            "urdfdom drops a visual or collision without geometry and an inertial without mass or inertia: the "
            "part is missing in every ROS tool."
        ),
        example="<collision>\n  <origin xyz='0 0 0'/>\n</collision>   <!-- GC109: no <geometry> -->",
        fix="Add the element named in the message, or remove the empty parent.",
        metrics=(replace(ELEMENT, description="The missing element.", optional=True), ACCEPTED_BY, ALSO),
        severity_reason=(
            "Error: urdfdom gives up on a visual or collision without geometry and an inertial without mass or "
            "inertia: it logs the error and loads the robot without that element (accepted_by), which every "
            "consumer then lacks. A document whose root is not <robot> is refused. Never lowered."
        ),
    )
)

NUMBER_OUT_OF_RANGE = register(
    Rule(
        code="GC126",
        name="number-out-of-range",
        severity=Severity.ERROR,
        summary="A numeric attribute is finite but too large for any robot (1e308 in a box size), or a size too small.",
        what=(
            "Checks the magnitude of lengths (origins, sizes, radii, lengths, joint limits, axes), mesh scales, "
            "masses and inertias against the load limits (100 km, 1e5, 1e9 kg, 1e12 kg m^2), and nonzero primitive "
            "sizes and mesh scales against their floor (1 nm, 1e-9). The element keeps its default value, as for an "
            "unparseable number. Joint bounds count only on revolute and prismatic joints, the only ones a consumer "
            "reads them on; there, 1e16 and beyond is SDFormat's 'no limit' (Gazebo reads the joint as unlimited), "
            "and a bound beyond 100 km or 1e5 rad on its own side (a lower bound below, an upper bound above: "
            "999999 on a mobile base's virtual joints) is 'no limit' written as a large number: both reported as "
            "info, and the side taken as unbounded."
        ),
        why=(
            "Such numbers overflow to infinity in the first product or square (a transform, a volume, an "
            "inertia bound): the geometry is no longer finite and no check can say anything about it."
        ),
        example='<box size="1e308 0.1 0.1"/>   <!-- GC126: 1e308 m is beyond 100000 m -->',
        fix="Write the value in metres, kilograms and kg m^2 (a unit or exponent slipped).",
        metrics=(
            ELEMENT,
            ATTRIBUTE,
            Metric("value", "SI", description="The value beyond the limit, in the attribute's unit."),
            Metric("limit", "SI", description="The limit, in the same unit."),
            ACCEPTED_BY,
            ALSO,
        ),
        severity_reason=(
            "Error: geometry built from such a number is not finite and no check can use it; urdfdom loads it as "
            "written (accepted_by), so the finding is geomcheck's, which leaves the element out. Joint bounds are "
            "judged only where a consumer reads them (revolute and prismatic joints); a bound of SDFormat's 'no "
            "limit' magnitude (1e16 and beyond, which Gazebo reads as unlimited), or a bound beyond 1e5 on its own "
            "side, which no joint travels and which urdfdom, MoveIt and pinocchio read as an open range, is info, "
            "and that side is taken as unbounded."
        ),
    )
)

URDF_VERSION = register(
    Rule(
        code="GC127",
        name="unsupported-urdf-version",
        severity=Severity.ERROR,
        summary="<robot version> is not a URDF version urdfdom reads (1.0, 1.1 or 1.2, written as x.y).",
        what=(
            "Reads the version attribute of <robot> as urdfdom does: absent means 1.0; otherwise it must be two "
            "non-negative integers separated by one dot ('1.0', not '1', '1.0.0' or 'one.zero'), and a version "
            "urdfdom reads: 1.0, 1.1 (capsules, quat_xyzw origins) or 1.2 (acceleration, deceleration and jerk "
            "limits). A 1.1 feature in a 1.0 file is ignored by urdfdom and reported where it stands (GC129 for a "
            "capsule)."
        ),
        why=(
            "urdfdom refuses the whole robot when the version attribute is malformed or names a version it does not "
            "read."
        ),
        example='<robot name="r" version="2.0">   <!-- GC127: urdfdom reads 1.0, 1.1 and 1.2 -->',
        fix='Write version="1.0" (or leave it out), or the version whose features the file uses.',
        metrics=(Metric("version", "text", description="The version attribute as written."),),
        severity_reason=(
            "Error: urdfdom refuses the whole robot for it, so robot_state_publisher, MoveIt and every urdfdom "
            "consumer load nothing. Never lowered."
        ),
    )
)

UNKNOWN_GEOMETRY = register(
    Rule(
        code="GC129",
        name="unknown-geometry",
        severity=Severity.ERROR,
        summary="A <geometry> holds a shape the file's URDF version does not define; urdfdom drops the element.",
        what=(
            "Checks the shape inside every <geometry> of a URDF visual or collision: <box>, <cylinder>, <sphere> "
            "and <mesh>, and from URDF 1.1 <capsule>. Any other shape (a <torus>, a <capsule> in a 1.0 file) is "
            "reported and the element is left out of the model, as urdfdom leaves it out."
        ),
        why=(
            "urdfdom logs an error ('Unknown geometry type') and loads the robot without the visual or collision: "
            "the part is not drawn, or not collided, by every ROS tool."
        ),
        example='<geometry><torus radius="1"/></geometry>   <!-- GC129: urdfdom drops this visual -->',
        fix='Use a URDF shape or a mesh; for a capsule, declare <robot version="1.1">.',
        metrics=(ELEMENT, ACCEPTED_BY, ALSO),
        severity_reason=(
            "Error: urdfdom loads the robot (accepted_by) but without the element, so the part is missing in every "
            "consumer. Never lowered."
        ),
    )
)
