"""GC1xx: syntax and structure of the description (XML, xacro, URDF elements, kinematic tree)."""

from __future__ import annotations

from dataclasses import replace

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register

ALSO = Metric(
    "also",
    "text",
    description="The other subjects the same source line wrote, when a macro wrote it for several.",
    optional=True,
)
ELEMENT = Metric("element", "text", description="The URDF element.")
ATTRIBUTE = Metric("attribute", "text", description="The attribute.")
SUGGESTION = Metric("suggestion", "text", description="The closest known name, or null.")
FIRST = Metric("first", "text", description="Where the name was first used.")
JOINTS = Metric("joints", "text", description="The joints concerned.")
ACCEPTED_BY = Metric(
    "accepted_by",
    "text",
    description=(
        "The format's own parser that loads the file as written (urdfdom, libsdformat): the finding is "
        "geomcheck's judgement of what a consumer does with it, not a refusal of the file."
    ),
    optional=True,
)
AXIS: tuple[Metric, ...] = (
    Metric("axis", "1", description="The axis as written."),
    Metric("norm", "1", description="Its length."),
)

XACRO_NS = "http://www.ros.org/wiki/xacro"

MALFORMED_XML = register(
    Rule(
        code="GC101",
        name="malformed-xml",
        severity=Severity.ERROR,
        summary="A file of the description is not well-formed XML, or is refused by the hardened parser.",
        what=(
            "Reports a file that cannot be parsed: a syntax error (unclosed tag, bad attribute quoting, "
            "undeclared namespace prefix), a DOCTYPE that declares entities, nesting deeper than the "
            "configured limit. The check stops: nothing else can be said about the robot."
        ),
        why=(
            "ROS tools (xacro, robot_state_publisher, MoveIt) refuse the same file. Entity declarations "
            "are refused because they are how XML bombs (billion laughs) and external-entity reads work."
        ),
        example='<link name="base_link">\n  <visual>\n</link>   <!-- GC101: mismatched tag -->',
        fix="Fix the XML at the given line and column; remove any <!DOCTYPE> with <!ENTITY> declarations.",
        severity_reason=(
            "Error: xacro, urdfdom and every ROS tool refuse a file that is not well-formed XML; geomcheck cannot "
            "go on either. Never lowered."
        ),
    )
)

XACRO_ERROR = register(
    Rule(
        code="GC102",
        name="xacro-error",
        severity=Severity.ERROR,
        summary="xacro failed to expand the description (undefined property, unknown macro, bad include).",
        what=(
            "Runs the real xacro expander (in process, no ROS install) and reports its error message with "
            "the file and line where the failing expression, macro call or include was found."
        ),
        why="The description cannot be turned into URDF, so no ROS tool can load it.",
        example='<xacro:property name="r" value="0.1"/>\n<cylinder radius="${radius}" length="1"/>  <!-- GC102 -->',
        fix="Define the property, macro or argument, or fix the include path; pass arguments with --arg NAME=VALUE.",
        metrics=(Metric("macros", "text", description="The macro calls being expanded, outermost first."),),
        severity_reason=("Error: xacro stops and produces no URDF, so no consumer can load the robot. Never lowered."),
    )
)

LEGACY_XACRO = register(
    Rule(
        code="GC103",
        name="legacy-xacro-syntax",
        severity=Severity.WARNING,
        summary="A file uses pre-2013 xacro syntax: bare <property>, <include>, <macro>, <insert_block>...",
        what=(
            "Reports, once per file, the xacro tags written without the xacro: prefix (<property>, "
            "<include>, <macro>, <insert_block>, <arg>, <if>, <unless>, <call>, bare macro calls) and a "
            "missing or wrong xmlns:xacro declaration. geomcheck rewrites them in memory and goes on. Severity by what "
            "xacro does with the file: see severity_reason."
        ),
        why=(
            "ROS 2 xacro no longer understands the bare tags (ROS 1 xacro accepted them with a deprecation "
            "warning): it copies them into the URDF unexpanded, so the robot silently loses its includes and macros."
        ),
        example=(
            '<robot name="pr2">\n  <include filename="$(find pr2_description)/urdf/common.xacro"/>\n'
            '  <property name="M_PI" value="3.1415926535897931"/>'
        ),
        fix=f'Prefix the tags with xacro: and declare xmlns:xacro="{XACRO_NS}" on the root element.',
        metrics=(
            Metric("file", "text", description="The file using the legacy syntax."),
            Metric("tags", "object", description="Each legacy tag used, and how many times."),
            Metric("namespace", "text", description="What the file declares as the xacro namespace, or null."),
        ),
        severity_reason=(
            "By what xacro does with the file (it matches its instructions by the xacro: prefix of the tag name, "
            "never by the namespace URI): a xacro: prefix without its xmlns:xacro declaration makes xacro's "
            "namespace-aware XML parser refuse the file (error); bare <property>/<include>/<macro>/<insert_block> "
            "tags were accepted by ROS 1 xacro with a deprecation warning and are copied unexpanded by ROS 2 "
            "xacro, which a maintainer modernises (warning), unless they all lie in macros this robot never calls "
            "(they cannot reach its URDF: info); a wrong or old namespace URI on a file that expands as it is is "
            "dead markup (info)."
        ),
    )
)

XACRO_WARNING = register(
    Rule(
        code="GC104",
        name="xacro-warning",
        severity=Severity.WARNING,
        summary="xacro warned while expanding (unknown attribute on a xacro tag, redefined symbol...).",
        what="Reports the warnings that the xacro expander prints, with the file being processed.",
        why="xacro warnings usually point at a typo or at a construct that newer xacro versions reject.",
        example='<xacro:include filename="arm.xacro" nss="arm"/>   <!-- GC104: unknown attribute(s): nss -->',
        fix="Fix what the xacro message names.",
        metrics=(Metric("file", "text", description="The file xacro warned about."),),
        severity_reason=(
            "Warning: xacro expanded the file but printed a warning, which names a construct the maintainer would "
            "fix (a typo, an attribute newer xacro rejects)."
        ),
    )
)

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
            "without lower and upper: urdfdom, MoveIt and pinocchio read the range as [0, 0] and the joint cannot "
            "move, which the maintainer fixes; bounds written as SDFormat's 1e16 'no limit' are not missing."
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
            "reads them on; there, 1e16 and beyond is SDFormat's 'no limit' (Gazebo reads the joint as unlimited): "
            "reported as info, and the side taken as unbounded."
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
            "limit' magnitude (1e16 and beyond, which Gazebo reads as unlimited) is info, and that side is taken "
            "as unbounded."
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
