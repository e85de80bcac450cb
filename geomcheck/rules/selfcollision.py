"""GC401-GC409: self-collision of the moving robot (continuous-joint sweep, default pose)."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register

# the data of a finding of the sweep of one joint
SWEPT: tuple[Metric, ...] = (
    Metric("joint", "text", description="The joint swept."),
    Metric("moving_link", "text", description="The link of the pair that the joint moves."),
    Metric("min_clearance", "m", "higher", "The smallest distance between the pair over the turn (negative: depth)."),
    Metric("min_clearance_mm", "mm", "higher", "The same in millimetres."),
    Metric("angle_deg", "deg", description="The joint angle of the smallest clearance."),
)

SWEEP_COLLISION = register(
    Rule(
        code="GC401",
        name="sweep-collision",
        severity=Severity.ERROR,
        summary="A link turned by a continuous joint hits a non-adjacent link somewhere in its turn.",
        what=(
            "Turns every continuous joint (caster rotation, wheel spin, spinning sensor) over a full turn, "
            "together with the continuous joints directly below it (a caster's wheels), the rest of the "
            "robot at the default pose, and tests every moving link against every link whose pose relative "
            "to it changes. For a pair MoveIt calls Adjacent (parent and child, or joined only through links "
            "without geometry: a caster housing and the base), only a contact that depends on the angle is "
            "reported; one over the whole turn is the joint's own overlap. The search is exhaustive, not "
            "sampled: between two distance queries "
            "no point moves faster than its distance from the axis per radian, so every angle is either "
            "proven clear or shown in contact (distance at or below contact_tolerance_m). The finding names "
            "the pair, the angle ranges in contact and the largest penetration depth. A pair also in "
            "collision at the default pose is reported by GC403 as well. A turn that brings several pairs into "
            "contact is one cause (most often a joint that cannot turn a full turn: a leg's hip written "
            "continuous), reported once, on its deepest contact, naming the other pairs (each of them info, "
            "saying so), with the joint's range as the first fix."
        ),
        why=(
            "A caster housing that clips the base at one steering angle makes the robot report itself in "
            "collision (MoveIt refuses to plan, safety monitors stop it) only when the caster happens to "
            "turn there: a fault that sampling and default-pose checks miss and that shows up in the field."
        ),
        example=(
            '<joint name="fl_caster_rotation_joint" type="continuous"> ... <origin xyz="0.2225 0.2225 0.03"/>\n'
            "fl_caster_rotation_link touches base_link while fl_caster_rotation_joint turns: in contact from "
            "35.0° to 55.0°, deepest 4.1 mm at 45.0°"
        ),
        fix=(
            "Make the collision geometry match the real parts (shrink or move the two links' collision shapes "
            "so they clear over the whole turn: a caster's or the base's), or correct the joint origin."
        ),
        metrics=(
            *SWEPT,
            Metric("max_depth", "m", "lower", "The deepest penetration over the turn."),
            Metric("max_depth_mm", "mm", "lower", "The same in millimetres."),
            Metric(
                "hull_depth_mm",
                "mm",
                description="The convex hulls' depth there: the sweep's measure; for meshes the depth given is the "
                "one at which their triangles part, at most this.",
            ),
            Metric("ranges_deg", "deg", description="The joint ranges [lower, upper] in which the pair is in contact."),
            Metric(
                "proven",
                "bool",
                description="False when the search stopped at its query budget: more contact may lie outside "
                "the ranges (no separate GC404 is then reported for the pair). Only then.",
                optional=True,
            ),
            Metric("queries", "count", description="The distance queries spent on the pair. Only then.", optional=True),
            Metric(
                "also_pairs",
                "text",
                description="The other pairs the same turn brings into contact, when there are.",
                optional=True,
            ),
        ),
        severity_reason=(
            "An error when only the swept joints move the pair (a caster housing against the base's post, "
            "a wheel against another caster): the contact comes whenever the freely turning joint gets "
            "there, and MoveIt reports the robot in collision. Info for MoveIt's Adjacent pairs, which the "
            "Setup Assistant, Gazebo and MuJoCo never collide: no consumer meets the contact; info when "
            "limited (revolute or prismatic) joints between the two links, held at the default pose by the "
            "sweep, move them apart: an ordinary self-collision of some poses of an arm or a leg, which "
            "MoveIt checks and plans around; info too when a shift of contact_tolerance_m parts the "
            "deepest contact (faces meeting flush, whatever the depth of the convex hulls)."
        ),
    )
)

SWEEP_CLEARANCE = register(
    Rule(
        code="GC402",
        name="sweep-low-clearance",
        severity=Severity.INFO,
        summary="A link turned by a continuous joint passes a non-adjacent link closer than the clearance margin.",
        what=(
            "Same sweep as GC401; reports a pair that never touches but whose smallest clearance over the "
            "turn is below clearance_margin_m, with that clearance in millimetres and the angle where it "
            "occurs. The clearance is proven: no angle of the turn comes closer than the reported value "
            "minus sweep_clearance_resolution_m. An Adjacent pair is reported only when its clearance is at "
            "least the margin at some other angle (a parent and child sitting uniformly close is by design)."
        ),
        why=(
            "Collision shapes approximate the real parts; a clearance of a millimetre or two in the model "
            "is within modelling error, and a padding a user gives the planner (MoveIt's link padding, "
            "0 by default) turns it into a collision."
        ),
        example=(
            "fl_caster_l_wheel_link passes base_link with 1.2 mm clearance at -90.0° "
            "while fl_caster_rotation_joint turns"
        ),
        fix="Check the real clearance; give the parts more room in the model, or lower clearance_margin_m.",
        metrics=(*SWEPT, Metric("margin_mm", "mm", description="The clearance margin the pair should keep.")),
        severity_reason=(
            "Info: the links never touch, and no consumer sees a clearance (MoveIt's default link padding "
            "is 0, Gazebo and MuJoCo collide only on contact); a few millimetres between modelled parts is "
            "worth knowing when the real parts are larger than their shapes, not a defect."
        ),
    )
)

DEFAULT_POSE_COLLISION = register(
    Rule(
        code="GC403",
        name="default-pose-collision",
        severity=Severity.ERROR,
        summary="Two non-adjacent links are in collision at the default pose.",
        what=(
            "Places the robot at its default pose (every joint at 0, or mid-range where 0 is outside the "
            "limits; or the values given with --pose JOINT=VALUE, or the SRDF group_state named with "
            "--pose-name) and reports every pair of non-adjacent links whose collision shapes intersect, "
            "with the penetration depth (for meshes, the depth of their convex hulls). Pairs that the SRDF "
            "given with --srdf disables are not reported: MoveIt never checks them. Nor are pairs whose "
            "relative pose no joint changes (only fixed joints on the tree path between them, such as a "
            "camera frame's placeholder box inside the head it is fixed to): they overlap in every "
            "configuration, which is not a property of the default pose. MoveIt's Setup Assistant disables "
            "them (Adjacent or Default), pinocchio and Gazebo merge links joined by fixed joints into one "
            "body; the collision matrix (--matrix) lists them as Default, and with --srdf an SRDF that "
            "leaves one enabled is reported (GC413). Each pair is then collided in default_pose_samples "
            "poses drawn within the limits of the joints between its links (mimic joints following their "
            "leaders), which tells a pose-dependent collision from an overlap by design."
        ),
        why=(
            "A robot in collision at its zero or home pose is in collision whenever it starts: MoveIt "
            "refuses to plan from it and simulators push the links apart. It usually means a shape was "
            "placed in the wrong frame or a mesh was exported with the wrong origin or units."
        ),
        example="torso_lift_link and base_link are in collision at the default pose: 12.0 mm deep",
        fix=(
            "Fix the collision geometry or the joint origin; if the contact is intended (parts that touch "
            'by design), disable the pair in the SRDF with reason="Default".'
        ),
        metrics=(
            Metric(
                "hull_depth_mm",
                "mm",
                description="The depth of the shapes' convex hulls; the depth given is where meshes part.",
                optional=True,
            ),
            Metric("depth", "m", "lower", "How deep the pair's shapes overlap."),
            Metric("depth_mm", "mm", "lower", "The same in millimetres."),
            Metric("pose", "text", description="The pose checked: the default one, or the one named with its values."),
            Metric(
                "collisions",
                "count",
                "lower",
                "In how many sampled poses of the joints between the two links they also collide.",
            ),
            Metric("tested", "count", description="The poses of the joints between the two links sampled."),
            Metric("srdf_line", "text", description="The SRDF element that disables the pair (reason Default)."),
        ),
        severity_reason=(
            "An error when the pair collides at the default pose but not in most other poses of the joints "
            "between its links: MoveIt starts in collision and refuses to plan, and the Setup Assistant's "
            "Default entry that silences it also hides the pair's collisions in the other poses. Info, with "
            "the SRDF line to add, when the shapes only touch (a shift of contact_tolerance_m along a world "
            "axis parts them: closed gripper fingers, mated faces) or collide in at least always_fraction "
            "of the sampled poses (a four-bar linkage at its pin, a telescoping column, a shell around a "
            "joint): an overlap by design that "
            "the Setup Assistant disables and no planner could avoid; info too when meshes graze, parting after "
            "a shift of at most mesh_graze_m (1.5 mm) where their convex hulls overlap deeper: facets of "
            "neighbouring CAD parts touching, which no maintainer edits. Info too when the two links' visual "
            "meshes (the parts as drawn) overlap there by more than mesh_graze_m with every joint between them "
            "inside its range: the parts themselves collide, so the pose is one the robot cannot take (an arm "
            "folded onto itself at zero), and the help says to check it in a pose it can take rather than "
            "disable the pair. With a joint between them at a limit it stays an error, and the message says "
            "the limit lets the parts meet: a limit past the part's stop is the description's own error. "
            "Info too when the parts as drawn are apart there, the pose puts joints between them at a limit, and "
            "with those joints moved stop_probe_fraction (5%) of their range off it the collision shapes part: "
            "padded collision geometry meeting at the joint's stop (a lift at its bottom, an arm retracted), "
            "which the parts themselves clear. Info too when the parts as drawn are apart there, only "
            "prismatic joints along one direction move the two links, and one is drawn within the other's "
            "convex hull (nested_share, half its surface): nested sections of a telescope, whose solid "
            "collision shapes fill the hollow the other slides in. "
            "The depth given for meshes is the "
            "shift along a world axis that parts their triangles, as MoveIt and Gazebo collide them, not the "
            "overlap of their convex hulls, which overstates it for hollow and concave parts."
        ),
    )
)

SWEEP_UNPROVEN = register(
    Rule(
        code="GC404",
        name="sweep-unproven",
        severity=Severity.WARNING,
        summary="The sweep could not decide a pair over the whole turn within its query budget.",
        what=(
            "Reports a pair for which the continuous-joint sweep ran out of distance queries "
            "(sweep_max_queries) before every angle was proven clear or shown in contact; the smallest "
            "clearance found so far is given. This happens with grazing contacts along a long arc, and on a "
            "robot with many continuous joints whose sweeps share the check's budget "
            "(sweep_max_queries_total, 1000000, a query between meshes counting sweep_mesh_query_weight, 10): "
            "each pair then gets an even share of what is left, and the joints reached after it is spent are not "
            "swept (the report's skipped checks name them). A pair found in contact is GC401's, which then says "
            "its ranges may be incomplete, not a second finding here."
        ),
        why="An unproven pair may still collide at an angle that was not resolved.",
        example=(
            "the sweep of fl_caster_rotation_joint could not decide fl_caster_rotation_link / base_link "
            "within 20000 distance queries"
        ),
        fix="Raise sweep_max_queries, or give the two parts a clear gap (or a clear overlap) in the model.",
        metrics=(
            *SWEPT,
            Metric("queries", "count", description="The distance queries spent on the pair."),
            Metric("budget_shared", "bool", description="Whether the check's shared budget cut the pair's own."),
        ),
        severity_reason=(
            "A warning: the parts graze each other along a long arc, within the sweep's resolution of "
            "touching; a maintainer would give them a clear gap (or a clear overlap) so the model says which. "
            "Info when the smallest clearance found is beyond clearance_margin_m (5 mm): the search ran out far "
            "from contact (a two-joint sweep whose bound is loose), not at a graze. Info too when the check's "
            "budget, shared by many continuous joints (a legged robot whose every joint is "
            "continuous), cut the pair's own: the search was cut short, not held at a graze, and nothing in the "
            "file is shown to need a change."
        ),
    )
)
