"""GC410-GC419: the collision matrix against a MoveIt SRDF (``check --srdf FILE``)."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register

REASON = Metric("reason", "text", description="The reason the SRDF gives for disabling the pair.")
CLASS = Metric("class", "text", description="The pair's class in the collision matrix.")
DEPTH = Metric("depth", "m", "lower", "How deep the pair's shapes overlap.")
DEPTH_MM = Metric("depth_mm", "mm", "lower", "The same in millimetres.")
TESTED = Metric("tested", "count", description="The random configurations sampled for the pair.")

DISABLED_PAIR_CAN_COLLIDE = register(
    Rule(
        code="GC410",
        name="srdf-disabled-pair-can-collide",
        severity=Severity.ERROR,
        summary="An SRDF disables collision checking for a pair of links that can collide",
        what=(
            "Compares every pair the SRDF disables (`<disable_collisions>`, or "
            "`<disable_default_collisions>` without a matching `<enable_collisions>`) with the "
            "collision matrix. A pair that is not adjacent, not in collision at the default pose "
            "and not always in collision, but collides in some sampled configuration or in one "
            "found by the witness search, is reported with that configuration and the depth."
        ),
        why=(
            "MoveIt never checks a disabled pair: a planner will happily drive the robot through "
            "that collision. The Setup Assistant marks pairs 'Never' when random samples missed "
            "them, so pairs that collide in a small part of joint space are disabled by mistake "
            "(moveit/moveit#3526, panda_moveit_config#35)."
        ),
        example=(
            '<disable_collisions link1="panda_link5" link2="panda_hand" reason="Never"/>\n'
            "while the hand reaches link5 at panda_joint6=0.1 with 4 mm of penetration"
        ),
        fix=(
            "Delete the `<disable_collisions>` element for this pair (regenerate the list with "
            "`geomcheck matrix PATH --srdf-out FILE`), so that MoveIt checks it."
        ),
        severity_reason=(
            "An error: MoveIt never checks a disabled pair, so a planner drives the robot through the "
            "collision; the configuration given is within the joint limits, found by sampling or by the "
            "witness search, and its depth is the overlap of the collision shapes there. Info when the SRDF "
            "checks the two links' bodies through other links fixed to them (proxy links such as Franka's "
            "capsule `*_sc` links) whose enabled pair collides at that same configuration: the SRDF disables "
            "the pair on purpose and no contact is lost."
        ),
        metrics=(
            Metric(
                "checked_through",
                "text",
                description="The enabled pair of links fixed to the same bodies that collides there too, or null.",
            ),
            REASON,
            CLASS,
            TESTED,
            Metric(
                "configuration",
                "SI",
                description="A configuration in which the pair collides: joint values [rad or m], by joint name.",
                optional=True,
            ),
            Metric(
                "depth", "m", "lower", "How deep the pair overlaps there. Only with a configuration.", optional=True
            ),
            Metric("depth_mm", "mm", "lower", "The same in millimetres. Only with a configuration.", optional=True),
            Metric(
                "source",
                "text",
                description="How the configuration was found. Only with a configuration.",
                optional=True,
            ),
        ),
    )
)

UNKNOWN_LINK = register(
    Rule(
        code="GC411",
        name="srdf-unknown-link",
        severity=Severity.WARNING,
        summary="An SRDF collision entry names a link the robot does not have",
        what=(
            "Checks that every link named by `<disable_collisions>`, `<enable_collisions>` and "
            "`<disable_default_collisions>` is a link of the URDF, and suggests a close name. Names close to "
            "no link of the robot are reported together, once per SRDF."
        ),
        why=(
            "An entry for an unknown link does nothing: the pair it was meant to disable stays "
            "enabled (or the other way round), usually after a link was renamed."
        ),
        example='<disable_collisions link1="panda_link8" link2="panda_hnad" reason="Adjacent"/>',
        fix="Rename the link to the one the URDF uses, or delete the entry.",
        severity_reason=(
            "A warning for a name close to one of the robot's links (a typo or a rename): the pair it "
            "meant stays checked or unchecked. Names that resemble no link are the links of another variant "
            "the SRDF also serves (MoveIt's srdfdom skips such entries with a warning, pinocchio ignores "
            "them): one info finding per SRDF, as the audit of the robot's own pairs reports what it lacks."
        ),
        metrics=(
            Metric("element", "text", description="The SRDF element naming the link."),
            Metric("unknown_link", "text", description="The link name the robot does not have."),
        ),
    )
)

ENABLED_PAIR_ALWAYS_COLLIDING = register(
    Rule(
        code="GC412",
        name="srdf-enabled-pair-always-colliding",
        severity=Severity.WARNING,
        summary="An SRDF leaves enabled a pair of links that is in collision almost everywhere",
        what=(
            "Reports pairs the SRDF does not disable that are in collision in at least the "
            "`always_fraction` of the sampled configurations (95 % by default)."
        ),
        why=(
            "MoveIt will find these links in collision in nearly every state, so planning and "
            "state validation fail; such pairs are usually overlapping collision shapes."
        ),
        example="base_link and a caster housing whose collision meshes overlap by 1 cm everywhere",
        fix=(
            'Disable the pair (`<disable_collisions link1="LINK1" link2="LINK2" reason="Always"/>`), '
            "or better, fix the collision shapes so that they do not overlap."
        ),
        severity_reason=(
            "A warning: the pair stays checked, so nothing collides unseen, but MoveIt reports the robot "
            "in collision in nearly every state until a maintainer disables the pair or fixes the shapes."
        ),
        metrics=(
            Metric("fraction", "1", "lower", "Share of the sampled configurations in which the pair collides."),
            TESTED,
        ),
    )
)

ENABLED_ADJACENT_IN_CONTACT = register(
    Rule(
        code="GC413",
        name="srdf-enabled-adjacent-in-contact",
        severity=Severity.WARNING,
        summary="An SRDF leaves enabled a pair of adjacent or rigidly attached links that touch at the default pose",
        what=(
            "Reports adjacent links (parent and child with geometry, or joined only through links "
            "without geometry) and rigidly attached links (only fixed joints between them, so in "
            "contact in every pose) that the SRDF does not disable and that are in collision at the "
            "default pose; the help gives the line to add, with the reason the Setup Assistant would "
            "write (Adjacent, or Default for a rigidly attached pair that is not adjacent). Other pairs "
            "in contact at the default pose are GC403."
        ),
        why=(
            "Adjacent links usually touch at their joint; MoveIt then sees the robot in "
            "collision from the start and every plan fails."
        ),
        example="an SRDF without the Adjacent entry for panda_link3 / panda_link4",
        fix='Disable the pair: `<disable_collisions link1="LINK1" link2="LINK2" reason="Adjacent"/>`.',
        severity_reason=(
            "A warning: MoveIt (and pinocchio, which checks every pair the SRDF keeps) finds the robot in "
            "collision at the default pose until the line is added. Info for links joined only by fixed "
            "joints when the SRDF is written for pinocchio (its named poses set a 7-value free-flyer that no "
            "<virtual_joint> declares): pinocchio makes them one body and never collides it with itself."
        ),
        metrics=(
            DEPTH,
            DEPTH_MM,
            Metric("fixed_joints", "text", description="The fixed joints joining the pair, when only they do."),
        ),
    )
)

REASON_MISMATCH = register(
    Rule(
        code="GC414",
        name="srdf-reason-mismatch",
        severity=Severity.INFO,
        summary="An SRDF disables a pair for a different reason than the collision matrix finds",
        what=(
            "For pairs that both the SRDF and the matrix disable, compares the SRDF `reason` with "
            "the class found here (Adjacent, Default, Always, Never)."
        ),
        why=(
            "The pair stays disabled either way, but a different reason shows that the SRDF was "
            "made for another version of the robot or another default pose."
        ),
        example='<disable_collisions link1="a" link2="b" reason="Adjacent"/> for links two joints apart',
        fix="Regenerate the list with `geomcheck matrix PATH --srdf-out FILE` if the robot changed.",
        severity_reason="Info: the pair stays disabled whatever the reason says; only the SRDF's history shows.",
        metrics=(REASON, CLASS),
    )
)

UNKNOWN_JOINT = register(
    Rule(
        code="GC415",
        name="srdf-unknown-joint",
        severity=Severity.WARNING,
        summary="An SRDF named pose sets a joint the robot does not have",
        what=(
            "Checks that every joint of every `<group_state>` is a joint of the URDF or a "
            "`<virtual_joint>` of the SRDF. Names that misspell no joint the pose leaves unset are "
            "reported together, once per SRDF."
        ),
        why="MoveIt rejects or ignores the value, so the named pose is not the pose intended.",
        example='<group_state name="home" group="arm"><joint name="elbow_jiont" value="1.2"/></group_state>',
        fix="Rename the joint to the one the URDF uses, or delete it from the pose.",
        severity_reason=(
            "A warning for a name close to a joint the pose does not already set (a typo or a rename): "
            "MoveIt and pinocchio skip the value and the named pose is not the one intended. Other unknown "
            "names (another variant's joints, pinocchio's free-flyer 'root_joint') are skipped while the "
            "pose's other values apply: one info finding per SRDF."
        ),
        metrics=(
            Metric("group_state", "text", description="The group state that sets the joint."),
            Metric("unknown_joint", "text", description="The joint name the robot does not have."),
        ),
    )
)

ROBOT_NAME_MISMATCH = register(
    Rule(
        code="GC416",
        name="srdf-robot-name-mismatch",
        severity=Severity.WARNING,
        summary="The SRDF is written for a robot of another name",
        what="Compares the `name` of the SRDF's `<robot>` with the URDF's.",
        why=(
            "MoveIt reports 'Semantic description is not specified for the same robot as the URDF'; "
            "usually the wrong file was given."
        ),
        example='URDF <robot name="panda">, SRDF <robot name="fr3">',
        fix="Use the SRDF made for this robot, or correct its robot name.",
        severity_reason=(
            "A warning: MoveIt logs that the semantic description is not for the same robot and goes on; "
            "usually the wrong file was given, which a maintainer corrects."
        ),
        metrics=(
            Metric("srdf_robot", "text", description="The robot name the SRDF is written for."),
            Metric("urdf_robot", "text", description="The description's robot name."),
        ),
    )
)
