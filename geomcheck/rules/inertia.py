"""GC5xx: inertia and mass. Checks live in :mod:`geomcheck.checks.inertia`."""

from __future__ import annotations

from dataclasses import replace

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, optional, register

MASS = Metric("mass", "kg", description="The link's mass, as written.")
# what a finding carries when its severity was lowered because the link's mass matters little
WEIGHED: tuple[Metric, ...] = (
    Metric("mass_share", "1", description="The link's share of the robot's mass.", optional=True),
    Metric(
        "body",
        "text",
        description="The rigid body a fixed joint lumps the link into, or null. Only with mass_share.",
        optional=True,
    ),
    Metric(
        "body_mass_share",
        "1",
        description="The link's share of that body's mass, or null. Only with mass_share.",
        optional=True,
    ),
)
BODY_LINKS = Metric(
    "body_links",
    "text",
    description="The links fixed below this one that consumers merge into its body, none carrying mass.",
    optional=True,
)
MERGED = (
    "When fixed joints merge the link into a body that passes the same check (pinocchio's model, Gazebo's "
    "fixed-joint lumping in sdformat and MuJoCo's URDF import simulate that merged body, not the link), the message "
    "says so and an error becomes a warning; never lower: the merged body carries the link's wrong values inside "
    "it, KDL and RViz read the link itself, and the maintainer would correct them."
)
LIGHT = (
    "On a link carrying less than `minor_mass_share` (1%) of the robot's mass the message says so and an error "
    "becomes a warning, never lower: the values are still wrong for that part (a 0.01 kg wheel with a 0.32 m "
    "radius of gyration) and its maintainer would change them. Info only where no part's computed data is judged "
    "wrong: every link carries the same <inertial> (a macro's placeholder: the whole robot's dynamics are "
    "fictitious, not this link's); the link's geometry is itself a placeholder, no larger than "
    "`placeholder_extent_m` (2 mm) or primitives alone no larger than `marker_extent_m` (1 cm: a frame's marker "
    "box, not a part); the link weighs no more than `negligible_mass_kg` (0.1 g: what authors type for a massless "
    "frame where a simulator refuses zero); the link is a frame fixed to a body that passes the check and carries "
    "a point mass or values typed for 'unknown' (mass and moments powers of ten, no products: a camera frame's "
    "0.01 kg and 0.001 kg m^2), which consumers merge away; a light link (under `minor_mass_share`) misses the "
    "geometry's bound by at most `marginal_ratio` (2) in moment, the estimate of a small part a little off; or the "
    "link carries its computed mass with a round tensor, the same power of ten on every axis and no products, "
    "which authors set on purpose to steady small links in Gazebo."
)
MOMENTS = Metric("principal_moments", "kg m^2", description="The tensor's principal moments, ascending.")

