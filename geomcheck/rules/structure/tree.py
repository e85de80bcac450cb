"""GC110-GC117: unique names and one kinematic tree (links and joints, one root, no loop)."""

from __future__ import annotations

from dataclasses import replace

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register
from geomcheck.rules.structure.metrics import ACCEPTED_BY, ALSO, JOINTS, SUGGESTION

DUPLICATE_LINK = register(
    Rule(
        code="GC110",
        name="duplicate-link-name",
        severity=Severity.ERROR,
        summary="Two links have the same name.",
        what="Reports every link whose name was already used by an earlier link.",
        why="Link names identify frames; urdfdom refuses duplicates, and TF cannot hold two frames with one name.",
        example='<link name="wheel"/>\n<link name="wheel"/>   <!-- GC110 -->',
        fix="Rename one of the links (a macro instantiated twice with the same prefix is the usual cause).",
        metrics=(Metric("first", "text", description="Where the name was first used."), ALSO),
        severity_reason=("Error: urdfdom refuses duplicate link names ('link is not unique'). Never lowered."),
    )
)

DUPLICATE_JOINT = register(
    Rule(
        code="GC111",
        name="duplicate-joint-name",
        severity=Severity.ERROR,
        summary="Two joints have the same name.",
        what="Reports every joint whose name was already used by an earlier joint.",
        why="Joint names key joint states and controllers; urdfdom refuses duplicates.",
        example='<joint name="j1" .../>\n<joint name="j1" .../>   <!-- GC111 -->',
        fix="Rename one of the joints.",
        metrics=(Metric("first", "text", description="Where the name was first used."), ALSO),
        severity_reason=("Error: urdfdom refuses duplicate joint names. Never lowered."),
    )
)

JOINT_MISSING_LINK = register(
    Rule(
        code="GC112",
        name="joint-missing-link",
        severity=Severity.ERROR,
        summary="A joint has no <parent>/<child>, or names a link that is not declared.",
        what=(
            "Checks that every joint has a parent and a child link and that both are declared. A parent "
            "called world is reported separately (GC113)."
        ),
        why="The joint cannot be placed in the kinematic tree; urdfdom refuses the robot.",
        example='<joint name="j" type="fixed">\n  <parent link="bse_link"/>   <!-- GC112 -->',
        fix="Declare the link, fix the spelling of its name, or add the missing <parent>/<child> element.",
        metrics=(
            Metric("role", "text", description="parent, child, or parent+child when the joint names neither."),
            Metric("link", "text", description="The link name the joint gives, or null when it gives none."),
            ALSO,
            replace(SUGGESTION, optional=True, description="The closest declared link, when a name is given."),
        ),
        severity_reason=(
            "Error: urdfdom refuses a joint without parent or child, or naming an undeclared link, when it builds "
            "the tree. A joint missing both is one finding; one source line written for several joints (a macro) "
            "is one finding naming the others."
        ),
    )
)

WORLD_LINK = register(
    Rule(
        code="GC113",
        name="undeclared-world-link",
        severity=Severity.WARNING,
        summary="A joint's parent is the undeclared link 'world' (a convention urdfdom no longer accepts).",
        what=(
            "Reports joints that attach the robot to a 'world' link that is not declared as a <link>. "
            "geomcheck takes it as the fixed world frame and checks the robot as attached to it. "
            "Severity: a warning, the policy for what some tools accept and others refuse (as GC202's "
            "three-slash URIs): the boxturtle URDF parser (ROS until 2010) added the undeclared link, "
            "which is why older descriptions rely on it; current urdfdom refuses any joint to an "
            "undeclared link. (MoveIt's virtual joint to a `world` frame is declared in the SRDF and "
            "needs no URDF link: it is not this case.)"
        ),
        why=(
            "robot_state_publisher, MoveIt, Gazebo's URDF import and every other urdfdom-based tool refuse "
            "the robot with 'parent link [world] of joint [...] not found'; declaring <link name=\"world\"/> "
            "satisfies every tool."
        ),
        example='<joint name="base_joint" type="planar">\n  <parent link="world"/>   <!-- GC113 -->',
        fix='Declare <link name="world"/>, or remove the joint if the robot is not fixed to the world.',
        metrics=(
            Metric("role", "text", description="parent or child."),
            Metric("link", "text", description="The undeclared link name."),
            ALSO,
        ),
        severity_reason=(
            "Warning, not error, although current urdfdom refuses the robot: the declaration is one line and the "
            "convention was valid for the boxturtle parser the description was written for; a maintainer adds "
            '<link name="world"/>.'
        ),
    )
)

