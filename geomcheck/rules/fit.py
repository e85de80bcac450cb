"""GC3xx: collision geometry against the link's visual geometry."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, optional, register

# The data of a fitted element's finding (ElementFit.to_dict and what classify adds).
ELEMENT = Metric("element", "text", description="The element's type: box, cylinder, sphere or mesh.")
MULTI = Metric("multi", "bool", description="Whether the link has several collision elements.")
TOLERANCE = Metric(
    "tolerance", "m", description="How far the mesh may stick out: the protrusion tolerance at the part's size."
)
DISJOINT = Metric("disjoint", "bool", description="Away from the mesh (true) or misplaced on it (false).")
HELD_BY = Metric(
    "held_by",
    "text",
    description="The link whose collision geometry holds this link's mesh, rigidly or at every position of the "
    "joint between them (then info). Only then.",
    optional=True,
)

FITTED: tuple[Metric, ...] = (
    ELEMENT,
    MULTI,
    TOLERANCE,
    Metric("coverage", "1", "higher", "Share of the mesh's surface inside the element or within the tolerance."),
    Metric("protrusion_max_mm", "mm", "lower", "How far the mesh sticks out of the element, at most."),
    Metric("protrusion_p95_mm", "mm", "lower", "95th percentile of how far the mesh sticks out."),
    Metric(
        "gaps_mm",
        "mm",
        description="Per side (x-, x+, ..., radial), the element's reach past the mesh; negative: the mesh sticks out.",
    ),
    Metric("slack", "1", "lower", "The element's volume over the volume of the mesh's convex hull."),
    Metric("primitive_volume", "m^3", description="The element's volume."),
    Metric(
        "hull_volume",
        "m^3",
        description=(
            "The volume of the convex hull of the mesh's part and of the mesh the element holds that a nearer "
            "element owns."
        ),
    ),
    Metric("mesh_inside", "1", "higher", "Share of the mesh within the tolerance of the element."),
    Metric("in_hull", "1", "higher", "Share of the element inside the mesh's convex hull (null: not measured)."),
    Metric("part_points", "count", description="Mesh points the element answers for."),
    Metric("offset_mm", "mm", description="The move (x, y, z) centring the element on its part of the mesh, or null."),
    Metric("fits_when_moved", "bool", description="Whether the element, so moved, would enclose its part."),
    Metric(
        "axis_alternative",
        "object",
        description="The cylinder turned onto the mesh's axis (axis, axis_name, rpy [rad], coverage, "
        "protrusion_max_mm), or null.",
    ),
    Metric("suggested", "object", description="A primitive of the element's type fitted to the mesh, or null."),
    Metric("capsule_cap", "bool", description="Whether the element is a sphere closing a capsule of the link."),
    Metric("covers_neighbour", "text", description="The neighbour whose mesh the element lies on, or null."),
    Metric("part_note", "text", description="Which part of the mesh the element answers for, or null."),
)
# a collision mesh compared with the visual geometry both ways (GeometryComparison)
COMPARED: tuple[Metric, ...] = (
    Metric(
        "reverse_coverage",
        "1",
        "higher",
        "Share of the collision surface inside the visual's hull or within tolerance.",
    ),
    Metric("overshoot_max_mm", "mm", "lower", "How far the collision mesh reaches out of the visual's hull, at most."),
    Metric("overshoot_p95_mm", "mm", "lower", "95th percentile of how far the collision mesh reaches out."),
    Metric("surface_distance_max_mm", "mm", "lower", "Largest distance between the two surfaces, both ways."),
    Metric("surface_distance_p95_mm", "mm", "lower", "95th percentile of the distances between the two surfaces."),
)
# GC303 for an element lying on a neighbour's mesh
LENT: tuple[Metric, ...] = (
    Metric("outside_own_mesh", "1", "lower", "Share of the element outside the convex hull of its link's own mesh."),
    Metric("link_coverage", "1", "higher", "Share of the link's mesh covered by its collision geometry."),
    Metric("link_protrusion_max_mm", "mm", "lower", "How far the link's mesh sticks out of its collision geometry."),
)


COLLISION_DOES_NOT_COVER = register(
    Rule(
        code="GC301",
        name="collision-does-not-cover-mesh",
        severity=Severity.WARNING,
        summary="The visual mesh sticks out of its collision primitive beyond the tolerance.",
        what=(
            "Brings the link's visual geometry into each collision element's frame and measures, on "
            "area-weighted surface samples and the vertices, how far the mesh sticks out (largest and "
            "95th percentile, exact distances) and which share of its surface is covered (inside, or "
            "within `protrusion_tolerance_m`, 10 mm). Reported when the mesh sticks out more than the "
            "tolerance or coverage is below `min_coverage` (90%); an error when less than "
            "`gross_coverage` (50%) is covered. With several collision elements on a link, each "
            "answers for the part of the mesh nearest to it, so a union of primitives is judged as a "
            "whole: when several elements leave their parts out, one finding stands for the link (the element "
            "answering for the mesh's largest part), naming the others, since a misplaced element leaves its part "
            "nearest to a correctly placed neighbour; and an element standing for one of the link's several visual "
            "elements (a primitive of its kind at its origin: a caster's sphere on a body) answers for that "
            "element, not for the rest of the mesh. A neighbour's element that is the same at every position of "
            "the joint between them (across a fixed joint; a sphere centred on, or a cylinder along, the axis of a "
            "revolute or continuous joint: Franka's capsules) counts in the union, and so does one of a link fixed "
            "to that neighbour (Laikago's thigh-motor cylinder, on a link fixed to the hip, about the thigh joint). "
            "The message gives the worst axis: the primitive's extent "
            "against the mesh's."
            " The tolerance follows the part's size: `protrusion_tolerance_m` (10 mm), or "
            "`protrusion_tolerance_fraction` (a quarter) of the mesh's smallest extent (and of the smallest extent "
            "of the part each element answers for) when that is less, never below "
            "`protrusion_floor_m` (2 mm), so a box 8 mm short on a 1 cm finger is reported; on a large part it is "
            "`protrusion_size_fraction` (5%) of the mesh's largest extent when that is more, up to "
            "`protrusion_size_cap_m` (25 mm). Severity is judged on the link's collision elements together with "
            "those of the adjacent links at zero joint positions (the share of the link's visual surface they cover "
            "within the tolerance: a finger's boxes running joint to joint take the knuckles reaching past each "
            "joint; the links a loop-closing constraint pins to it count as adjacent: an MJCF `<equality>` "
            "`connect` holds a gripper's inner knuckle against its finger at every position of the linkage): an "
            "error under `gross_coverage` (50%), a warning under `min_coverage` (90%), else info (a "
            "small part sticks out). A thin box on the mesh's face of a link ending a chain of moving joints (its "
            "thinnest side under `contact_plate_ratio` of the next: a sole plate) is a contact shape: info."
        ),
        why=(
            "Collision geometry that misses part of the link lets planners and simulators drive that "
            "part into obstacles and into the robot itself."
        ),
        example=(
            "The 2009 PR2 base: the collision box is 0.65 x 0.65 x 0.04 m while the base mesh spans "
            "0.66 x 0.66 x 0.90 m, so the box covers a 4% slab of the base's height."
        ),
        fix="Enlarge or move the primitive; the suggested primitive in the report data encloses the mesh.",
        severity_reason=(
            "Visual geometry outside the collision geometry is where planners and simulators miss contacts: a "
            "warning when more than a tenth of the link's surface is out, an error when more than half is (the "
            "part is mostly unprotected). Lowered to info when the link's elements, with the adjacent links' (and "
            "those a loop-closing constraint pins to it) at zero joint positions, cover over `min_coverage` of "
            "its surface: a tab, trim ring, shaft stub or "
            "knuckle outside a primitive misses contacts over a sliver of the part; for a foot's sole plate, "
            "which is the contact shape by design; and for a wheel (a link its continuous joint turns about the axis "
            "of one of its collision cylinders) whose surface lies, over `min_coverage`, within the collision "
            "geometry or within that cylinder's radius: a wheel touches through its tyre, and a hub or motor cover "
            "standing out of the cylinder's faces within its radius meets nothing the tyre does not meet first. "
            "Info too (and so GC303 for an element away from the mesh) when the link's collision elements are "
            "placeholders, none larger than `marker_element_m` (1 cm), and its mesh lies, over `min_coverage`, "
            "within another link's collision geometry, rigidly attached or at every position of the joint between "
            "them (Baxter's head with a 2 mm sphere, held by two spheres fixed to the base over its whole pan): "
            "contacts reach the part through that geometry. Elements of a real size are judged whatever holds the "
            "mesh: away from their part they make contacts where it is not."
        ),
        metrics=(
            *FITTED,
            HELD_BY,
            Metric(
                "also_elements",
                "text",
                description="The link's other elements whose parts of the mesh stick out, when several do.",
                optional=True,
            ),
        ),
        messages={
            "held": "; the link's mesh lies within the collision geometry of {cover}, rigidly attached to it: "
            "contacts reach the part through that geometry",
            "held_moving": "; the link's mesh stays within the collision geometry of {cover} at every position of "
            "joint {joint}: contacts reach the part through that geometry",
            "tyre": "; the rest lies within the tyre's radius (a hub, a motor cover): a wheel touches the ground and "
            "obstacles with its tyre, and {tyre:.0%} of its surface is held by the cylinder or inside its radius",
            "": "{label} {kind} covers {axis_share} and {coverage:.0%} of its surface: {axis_text}; "
            "the mesh sticks out up to {protrusion_max} (95th percentile {protrusion_p95})",
            # the worst axis: its share, then the element's and the mesh's extents along it
            "radial_share": "{share:.0%} of the mesh's diameter about its {about}",
            "radial_extent": "the {kind} is {extent:.3g} m across, the mesh reaches {reach:.3g} m from its {about}",
            "axis_share": "{share:.0%} of the mesh's {noun}",
            "axis_extent": "the {kind} is {extent:.3g} m {size} ({element_at}), "
            "the mesh spans {span:.3g} m ({mesh_at})",
        },
    )
)

COLLISION_OVERSIZED = register(
    Rule(
        code="GC302",
        name="collision-oversized",
        severity=Severity.WARNING,
        summary="A collision primitive is far larger than the mesh it stands for.",
        what=(
            "Over-coverage, judged as under-coverage is, on the element's part of the mesh (the points nearer to "
            "it than to the link's other elements). Reported when a side of the element stands off its part: the "
            "face (or the radius) lies beyond the part's extreme on that side by more than the part's tolerance "
            "(GC301's), more than `oversize_gap_fraction` (10%) of the part's extent across it and more than "
            "`oversize_floor_m` (5 mm: padding a few millimetres proud of a thin part is within the margin the "
            "sweeps call a near miss, not a false contact), while a "
            "primitive of the same kind fitted to the part has `oversize_volume_ratio` (1.5) times less volume. A "
            "face of one element of a union that lies inside another of the link's elements is an inner face "
            "and is not judged, nor an element of a union answering for less than `oversize_min_part_share` (25%) "
            "of the mesh (it may stand for what the visual does not draw: a cable, a mount), nor a link's only "
            "element left that little by a rigidly attached neighbour's collision geometry holding the rest of "
            "the mesh (a motor stator inside the box of the bracket it is bolted to: its part is a sliver, which "
            "any element dwarfs). For a link's only "
            "element, also when another kind fitted to the mesh encloses it "
            "in `oversize_kind_ratio` (2) times less volume than the element and than an element of its own kind "
            "fitted to the mesh (a sphere of a wheel's radius on a wheel; a capsule on a rod-like part, which a "
            "fitted capsule encloses in 1.5 times a box's volume, is of the right kind, only larger than its fit), "
            "and when "
            "its slack (volume over the mesh's convex hull volume) exceeds `max_slack` (4) while a fitted "
            "primitive of its type is `min_slack_gain` (1.5) times tighter."
            " Severity: a warning; info for a sphere at the distal end of a chain of moving joints (a foot: "
            "its rigid group moves and nothing moves below it), the chain's contact shape, sized for contact."
        ),
        why="Oversized collision geometry reports false contacts and shrinks the reachable workspace.",
        example=(
            'A 2 cm finger modelled as <sphere radius="0.1"/>; a 140 x 140 x 184 mm box on a 109 x 120 x 155 mm '
            "forearm; a wheel's cylinder twice its tyre's width."
        ),
        fix="Use the suggested primitive from the report data, or shrink the primitive to the mesh.",
        severity_reason=(
            "Too much collision geometry costs reach and reports false contacts, never missed ones: a warning, "
            "for the maintainer to tighten. Info for a sphere ending a leg (nothing moves below its link): a "
            "foot's sphere is its contact shape and is sized for contact, not to the foot's mesh."
        ),
        metrics=(
            *FITTED,
            *optional(
                (
                    Metric("standoff_side", "text", description="The side standing off the part (x-, ..., radial)."),
                    Metric("standoff_mm", "mm", "lower", "How far that side reaches past the part."),
                    Metric("standoff_allowed_mm", "mm", description="How far it may: the part's tolerance or share."),
                    Metric("volume_ratio", "1", "lower", "The element's volume over a fitted element's of its kind."),
                ),
                "for a side standing off its part",
            ),
            *optional(
                (
                    Metric("kind_ratio", "1", "lower", "The element's volume over the better-fitting kind's."),
                    Metric(
                        "own_kind_ratio", "1", "lower", "A fitted element of its kind's volume over the better kind's."
                    ),
                    Metric("better_kind", "object", description="The primitive of another kind fitted to the mesh."),
                ),
                "for the wrong kind of shape",
            ),
        ),
        messages={
            "": "{label} {kind} has {slack:.1f} times the volume of the mesh's convex hull; "
            "a fitted {kind} would have {fitted_slack:.1f} times",
            "contact": "; it ends a chain of moving joints, the chain's contact shape",
            "standoff": "{label} {kind} reaches {gap} past its part of the mesh at its {side} ({allowed} allowed, the "
            "part being {span} across there), with {volume_ratio:.1f} times the volume of a {kind} fitted to the part",
            "kind": "{label} {kind} has {kind_ratio:.1f} times the volume of a {better} fitted to the mesh, which "
            "encloses {coverage:.0%} of its surface: the part is not {kind}-shaped",
            "own_kind": " (a {kind} fitted to the mesh would have {own_kind_ratio:.1f} times)",
        },
    )
)

COLLISION_OFFSET = register(
    Rule(
        code="GC303",
        name="collision-offset-from-mesh",
        severity=Severity.ERROR,
        summary="A collision element is somewhere else than the mesh: disjoint from it, or misplaced.",
        what=(
            "Reported when the element holds less than `offset_overlap_fraction` (5%) of the mesh and "
            "less than that share of its volume lies in the mesh's convex hull (disjoint), or when it "
            "does not cover the mesh (the link's elements together cover less than `min_coverage`) but would once "
            "centred on it and the move needed exceeds `offset_min_fraction` (20%) of the element's size "
            "(misplaced), unless it reaches across a joint onto the neighbour's mesh where it stays at every joint "
            "position (a cylinder coaxial with a roll joint, spanning both links, as Baxter's wrist): that is "
            "deliberate, and the element is judged on its part of the mesh by GC301. The offset is stated."
            " An element that lies on a neighbour's mesh (the same there at every position of the joint between "
            "them) is reported for its own link too, with the share of it outside the link's own mesh: it makes the "
            "link collide where the link is not. Severity: an error; for an element lying on a neighbour's mesh, a "
            "warning when the link's own mesh is still covered (within the tolerance, over `min_coverage`) by its "
            "other elements and borrowed ones, an error when it is left uncovered. A sphere that closes a "
            "capsule of its own link (centred on an end of the axis of one of the link's cylinders, with that "
            "cylinder's radius, within `capsule_cap_tolerance_m`: URDF writes a capsule as a cylinder and two "
            "such spheres) is not reported when it lies past the mesh: it is the capsule's rounded end, placed "
            "with the cylinder, whose own fit judges the capsule. An element of a union away from the mesh but "
            "against it (its surface no farther from the mesh than its own largest half-extent) and small beside "
            "it (at most `beside_volume_share` (10%) of the mesh's convex hull) is info: it stands for a part the "
            "visual does not draw (a tooth on a jaw bone, a cable, a bumper pad), where a wrong origin moves an "
            "element farther than its own size."
        ),
        why=(
            "A collision element away from its link's geometry protects empty space and leaves the "
            "link unprotected: usually a wrong `<origin>`, a sign error or a frame mix-up."
        ),
        example='<origin xyz="0 0 0.5"/> on a collision box whose mesh sits at the link origin.',
        fix="Move the element's <origin> by the stated offset (the report data has the corrected origin).",
        severity_reason=(
            "An element away from its link protects empty space and leaves the link unprotected, almost always a "
            "wrong origin: an error. An element lying on a neighbour's mesh, where it stays at every joint position, "
            "is a warning: it takes the space of a part of the neighbour (a motor on the joint's axis carried by "
            "the link), and either it belongs to the neighbour or the link's own mesh lacks geometry of its own. "
            "An element that still covers `min_coverage` of the link is "
            "not reported here (a small protrusion is GC301's)."
        ),
        metrics=(
            *(m for m in FITTED if m.name in ("element", "multi", "tolerance", "covers_neighbour")),
            DISJOINT,
            HELD_BY,
            Metric("offset", "m", description="The move (x, y, z) the message states.", optional=True),
            *optional(
                tuple(m for m in FITTED if m.name not in ("element", "multi", "tolerance", "covers_neighbour")),
                "for an element on its own link's mesh",
            ),
            *optional(COMPARED, "for a collision mesh"),
            *optional(LENT, "for an element lying on a neighbour's mesh"),
        ),
        messages={
            "disjoint": "{label} {kind} is away from the link's visual geometry: {inside}; its nearest mesh "
            "point is {nearest} from its surface, the mesh's centre {distance} from its centre, at {offset}",
            "disjoint_inside": "no more than {mesh_inside:.0%} of the mesh is within {tolerance} of it",
            "disjoint_in_hull": " and {in_hull:.0%} of it lies inside the mesh's convex hull",
            "beside": "; it is one of the link's elements, against the mesh (no farther from it than its own size) "
            "and small beside it: it stands for what the visual does not draw",
            "misplaced": "{label} {kind} is {distance} off its mesh: it covers {coverage:.0%} of it (sticking out "
            "up to {protrusion_max}) but would enclose it moved by {offset}",
            "held": "; the link's mesh lies within the collision geometry of {cover}, rigidly attached to it: "
            "contacts reach the part through that geometry",
            "held_moving": "; the link's mesh stays within the collision geometry of {cover} at every position of "
            "joint {joint}: contacts reach the part through that geometry",
            "lent": "{label} {kind} lies mostly outside link {link}'s own mesh: {outside:.0%} of it is outside that "
            "mesh's convex hull, on the mesh of neighbour {neighbour} (where it stays at every joint position); "
            "link {link}'s mesh is {link_coverage:.0%} covered by the collision geometry, sticking out up to "
            "{link_protrusion_max}",
        },
    )
)

CYLINDER_AXIS_MISALIGNED = register(
    Rule(
        code="GC304",
        name="cylinder-axis-misaligned",
        severity=Severity.ERROR,
        summary="A collision cylinder lies along the wrong axis of its mesh.",
        what=(
            "A URDF cylinder's axis is the z axis of its `<origin>` frame. When the cylinder does not "
            "cover its mesh but the same cylinder turned onto another axis (a link axis or a principal "
            "axis of the mesh) covers at least `axis_coverage_gain` (30 points) more of it, the "
            "rotation and the `rpy` to use are reported."
            " Severity: always an error: a cylinder across its part leaves most of it unprotected."
        ),
        why=(
            "Wheels, rollers and shafts are often modelled with the axis left on z; the collision "
            "cylinder then stands across the wheel and misses most of it."
        ),
        example='A wheel turning about y with <origin rpy="0 0 0"/> on its collision cylinder.',
        fix="Set the cylinder's <origin rpy> to the stated value.",
        severity_reason=(
            "A cylinder across its part leaves most of it unprotected and the turned cylinder is a one-line fix: "
            "always an error."
        ),
        metrics=FITTED,
        messages={
            "": "{label} cylinder lies along {along} but the mesh's axis is {axis}: the same cylinder turned "
            "{angle:.0f} degrees about {turn_axis} covers {turned_coverage:.0%} of the mesh instead of {coverage:.0%}",
        },
    )
)

VISUAL_WITHOUT_COLLISION = register(
    Rule(
        code="GC305",
        name="visual-without-collision",
        severity=Severity.WARNING,
        summary="A link has visual geometry but no collision geometry.",
        what=(
            "Reports links with at least one `<visual>` and no `<collision>` element. Severity by what can touch "
            "the part: info when the collision geometry of a link rigidly attached to it (fixed joints) holds "
            "over `min_coverage` of its visual surface, or that of the link it hangs from at `joint_samples` "
            "positions over the joint's range (a rocker pivoting inside the chassis); the convex hull of that "
            "link's visual geometry counts as well (a rotor in its motor housing, a logo on a torso: the housing's "
            "own fit judges its collision geometry) unless the part ends a chain of moving joints (a foot, a "
            "fingertip: the chain's contact point) or, across a joint, moves other than turning in place about "
            "its axis. Info too when, at rest (joints at zero), the collision geometry of the links around it "
            "holds over `min_coverage` of its visual surface, as GC301 counts a link's neighbours: the links joined "
            "to it by a fixed, revolute or continuous joint, a neighbour without collision geometry passed through "
            "to the links beyond it (a knee housing between the thigh's and the shin's capsules, a rod of a "
            "linkage along the leg it drives). A part of the robot's root body that no moving body of the robot "
            "can reach stays a warning, and the message says so (the space each moving body's collision geometry "
            "sweeps is bounded by turning its convex bound about every revolute joint between it and the root "
            "body and stretching it along every prismatic joint over its limits): obstacles, walls and the ground "
            "still reach it; info when it stands out of its body's collision geometry by no more than that body's "
            "tolerance (`protrusion_size_fraction` of its largest extent, at most `protrusion_size_cap_m`), as "
            "GC301 lets a small part stick out. A moving link, or a part some moving body can reach, is a warning "
            "too. In an MJCF model, info: MuJoCo collides every geom its author does not exclude, so a body whose "
            "geoms collide with nothing (contype and conaffinity 0) was left out of collision on purpose."
        ),
        why=(
            "Planners and simulators ignore links without collision geometry: the part is visible but "
            "can pass through obstacles and through the robot."
        ),
        example='<link name="camera_mount"><visual>...</visual></link>',
        fix="Add a collision element; the report's suggested primitive for the link is a starting point.",
        severity_reason=(
            "A moving part without collision passes through obstacles and through the robot: a warning. Info when "
            "nothing can touch it: it sits inside the collision geometry of the body it is bolted to, it lies at "
            "rest inside the collision geometry of the links around it (what touches it touches them first; the "
            "same judgement GC301 makes of a link whose own elements leave a part to its neighbours). A part of "
            "the robot's root body out of reach of every moving body stays a warning: planners collide the robot "
            "with the obstacles around it and simulators with walls and the ground, and a sensor or a cover no "
            "collision geometry holds passes through them. "
            "Each format by its own semantics: URDF and SDFormat have no way to say a part is meant not to collide, "
            "so a missing <collision> is judged by what can touch the part; MuJoCo collides every geom unless its "
            "author excludes it, so a body whose geoms collide with nothing (contype and conaffinity 0) was left out "
            "of collision on purpose: info, saying so. A description without any collision element is reported "
            "once, on its root link, at warning (each link's finding info, naming it): one cause, one finding."
        ),
        metrics=(
            Metric("suggested", "object", description="The box enclosing the visual geometry, or null."),
            Metric(
                "covered_by",
                "text",
                description="The rigidly attached link whose collision or visual hull holds the visual, or null.",
            ),
            Metric(
                "reached_by",
                "text",
                description="A moving link whose swept space meets the part of the root body, or null.",
            ),
            *optional(
                (
                    Metric(
                        "held_at_rest_by",
                        "text",
                        description="The links around it whose collision geometry holds its visual at rest.",
                    ),
                ),
                "when they hold it",
            ),
            *optional(
                (Metric("links_without", "text", description="The links drawn without collision geometry."),),
                "on the one finding of a description without any collision element",
            ),
        ),
        messages={
            "": "link '{link}' has {count} visual element{plural} but no collision geometry",
            "covered": "; its visual lies within the {what} of {cover}, rigidly attached to it",
            "enclosed": "; its visual stays within the {what} of {cover} at every position of joint {joint}",
            "unreached": "; it is rigidly attached to the robot's root body {anchor}: no moving body of the robot "
            "can reach it, but obstacles and the ground can",
            "reached": "; moving link {other} can reach it",
            "flush": ", and it stands out of that body's collision geometry by at most {out} ({allowed} allowed at "
            "the body's size): what reaches it meets the body first",
            "visual_only": "; MuJoCo collides every geom its author does not exclude, and this body's geoms collide "
            "with nothing (contype and conaffinity 0): left out of collision on purpose",
            "moving": "; it moves (joint {joint})",
            "resting": "; at rest {share:.0%} of its visual lies within the collision geometry of the links around "
            "it ({holders})",
            "none_at_all": "none of the description's {links} links has collision geometry: {count} are drawn with "
            "visual geometry only ({names}): planners and simulators see no part of the robot to collide",
            "in_none": "; one of {count} links drawn without collision in a description that has none (reported "
            "once, on {root})",
        },
    )
)

COLLISION_MESH_MISMATCH = register(
    Rule(
        code="GC306",
        name="collision-mesh-mismatch",
        severity=Severity.WARNING,
        summary="A collision mesh does not match the link's visual mesh.",
        what=(
            "Compares a collision mesh with the visual geometry both ways: the visual must lie inside "
            "the collision mesh's convex hull (within `protrusion_tolerance_m`, over `min_coverage` of "
            "its surface), and the collision mesh must not reach more than "
            "`mesh_overshoot_tolerance_m` (20 mm) out of the visual's convex hull."
            " The tolerance follows the part's size: `protrusion_tolerance_m` (10 mm), or "
            "`protrusion_tolerance_fraction` (a quarter) of the mesh's smallest extent (and of the smallest extent "
            "of the part each element answers for) when that is less, never below "
            "`protrusion_floor_m` (2 mm), so a box 8 mm short on a 1 cm finger is reported. Severity: a warning "
            "when the visual sticks out and the link's collision elements together cover less than `min_coverage` "
            "of it (an error under `gross_coverage`); info when the collision mesh only reaches past the visual "
            "(the safe direction) or the union covers the visual."
        ),
        why=(
            "Collision meshes are simplified copies of the visual mesh; one that is scaled, moved, "
            "rotated or taken from another link protects the wrong volume."
        ),
        example="A collision mesh exported in another frame, 5 cm off the visual.",
        fix="Regenerate the collision mesh from the visual mesh (convex hull or decomposition) in the same frame.",
        severity_reason=(
            "A collision mesh that leaves the visual out misses contacts: judged on all the link's collision "
            "elements together, a warning when more than a tenth of the visual surface is out (an error when "
            "more than half is). One that only reaches past the visual errs on the safe side (false contacts): "
            "info, until it reaches out by `mesh_gross_overshoot_fraction` (a quarter) of the visual's largest "
            "extent: a collision mesh of another shape or in another place (a bumper's mesh turned a quarter turn), "
            "a warning."
        ),
        metrics=(*FITTED, *COMPARED),
        messages={
            "": "{label} mesh {name} does not match the visual geometry: {reasons} (surfaces up to {surface_distance} "
            "apart)",
            # the reasons, joined with "; "
            "sticks_out": "the visual sticks out of its hull by up to {protrusion_max} ({coverage:.0%} of the visual "
            "surface covered)",
            "overshoot": "it reaches {overshoot} out of the visual's hull",
            "lowered": "; the link's collision geometry covers {union_coverage:.0%} of the visual's surface",
        },
    )
)