MISSING_INERTIAL = register(
    Rule(
        code="GC501",
        name="missing-inertial",
        severity=Severity.ERROR,
        summary="A moving link has no <inertial>.",
        what=(
            "Flags a link that is the child of a non-fixed joint and has no <inertial> element, when no "
            "link fixed below it carries mass either: the body consumers build (the link merged with the "
            "links on fixed joints below it) has no mass. Root links (base_footprint, world) and links on "
            "fixed joints may be massless: their mass is lumped into the parent. When no link of the "
            "description has an <inertial>, one finding for the robot instead: a kinematics-only description. "
            "Several moving links without one are one finding, on the first, naming the others (each info, "
            "saying so): their inertials were left out together."
        ),
        why=(
            "Without mass the joint has no dynamics: Gazebo drops the link and its joint from the "
            "model, MuJoCo and Drake refuse a massless moving body, and Pinocchio/KDL build a "
            "singular mass matrix when nothing below the joint carries mass."
        ),
        example=(
            '<joint name="wheel_joint" type="continuous"> ... <child link="wheel"/></joint>\n'
            '<link name="wheel"><visual>...</visual></link>   <!-- no <inertial> -->'
        ),
        fix=(
            "Add an <inertial> with the link's mass, centre of mass and inertia tensor (from CAD, or "
            "the formulas of a box/cylinder/sphere enclosing the part), or make the joint fixed."
        ),
        metrics=(
            Metric("joint", "text", description="The joint that moves the link.", optional=True),
            Metric("joint_type", "text", description="That joint's type.", optional=True),
            BODY_LINKS,
            Metric(
                "moving_links",
                "1",
                "lower",
                description="How many links move, for the robot-level finding of a kinematics-only description.",
                optional=True,
            ),
            Metric(
                "also_links",
                "text",
                description="The other moving links without an <inertial>, on the one finding that names them.",
                optional=True,
            ),
        ),
        messages={
            "": "link moves on {joint_type} joint {joint} but has no <inertial>",
            "body": ", nor do the links fixed below it ({links})",
            "kinematics_only": "no link has an <inertial>: a kinematics-only description ({count} moving links), "
            "for planning and display; Gazebo drops every link without inertia and dynamics libraries have no "
            "mass to work with, so simulating it needs mass properties",
            "others": "; {count} more moving links have none: {links}",
            "reported_with": " (one of several moving links without one, reported once, on {link})",
        },
        severity_reason=(
            'Error: Gazebo drops a massless moving link with its joint and everything below it ("has no '
            "inertia, not modeled in gazebo\"), MuJoCo refuses a massless moving body and pinocchio's forward "
            "dynamics divide by zero. Judged on the merged body: no finding when a link fixed below carries mass "
            "(pinocchio and sdformat give the moving body that mass). When no link at all has an <inertial>, one "
            "info finding for the robot: such descriptions (ROS-Industrial support packages) are written for "
            "planning on purpose, and a simulator is not meant to load them."
        ),
    )
)

NON_POSITIVE_MASS = register(
    Rule(
        code="GC502",
        name="non-positive-mass",
        severity=Severity.ERROR,
        summary=(
            "A moving link has a mass of zero or less, any link a negative or non-finite mass, or a zero mass "
            "with a tensor."
        ),
        what=(
            "Flags <mass value> <= 0 (at or below thresholds inertia.min_mass_kg) on a link that is "
            "the child of a non-fixed joint when the links fixed below it carry no mass either, a "
            "negative or non-finite mass on any link, and a zero mass with a non-zero tensor on any link "
            "(a warning on a link that does not move)."
        ),
        why=(
            "A zero mass makes the joint's dynamics singular; a negative mass is not physical and "
            "makes simulators unstable."
        ),
        example='<inertial><mass value="0"/><inertia ixx="1e-4" ... /></inertial>',
        fix="Give the link its real mass in kilograms.",
        metrics=(
            replace(MASS, better="higher"),
            Metric("min_mass_kg", "kg", description="The least mass of a moving link."),
            BODY_LINKS,
        ),
        messages={
            "not_finite": "mass is {mass} kg, not a finite number",
            "negative": "mass is negative: {mass:.6g} kg",
            "moving": "mass is {mass:.6g} kg on a link that moves on {joint_type} joint {joint}",
            "body": ", and the links fixed below it ({links}) carry none",
            "massless_tensor": "mass is 0 kg but the inertia tensor is not zero (largest value {largest:.3g} kg m^2): "
            "no body without mass has rotational inertia",
        },
        severity_reason=(
            "Error, whatever the link weighs: a massless moving body makes its joint's dynamics singular and "
            "Gazebo drops it; a negative or non-finite mass breaks every simulator. A zero mass on a moving link "
            "is no finding when links fixed below it carry mass: the merged body consumers simulate has mass. A "
            "zero mass with a non-zero tensor on a fixed link is a warning: no body without mass has rotational "
            "inertia, and pinocchio, Gazebo and MuJoCo add that tensor, massless, to the body they merge the link "
            "into (a placeholder end effector of 0 kg with a 1e-8 tensor kept a simulator from loading an arm)."
        ),
    )
)