NO_ROOT = register(
    Rule(
        code="GC114",
        name="no-root-link",
        severity=Severity.ERROR,
        summary="The robot has no links, or every link is the child of a joint (no root).",
        what="Checks that the kinematic tree has a root link.",
        why="Without a root there is no base frame; URDF parsers refuse the robot.",
        example="<robot name='r'/>   <!-- GC114: no links -->",
        fix="Declare the links; break the cycle that makes every link a child.",
        metrics=(ACCEPTED_BY, ALSO),
        severity_reason=(
            "Error: urdfdom cannot find a root link and refuses the robot. libsdformat loads an SDFormat model "
            "whose links all hang from joints (a kinematic loop: accepted_by), but gz-physics (dartsim) refuses "
            "the joint that closes it. Never lowered."
        ),
    )
)

MULTIPLE_ROOTS = register(
    Rule(
        code="GC115",
        name="multiple-root-links",
        severity=Severity.ERROR,
        summary="Several links are no joint's child: the robot is several disconnected trees.",
        what="Lists the root links found; the first one in document order is taken as the robot's root.",
        why="urdfdom refuses a robot with several roots; links outside the main tree have no pose.",
        example='<link name="base"/>\n<link name="camera"/>   <!-- GC115: camera is not attached -->',
        fix="Attach each extra root with a joint (usually fixed) to a link of the main tree.",
        metrics=(
            Metric("roots", "text", description="The root links (the first few)."),
            Metric("root_count", "count", description="How many root links there are."),
            Metric("main_root", "text", description="The root of the largest tree."),
            Metric("subtree_links", "count", description="The links in this root's tree."),
            ACCEPTED_BY,
            ALSO,
        ),
        severity_reason=(
            "Error on URDF: urdfdom refuses a robot with several root links ('two root links found'). Info on "
            "SDFormat: libsdformat loads links and nested models without joints as free bodies, which is what "
            "Gazebo simulates (each moves on its own), so the file is valid and the finding says so "
            "(accepted_by). A root joined by a joint written backwards is GC117's finding instead."
        ),
    )
)

CYCLE = register(
    Rule(
        code="GC116",
        name="kinematic-cycle",
        severity=Severity.ERROR,
        summary="Joints form a closed loop (a link is its own ancestor).",
        what="Follows parent joints from every link and reports each loop once, with the links on it.",
        why="URDF describes trees only; closed chains cannot be expressed and make parsers fail.",
        example=(
            '<joint name="a" type="fixed"><parent link="l1"/><child link="l2"/></joint>\n'
            '<joint name="b" type="fixed"><parent link="l2"/><child link="l1"/></joint>'
        ),
        fix="Remove one joint of the loop; model closed chains with mimic joints or in the controller.",
        metrics=(Metric("links", "text", description="The links of the loop."), JOINTS, ACCEPTED_BY, ALSO),
        severity_reason=(
            "Error: a closed loop has no root and no tree; urdfdom refuses it. libsdformat loads an SDFormat "
            "loop (accepted_by), but gz-physics (dartsim, Gazebo's default engine) refuses the joint that closes "
            "it and the part it holds is simulated loose. Never lowered."
        ),
    )
)

MULTIPLE_PARENTS = register(
    Rule(
        code="GC117",
        name="multiple-parent-joints",
        severity=Severity.ERROR,
        summary="A link is the child of more than one joint.",
        what=(
            "Reports links that appear as <child> of several joints, naming the joints. A joint whose parent "
            "lies in another tree than the link (the root of a tree no joint attaches: a sensor model joined by "
            "parent=sensor, child=rack) is named as written the wrong way round, with the swap that makes one "
            "tree; that tree's root is then not also a GC115."
        ),
        why=(
            "In a tree each link has exactly one parent joint. urdfdom loads the robot but KDL (kdl_parser, "
            "robot_state_publisher) refuses it, adding the link twice; libsdformat loads it and Gazebo's default "
            "physics engine (gz-physics dartsim) refuses the second joint: the part it should hold falls free."
        ),
        example='two joints with <child link="gripper"/>   <!-- GC117 -->',
        fix=(
            "Keep one parent joint; give the other joint its own child link, or swap a reversed joint's parent "
            "and child."
        ),
        metrics=(
            JOINTS,
            Metric("reversed", "text", description="The joints joining another tree to the link, written backwards."),
            ACCEPTED_BY,
            ALSO,
        ),
        severity_reason=(
            "Error, though both parsers load the file (accepted_by): urdfdom keeps the link's last parent and "
            "lists the link twice among its parent's children, so KDL (robot_state_publisher) refuses the robot "
            "('Failed to add segment'); libsdformat allows it and gz-physics (dartsim, Gazebo's default engine) "
            "refuses the joint whose child already has a parent ('the child link already has a parent joint'): "
            "the part it should attach is simulated loose. Never lowered."
        ),
    )
)