NOT_POSITIVE_DEFINITE = register(
    Rule(
        code="GC503",
        name="inertia-not-positive-definite",
        severity=Severity.ERROR,
        summary="The inertia tensor is not positive definite.",
        what=(
            "Computes the principal moments (eigenvalues) of the tensor and flags a tensor with a "
            "zero, negative or non-finite moment. A zero moment on a link that does not move on "
            "its own (root, fixed joint) is only a warning: a point mass is a legitimate limit there."
        ),
        why=(
            "A rigid body of positive size has three positive principal moments. Simulators reject "
            "or blow up on a tensor with a zero or negative one; a sign error in an off-diagonal "
            "term is the usual cause."
        ),
        severity_reason=(
            "Error: MuJoCo and Drake refuse such a tensor on a moving body, and a simulator that accepts it "
            "integrates nonsense; a warning for a point mass (zero tensor) on a link that does not move, and info "
            "when fixed joints merge that point mass into a body that passes (a valid idealisation of the merged "
            "body). Not lowered by weight, since the refusal does not depend on it. " + MERGED
        ),
        example=(
            '<inertia ixx="0.01" ixy="0.02" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>\n'
            "(principal moments -0.01, 0.01, 0.03 kg m^2)"
        ),
        fix=(
            "Recompute the tensor (CAD mass properties, or a primitive's formula); check the sign of "
            "the off-diagonal terms: URDF's ixy is the tensor entry -integral(x y dm), not the "
            "product of inertia integral(x y dm) some CAD tools print."
        ),
        metrics=(
            replace(
                MOMENTS,
                optional=True,
                better="higher",  # the defect is a moment at or below zero
                description=f"{MOMENTS.description} Absent for non-finite values.",
            ),
            replace(MASS, optional=True, description=f"{MASS.description} Absent for non-finite values."),
            Metric("tensor", "text", description="The six written values, for non-finite ones.", optional=True),
            Metric("point_mass", "bool", description="Whether the tensor is zero (a point mass).", optional=True),
            *WEIGHED,
        ),
        messages={
            "": "inertia tensor is not positive definite: it {kind} (principal moments {moments} kg m^2)",
            # what is wrong, for "it ..."
            "zero": "is zero, as for a point mass",
            "semidefinite": "has a zero principal moment",
            "negative": "has a negative principal moment",
            "not_finite": "inertia tensor or its origin has non-finite values: {tensor} kg m^2",
        },
    )
)

TRIANGLE_INEQUALITY = register(
    Rule(
        code="GC504",
        name="inertia-breaks-triangle-inequality",
        severity=Severity.ERROR,
        summary="The principal moments break the triangle inequality A + B >= C.",
        what=(
            "Flags principal moments A <= B <= C with A + B < C beyond the relative tolerance "
            "(thresholds inertia.relative_tolerance)."
        ),
        why=(
            "A + B - C equals twice the body's second moment of mass along C's axis, which cannot "
            "be negative: no distribution of mass has such a tensor. Drake and MuJoCo reject it."
        ),
        severity_reason=(
            'Error: MuJoCo refuses the model ("inertia must satisfy A + B >= C") and Drake rejects it, '
            "however light the link. Not lowered by weight. " + MERGED
        ),
        example='<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.01"/>',
        fix="Recompute the tensor; a moment typed with a wrong exponent or unit is the usual cause.",
        metrics=(
            MOMENTS,
            MASS,
            Metric("excess", "kg m^2", "lower", "How much the largest moment exceeds the sum of the other two."),
            *WEIGHED,
        ),
        messages={
            "": "principal moments break the triangle inequality: A + B = {a:.4g} + {b:.4g} = {sum:.4g} kg m^2 "
            "is less than C = {c:.4g} kg m^2, which no mass distribution allows",
        },
    )
)

EXCEEDS_GEOMETRY = register(
    Rule(
        code="GC505",
        name="inertia-exceeds-geometry",
        severity=Severity.WARNING,
        summary="The inertia needs mass outside every visual and collision shape of the link.",
        what=(
            "For a rigid body inside the link's geometry (all visual and collision shapes, in the "
            "link frame), the moment about any axis through the centre of mass is at most "
            "mass x (largest distance of the geometry from that axis)^2, and the second moment "
            "along a direction at most mass x (largest distance from the plane through the centre "
            "of mass)^2. Checked about the principal axes and the link's x, y, z axes; the message "
            "compares the radius of gyration (or the rms spread) with the geometry's reach. Only "
            "reported for tensors that pass GC503 and GC504; links whose meshes cannot be read are "
            "skipped (the report's skipped checks say which)."
        ),
        why=(
            "A tensor that is impossible for the part's shape is copied from another part, in the "
            "wrong units, or computed for another axis orientation. Simulated motion (wheel "
            "spin-up, arm dynamics, controller gains tuned in simulation) is then wrong."
        ),
        severity_reason=(
            "Warning: no consumer refuses a tensor too large for the part (MuJoCo, Gazebo and pinocchio load any "
            "valid tensor), but the simulated dynamics are wrong and a maintainer would recompute it. "
            + MERGED
            + " "
            + LIGHT
        ),
        example=(
            "2009 PR2 wheel: mass 0.44036 kg, radius 0.079 m, moments about 0.012-0.015 kg m^2, so "
            "a radius of gyration of 0.16-0.19 m: more than twice the wheel's radius."
        ),
        fix=(
            "Recompute the tensor for this part: from CAD, or for a solid cylinder of mass m, radius r, "
            "length h along its axis: I_axis = m r^2 / 2, I_other = m (3 r^2 + h^2) / 12, with the "
            "axis of the formula turned onto the part's axis. When the link's centre of mass is itself off the "
            "part (GC506, GC511), the help gives the solid's tensor about the part's centroid too: the one about "
            "the stated centre of mass carries the offset's m d^2."
        ),
        metrics=(
            MASS,
            Metric("directions", "text", description="The directions judged: the link axes, then the principal axes."),
            Metric("moments", "kg m^2", description="The tensor's moment about each direction."),
            Metric("moment_bound", "kg m^2", description="The most the geometry allows about each direction."),
            Metric("radius_of_gyration", "m", "lower", description="The radius of gyration about each direction."),
            Metric("reach", "m", description="How far the geometry reaches from each axis through the centre of mass."),
            Metric("spread", "m", description="The rms spread of the mass along each direction."),
            Metric("extent", "m", description="How far the geometry extends from the centre of mass along each."),
            Metric(
                "worst",
                "object",
                description="The worst direction, its bound (moment or spread) and ratio to what the geometry allows.",
            ),
            Metric(
                "implied_inertia",
                "kg m^2",
                description="The tensor (ixx ... izz) of the geometry's solid hull with the written mass, when it has "
                "a volume.",
                optional=True,
            ),
            *WEIGHED,
        ),
        messages={
            "moment": "link {link}'s inertia needs a radius of gyration of {gyration:.3f} m about the "
            "{direction} (moment {moment:.4g} kg m^2, mass {mass:.6g} kg), but the link's geometry reaches only "
            "{reach:.3f} m from that axis through the centre of mass: the moment can be at most {bound:.4g} kg m^2",
            "spread": "link {link}'s inertia spreads the mass {spread:.3f} m (rms) from the centre of mass along "
            "the {direction} (second moment {second_moment:.4g} kg m^2, mass {mass:.6g} kg), but the link's "
            "geometry extends only {extent:.3f} m from it along that direction: at most {bound:.4g} kg m^2; the "
            "tensor may be for another orientation of the part",
        },
    )
)

COM_OUTSIDE = register(
    Rule(
        code="GC506",
        name="com-outside-geometry",
        severity=Severity.WARNING,
        summary="The centre of mass lies outside the link's geometry.",
        what=(
            "Flags a centre of mass farther than thresholds inertia.com_margin_m outside the convex "
            "hull of all visual and collision shapes of the link (the bounding box when the "
            "geometry is flat), and states the distance."
        ),
        why=(
            "The centre of mass of a rigid body lies inside the convex hull of its material. One "
            "outside it is usually given in another frame (the joint's or the parent's) or with a "
            "sign error, and moves the whole robot's balance."
        ),
        severity_reason=(
            "Warning: simulators accept any centre of mass, but gravity torques and balance come out wrong and a "
            "maintainer would move it into the part. " + MERGED + " " + LIGHT
        ),
        example='<inertial><origin xyz="0 0 0.5"/> ...   <!-- link geometry spans z -0.05 .. 0.05 -->',
        fix="Express the centre of mass in the link frame (the frame of the link's visual origins).",
        metrics=(
            Metric("com", "m", description="The centre of mass, in the link frame."),
            Metric("distance", "m", "lower", "How far the centre of mass lies outside the geometry's convex hull."),
            Metric("bounds", "m", description="The lower and upper corners of the geometry's bounding box."),
            *WEIGHED,
        ),
        messages={
            "": "centre of mass {com} m lies {distance:.3f} m outside the link's geometry (convex hull of its "
            "visual and collision shapes; bounds {bounds} m)",
        },
    )
)

COPIED_INERTIA = register(
    Rule(
        code="GC507",
        name="copied-inertia",
        severity=Severity.WARNING,
        summary="A link has exactly another link's inertia tensor with a very different mass.",
        what=(
            "Groups links by their six written tensor values and flags each link whose tensor is "
            "identical to that of the heaviest link sharing it while the masses differ by "
            "at least thresholds inertia.copied_inertia_mass_ratio. Zero tensors are left to GC503. "
            "When thresholds inertia.shared_tensor_sources or more <inertial> elements write it onto parts of "
            "other masses (a macro's repeats count once), it was typed for every part rather than copied from one: "
            "one finding, on the lightest part, names the others and counts those whose tensor is more "
            "than their geometry allows, whose GC505 it replaces."
        ),
        why=(
            "The inertia tensor scales with the mass: two parts with different masses cannot share "
            "it. This is copy-and-paste between links, or a placeholder tensor left in place."
        ),
        severity_reason=(
            "Warning: simulators load both tensors, one of which is wrong (which is not known); a maintainer would "
            "compute each. " + MERGED + " " + LIGHT
        ),
        example="2009 PR2: each caster wheel (0.44036 kg) has the tensor of its caster hub (3.473082 kg).",
        fix="Compute the tensor of each part from its own mass and shape.",
        metrics=(
            Metric("copied_from", "text", description="The link whose tensor this one repeats."),
            MASS,
            Metric("reference_mass", "kg", description="That link's mass."),
            Metric("mass_ratio", "1", "lower", "The larger mass over the smaller: how far off the shared tensor is."),
            Metric("tensor", "kg m^2", description="The shared tensor: ixx, ixy, ixz, iyy, iyz, izz."),
            *optional(
                (
                    Metric(
                        "shared_sources",
                        "count",
                        "lower",
                        "The <inertial> elements (file and line) writing the tensor.",
                    ),
                    Metric(
                        "exceeds_geometry",
                        "text",
                        description="The links among them whose tensor is more than their geometry allows (GC505).",
                    ),
                ),
                "when one tensor is typed on many parts (then reported once: copied_from is the heaviest, "
                "mass the lightest part's, also the others)",
            ),
            *WEIGHED,
        ),
        messages={
            "": "inertia tensor (ixx, ixy, ixz, iyy, iyz, izz) = {tensor} kg m^2 is exactly that of link "
            "{reference}, although the masses differ by a factor {ratio:.1f} ({mass:.6g} kg against "
            "{reference_mass:.6g} kg): one of the two tensors was copied",
            "shared": "inertia tensor (ixx, ixy, ixz, iyy, iyz, izz) = {tensor} kg m^2 is written on {count} links"
            "{written} whose masses range from {mass:.6g} kg ({link}) to {reference_mass:.6g} "
            "kg ({reference}), a factor {ratio:.3g}: one tensor typed for every part, computed for none (also on "
            "{listed})",
            "shared_exceeding": "; on {exceeding} of them it is more than the part's geometry allows",
        },
    )
)

IMPLAUSIBLE_DENSITY = register(
    Rule(
        code="GC508",
        name="implausible-density",
        severity=Severity.ERROR,
        summary="The mass is too large for the link's geometry to hold, even filled with osmium.",
        what=(
            "Divides the mass by the volume of the convex hull of the link's visual and collision "
            "shapes and flags an average density above thresholds inertia.max_density_kg_m3 "
            "(22600 kg/m^3, osmium)."
        ),
        why=(
            "No material is denser than osmium, so the mass or the geometry is wrong: grams written "
            "as kilograms (a factor of 1000, which the inertia checks cannot see when the tensor is "
            "scaled the same way), or placeholder shapes far smaller than the part."
        ),
        severity_reason=(
            "Error: a mass beyond osmium's density is usually grams written as kilograms; a link 1000 times too "
            "heavy cannot be moved by its joint's effort and its mass ratio to its neighbours destabilises "
            "Gazebo's solver. " + MERGED + " " + LIGHT
        ),
        example='<link name="wheel"><inertial><mass value="440.36"/> ...   <!-- a 0.079 m wheel -->',
        fix="Give the mass in kilograms (and the tensor in kg m^2), and the link the shapes of the real part.",
        metrics=(
            MASS,
            Metric("hull_volume", "m^3", description="The volume of the convex hull of the link's geometry."),
            Metric("density", "kg/m^3", "lower", "The mass over that volume."),
            *WEIGHED,
        ),
        messages={
            "": "mass {mass:.6g} kg in a geometry whose convex hull holds {volume:.4g} m^3 is an average density "
            "of {density:.4g} kg/m^3, {times:.1f} times that of osmium ({max_density:.0f} kg/m^3)",
        },
    )
)

COUNTERPART_INERTIA = register(
    Rule(
        code="GC510",
        name="counterpart-inertia-mismatch",
        severity=Severity.WARNING,
        summary="Left and right counterparts with mirrored geometry carry inertials that are not mirror images.",
        what=(
            "Pairs links whose names differ only by a side word (left/right, l/r, FL/FR, lf/rf, ...) and whose "
            "frames at the default pose (joints at 0 or mid-range) are mirror images across the robot's xz plane "
            "(within `counterpart_origin_tolerance_m`, 5 mm), and whose geometry occupies mirror-image boxes "
            "(within `counterpart_geometry_fraction`, 5%, of their size). When both draw the same mesh files at the "
            "same scales and places, they are one part mounted on both sides and their inertials must agree in "
            "the frames their geometry is drawn in; when the meshes differ, they are a left and a right part and "
            "their inertials, moved to the world and one reflected, must agree; with the same meshes placed "
            "differently, or primitives only, or one mesh that is its own mirror image (95% of its points within "
            "`counterpart_geometry_fraction` of its size of the other side's reflected: a thigh symmetric about "
            "its plane of motion), either reading will do. Agree: masses within "
            "`counterpart_mass_fraction` (10%), centres of mass within `counterpart_com_m` (5 mm) or "
            "`counterpart_com_fraction` (10%) of the part's size, tensors per unit mass within "
            "`counterpart_tensor_fraction` (25%) of the largest value."
        ),
        why=(
            "Mirrored parts have mirrored mass properties. A difference is a fix made on one side only, or a side "
            "copied without mirroring (a right leg carrying the left's centre of mass, products of inertia with "
            "the wrong sign): the robot's dynamics are lopsided in every simulator and controller."
        ),
        example=(
            "left_hip (1.2 kg, centre of mass at y = +0.02 m) and right_hip (1.5 kg, centre of mass at y = +0.02 m: "
            "not mirrored)"
        ),
        fix=(
            "Compute both sides from one source: the right side's mass, the left's centre of mass with y negated "
            "in the world, and its tensor with ixy and iyz negated (for frames that mirror each other)."
        ),
        severity_reason=(
            "Warning: simulators load both, and one side is wrong (which one, only the part's CAD tells); a "
            "maintainer would make them agree. Not lowered by weight: the difference is the description's own."
        ),
        metrics=(
            Metric("parts", "text", description="How the meshes relate the parts: identical or mirrored."),
            Metric("mass_difference", "1", "lower", "The masses' difference over the larger."),
            Metric("com_distance_mm", "mm", "lower", "How far one centre of mass, mirrored, lands from the other."),
            Metric("com_allowed_mm", "mm", description="How far it may: 5 mm or 10% of the part's size."),
            Metric("tensor_difference", "1", "lower", "The tensors' largest difference per unit mass, as a share."),
        ),
        messages={
            "": "{left} and {right} are counterparts in name, place and shape ({parts}), but their mass properties "
            "differ: {reasons}",
            "identical": "the same meshes: one part on both sides",
            "mirrored": "mirrored meshes: a left and a right part",
            "either": "read as one part on both sides and as mirrored parts, neither agrees",
            "mass": "{left} weighs {a:.4g} kg, {right} {b:.4g} kg",
            "com_identical": "{right}'s centre of mass lies {distance:.1f} mm from {left}'s, each taken from where "
            "its part is drawn",
            "com_mirrored": "{right}'s centre of mass lies {distance:.1f} mm from {left}'s mirrored",
            "tensor_identical": "their tensors differ by {share:.0%} of the largest value per unit mass",
            "tensor_mirrored": "their tensors differ by {share:.0%} of the largest value, mirrored and per unit mass",
        },
    )
)

COM_MISPLACED = register(
    Rule(
        code="GC511",
        name="com-misplaced",
        severity=Severity.WARNING,
        summary="The centre of mass lies inside the part, but at the link origin or with two coordinates swapped.",
        what=(
            "Compares the centre of mass with the centroid of the link's geometry (its convex hull taken as a "
            "solid of uniform density) and the part's size (its largest extent). Reported when it is written as "
            "the link origin, `0 0 0`, while the centroid lies `com_origin_fraction` (a third) of the part's "
            "extent or more away from it; and when exchanging two of its coordinates brings it `com_swap_gain` (3) "
            "times nearer the centroid, from at least `com_swap_fraction` (a fifth) of the extent away. A centre of "
            "mass outside the geometry is GC506."
        ),
        why=(
            "A template's `0 0 0` and swapped coordinates are the usual ways a centre of mass is left wrong while "
            "staying inside the part, where no bound shows it: gravity torques and balance come out wrong in every "
            "simulator and controller."
        ),
        example='A finger phalanx reaching 72 mm along z from its joint with <origin xyz="0 0 0"/> in its <inertial>.',
        fix="Compute the centre of mass of the part (from CAD, or the centroid of its geometry for a uniform part).",
        severity_reason=(
            "Warning: simulators accept any centre of mass, but the dynamics come out wrong and a maintainer would "
            "correct it. " + MERGED + " " + LIGHT
        ),
        metrics=(
            Metric("com", "m", description="The centre of mass as written, in the link frame."),
            Metric("centroid", "m", description="The centroid of the link's geometry."),
            Metric("distance", "m", "lower", "How far apart they are."),
            Metric("size", "m", description="The part's largest extent."),
            Metric("swapped", "text", description="The two axes whose coordinates look swapped (xy, xz, yz), or null."),
            *WEIGHED,
        ),
        messages={
            "origin": "centre of mass is written at the link origin (0, 0, 0), as templates leave it, while the "
            "part's geometry centres at {centroid} m, {distance:.0f} mm away ({share:.0%} of the part's extent)",
            "swapped": "centre of mass lies {distance:.0f} mm from the part's centroid, and {nearer:.0f} mm with its "
            "{a} and {b} coordinates exchanged, at {swapped} m: they look swapped",
        },
    )
)
