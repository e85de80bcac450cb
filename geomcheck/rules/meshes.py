"""GC2xx: mesh files, their units and their integrity."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, optional, register

FILENAME = Metric("filename", "text", description="The mesh's filename as written.")
KIND = Metric("kind", "text", description="The kind of problem.")
# a mesh that could not be loaded (MeshProblem)
PROBLEM: tuple[Metric, ...] = (
    FILENAME,
    Metric("path", "text", description="The file it resolved to, or null."),
    KIND,
    Metric("suggestion", "text", description="An existing file whose name differs only in letter case, or null."),
    Metric("alternative", "text", description="A file of the same name elsewhere in the bundle, or null."),
    Metric("generated_from", "text", description="The file a package's build generates it from, or null."),
)
# one finding for every element naming the meshes of one package
GROUPED: tuple[Metric, ...] = (
    Metric("package", "text", description="The package."),
    Metric("count", "count", description="The mesh references concerned."),
    Metric("links", "text", description="The links they are on."),
    Metric("references", "object", description="Each reference: link, about, filename and what was found for it."),
)
# the unit check of a loaded mesh
SIZED: tuple[Metric, ...] = (
    FILENAME,
    Metric("scale", "1", description="The <mesh> scale as written."),
    Metric("extents", "m", description="The scaled mesh's bounding box extents."),
    Metric("size", "m", description="Its largest extent."),
    Metric("link_reference", "m", description="The typical size of the link's other geometry, or null."),
    Metric("robot_reference", "m", description="The typical size of the robot's other links, or null."),
)
# the integrity of a loaded mesh
INTEGRITY: tuple[Metric, ...] = (
    FILENAME,
    Metric("area", "m^2", description="The surface area of its triangles."),
    Metric("hull_volume", "m^3", description="The volume of its convex hull."),
    Metric("finite", "bool", description="Whether every vertex coordinate is finite."),
)


MESH_FILE_NOT_FOUND = register(
    Rule(
        code="GC201",
        name="mesh-file-not-found",
        severity=Severity.ERROR,
        summary="A mesh file named by a visual or collision element does not exist.",
        severity_reason=(
            "An error: RViz draws nothing for the element, Gazebo loads the link without that geometry, MoveIt's "
            "geometric_shapes returns no shape (the link does not collide) and pinocchio's geometry model refuses"
            " the robot. Lowered to information for the convex decompositions a rosbuild package generates at "
            "build time when their source mesh is there: the package is not built, not broken."
        ),
        what=(
            "Resolves every `<mesh filename>` (package://, file://, absolute, or relative to the root "
            "file) and reports the elements whose file is missing. When a file exists whose path "
            "differs only in letter case (`base.STL` for `base.stl`), it is named. A missing "
            "`meshes/X/convex/NAME_convex.stlb` next to an existing `meshes/X/NAME.stl` is what it is: a "
            "convex decomposition that rosbuild-era packages generated at build time (convex_decomposition "
            "and ivcon). The package is then not built rather than broken: one finding per package, as "
            "information, lists the elements concerned, and every check analyses the source mesh in the "
            "build product's place (the decomposition covers the same part). Severity: an error for a "
            "missing file, information for a build product of a package that is not built."
        ),
        why=(
            "ROS tools fail or silently drop the geometry when a mesh is missing; case-only "
            "differences work on macOS and Windows but break on Linux robots and CI."
        ),
        example='<mesh filename="package://my_robot/meshes/base.stl"/>  <!-- the file is meshes/base.STL -->',
        fix="Correct the filename (exact letter case) or add the missing mesh file to the package.",
        metrics=(
            KIND,
            *optional(tuple(m for m in PROBLEM if m.name != "kind"), "for one missing file"),
            Metric(
                "existing_filename",
                "text",
                description="The filename with the existing file's letter case (what geomcheck fix writes). Only "
                "when such a file exists.",
                optional=True,
            ),
            *optional(GROUPED, "for the build products of a package"),
            Metric("files", "text", description="The missing build products. Only for a package.", optional=True),
        ),
    )
)

MESH_PACKAGE_UNRESOLVED = register(
    Rule(
        code="GC202",
        name="mesh-package-unresolved",
        severity=Severity.ERROR,
        summary="A `package://` mesh filename names a package that is not known.",
        severity_reason=(
            "An error: without the package, resource_retriever (RViz, Gazebo, MoveIt) and pinocchio cannot open "
            "any of its meshes, as for a missing file. A `package:///NAME/...` filename is an error too: "
            "resource_retriever reads an empty package name and refuses it, although pinocchio accepts it."
        ),
        what=(
            "Reports `package://NAME/...` mesh filenames whose package NAME was neither given nor discovered: "
            "one finding per unknown package (one defect, however many elements name it), an error, giving "
            "the number of references and listing them in its data with, for each, the file of the same name "
            "found elsewhere in the bundle when there is one. A `package:///NAME/...` filename (three "
            "slashes), which ROS's resource_retriever "
            "rejects and pinocchio accepts, is an error too, naming the tools; the mesh is loaded as pinocchio "
            "loads it, so every check still runs. An unknown package whose folder sits beside the root file "
            "(PyBullet's data: `package://xarm_description/...` next to `xarm_description/`, no package.xml) is "
            "an error too, one per package, and its meshes are read from that folder, as PyBullet reads them."
        ),
        why="Without the package the mesh cannot be found; the checks that need it are skipped.",
        example='<mesh filename="package://missing_description/meshes/arm.stl"/>',
        fix="Pass the package with `--package NAME=DIR` or `--search DIR`, or correct the package name.",
        metrics=(
            KIND,
            *optional(GROUPED, "for an unknown package"),
            *optional((FILENAME,), "for a filename some tools accept"),
            Metric("accepted_by", "text", description="The tools that accept the filename. Only then.", optional=True),
            Metric("alternative", "text", description="The filename every tool reads. Only then.", optional=True),
            Metric(
                "folder",
                "text",
                description="The folder beside the root file the package's meshes were read from. Only then.",
                optional=True,
            ),
        ),
    )
)

MESH_UNREADABLE = register(
    Rule(
        code="GC203",
        name="mesh-unreadable",
        severity=Severity.ERROR,
        summary="A mesh file exists but cannot be read (corrupt, unsupported format, too large).",
        severity_reason=(
            "An error: the mesh is as good as missing for the tools that fail on it as well (assimp in RViz, "
            "MoveIt and pinocchio, Gazebo's loaders), and geomcheck cannot check the link's geometry. Never "
            "lowered."
        ),
        what=(
            "Reads every mesh as trimesh reads it (STL, OBJ, DAE, PLY, GLB/glTF, OFF; binary STL, COLLADA and "
            "OBJ with numpy, to the same triangles), and an MJCF model's meshes in MuJoCo's own binary `.msh` "
            "format as MuJoCo reads them (no other tool does: under a URDF or SDFormat file it is unsupported), "
            "and reports those that fail, "
            "and COLLADA files whose declared `<unit meter>` is not a positive length."
        ),
        why="A mesh that cannot be read is as good as missing for simulators, planners and this tool.",
        example='<mesh filename="meshes/arm.3ds"/>',
        fix="Re-export the mesh as binary STL, OBJ or DAE.",
        metrics=PROBLEM,
    )
)

MESH_EMPTY = register(
    Rule(
        code="GC204",
        name="mesh-empty",
        severity=Severity.ERROR,
        summary="A mesh file holds no triangles.",
        severity_reason=(
            "An error: RViz reports no meshes in the file, coal (pinocchio) throws on it and MoveIt gets no "
            "shape: the element draws nothing and collides with nothing. Never lowered."
        ),
        what="Reports mesh files that load but contain no faces (points or lines only, or nothing).",
        why="An empty mesh has no surface: nothing is drawn and nothing collides.",
        example='<mesh filename="meshes/placeholder.stl"/>  <!-- 0 triangles -->',
        fix="Export the mesh again with its surfaces, or remove the element.",
        metrics=PROBLEM,
    )
)

MESH_SCALE_SUSPECT = register(
    Rule(
        code="GC205",
        name="mesh-scale-suspect",
        severity=Severity.ERROR,
        summary="A mesh is off in size by a unit factor (1000, 100, 39.37, 25.4) against its link and the robot.",
        severity_reason=(
            "An error: every consumer reads the mesh at its size in metres, so RViz draws it, Gazebo simulates it"
            " and MoveIt and pinocchio collide it a unit factor off. Never lowered: a COLLADA file's declared "
            "<unit meter> is applied first, as RViz and Gazebo apply it, so a mesh in a declared unit is not one."
        ),
        what=(
            "Compares each mesh's size (largest extent, `scale` applied) with the link's other geometry "
            "(collision primitives first: URDF primitives are typed in metres) and with the typical size "
            "of the robot's other links (median of their largest shapes). A ratio to the link's geometry "
            "near 1000 (millimetres read as metres), 100 (centimetres), 39.37 (inches) or 25.4 "
            "(millimetres read as inches), or the inverse, is reported with the `scale` that fixes it "
            "when the robot's typical link is off the same way, by at least a quarter of that factor. "
            "A mesh too large must also outgrow its whole link: span at least twice the extent of the "
            "link's primitives and joint origins together (typed in metres), so that a housing among "
            "screw heads is not judged by the screws' median size. "
            "Without other geometry on the link, only a factor of 1000 against the robot counts. A COLLADA "
            "file's declared `<unit meter>` is applied before any size is judged, as RViz and Gazebo apply it "
            "(its `<up_axis>` is not: no ROS consumer applies it)."
        ),
        why=(
            "CAD tools export millimetres or inches while URDF is in metres; a forgotten `scale` makes "
            "a link 1000 times too large, which breaks collision checking, visualisation and planning."
        ),
        example='<mesh filename="package://arm/meshes/link1.stl"/>  <!-- exported in mm: spans 250 m -->',
        fix='Add the scale to the mesh element, e.g. <mesh filename="..." scale="0.001 0.001 0.001"/>.',
        metrics=(
            *SIZED,
            Metric("factor", "1", description="How many times too large (below 1: too small) the mesh is."),
            Metric("suggested_scale", "text", description="The scale attribute that corrects it."),
            Metric("reference", "text", description="What it was compared with: link or robot."),
        ),
    )
)

MESH_SIZE_IMPLAUSIBLE = register(
    Rule(
        code="GC206",
        name="mesh-size-implausible",
        severity=Severity.ERROR,
        summary="A mesh is absurdly large or small for a robot link.",
        severity_reason=(
            "An error: a link mesh tens of metres or micrometres across is drawn, simulated and collided at that "
            "size by every consumer (a declared COLLADA <unit meter> is applied first, as RViz and Gazebo do). "
            "Never lowered."
        ),
        what=(
            "Reports meshes whose largest extent (`scale` applied) is above `max_link_extent_m` (5 m) or "
            "below `min_link_extent_m` (1 mm) when no unit factor explains it, with the most plausible scale. "
            "A COLLADA file's declared `<unit meter>` is applied first, as RViz and Gazebo apply it."
        ),
        why="A link mesh of tens of metres or of micrometres is a units or export error.",
        example='<mesh filename="meshes/gripper.stl" scale="10 10 10"/>',
        fix="Fix the `scale` attribute or re-export the mesh in metres.",
        metrics=(
            *SIZED,
            *optional(
                (
                    Metric("factor", "1", description="The unit factor the size suggests."),
                    Metric("suggested_scale", "text", description="The scale attribute that corrects it."),
                ),
                "when a unit explains the size",
            ),
        ),
    )
)

MESH_DEGENERATE = register(
    Rule(
        code="GC207",
        name="mesh-degenerate",
        severity=Severity.ERROR,
        summary="A mesh has non-finite vertices or no surface area.",
        severity_reason=(
            "An error: non-finite or overflowing coordinates break the bounding volumes of coal/FCL (MoveIt, "
            "pinocchio) and Gazebo's physics, and a mesh without area has no surface to draw or collide. Never "
            "lowered."
        ),
        what=(
            "Reports meshes with NaN or infinite vertex coordinates, coordinates beyond `max_length_m` "
            "(100 km, `scale` applied: geometry built from them overflows), or whose triangles all have zero area."
        ),
        why="Such meshes break bounding volumes, collision libraries and renderers.",
        example="An STL whose triangles all repeat one point.",
        fix="Repair or re-export the mesh.",
        metrics=(
            FILENAME,
            *optional(tuple(m for m in PROBLEM if m.name != "filename"), "for coordinates out of range"),
            *optional(tuple(m for m in INTEGRITY if m.name != "filename"), "for a loaded mesh"),
        ),
    )
)

MESH_FLAT = register(
    Rule(
        code="GC208",
        name="mesh-flat",
        severity=Severity.WARNING,
        summary="A mesh encloses no volume: all its vertices lie on one plane or line.",
        severity_reason=(
            "A warning: every tool loads a flat collision mesh, but it has no inside, so contacts and "
            "penetrations through it are missed; a maintainer would give it thickness. Lowered to information for"
            " a visual mesh: a flat label, screen or decal is drawn as intended and never collides."
        ),
        what=(
            "Reports meshes whose vertices are coplanar (or collinear): zero convex hull volume. A warning "
            "for collision meshes, information for visual ones."
        ),
        why=(
            "A flat mesh has no inside: as collision geometry it misses penetrations, and its fit and "
            "inertia bounds are meaningless."
        ),
        example="A single quad exported as the collision mesh of a panel.",
        fix="Give the part its thickness, or use a thin box as collision geometry.",
        metrics=INTEGRITY,
    )
)

MESH_UNIT_TOOL_DEPENDENT = register(
    Rule(
        code="GC209",
        name="mesh-unit-tool-dependent",
        severity=Severity.ERROR,
        summary=(
            "A COLLADA mesh declares a unit other than the metre: RViz and Gazebo apply it, "
            "MoveIt and pinocchio do not."
        ),
        severity_reason=(
            "An error for a collision mesh: MoveIt (geometric_shapes) and pinocchio (coal) drop the root transform "
            "in which assimp puts the declared unit, so they collide the mesh a unit factor off the size RViz shows "
            "and Gazebo simulates. Lowered to information for a visual mesh: RViz and Gazebo draw it at its declared "
            "size, and only viewers built on pinocchio's visual model draw it otherwise."
        ),
        what=(
            "Reports mesh elements whose COLLADA file declares `<asset><unit meter>` other than 1. geomcheck "
            "measures the mesh with the unit applied, as RViz (getMeshUnitRescale) and Gazebo's COLLADA loader "
            "do; MoveIt's geometric_shapes and coal (pinocchio) read the file through assimp and discard the "
            "scene's root transform, where assimp puts the unit, and so use the file's numbers as metres."
        ),
        why=(
            "The same robot then has collision geometry of two sizes: planned motions and contacts in MoveIt "
            "and pinocchio disagree with what RViz shows and Gazebo simulates."
        ),
        example='<mesh filename="package://leg/meshes/calf.dae"/>  <!-- calf.dae: <unit meter="0.0254"/> -->',
        fix=(
            'Declare <unit meter="1"/> in the file and put the unit in the element\'s scale '
            '(scale="0.0254 0.0254 0.0254"): every tool applies the URDF scale.'
        ),
        metrics=(
            FILENAME,
            Metric("unit", "m", description="Metres per file unit the file declares."),
            Metric("scale", "1", description="The <mesh> scale as written."),
            Metric("size", "m", description="Its largest extent with the unit applied (RViz, Gazebo)."),
            Metric("size_unapplied", "m", description="Its largest extent as MoveIt and pinocchio read it."),
            Metric("suggested_scale", "text", description="The scale attribute that holds the unit instead."),
            Metric(
                "meshes",
                "text",
                description="The link's other mesh files of the same kind declaring the same unit, reported in "
                "this one finding. Only when there are.",
                optional=True,
            ),
        ),
    )
)

MESH_WINDING = register(
    Rule(
        code="GC210",
        name="mesh-inconsistent-winding",
        severity=Severity.WARNING,
        summary="A mesh's faces are wound against their neighbours, or a closed mesh is inside out.",
        what=(
            "Counts the edges that two triangles share and run along in the same direction (neighbours wound "
            "against each other): reported when they are at least `inconsistent_winding_share` (25%) of the "
            "shared edges. A closed mesh (every edge shared by two triangles) wound alike everywhere whose "
            "signed volume is negative is inside out, and reported too. Meshes of more than "
            "`winding_max_faces` triangles are not examined."
        ),
        why=(
            "A face's winding gives its normal. RViz and Gazebo cull back faces, so wrongly wound faces show as "
            "holes and the part flickers; MuJoCo and tools that compute a mesh's volume and inertia from its faces "
            "get them wrong (a negative or tiny volume), and contact normals point into the part."
        ),
        example="A CAD export whose faces were written with mixed orientation (73% of the shared edges of link_2.stl).",
        fix="Recompute consistent outward normals (MeshLab: Re-Orient all faces coherently; Blender: Recalculate "
        "Outside) and export the mesh again.",
        severity_reason=(
            "A warning: every consumer loads the mesh, but viewers show holes and volume-based inertia and contact "
            "normals come out wrong; a maintainer would re-export it. The same for visual and collision meshes: "
            "both are drawn, and a collision mesh's winding also sets contact normals."
        ),
        metrics=(
            FILENAME,
            Metric("shared_edges", "count", description="Edges shared by exactly two triangles."),
            Metric("inconsistent_edges", "count", "lower", "Of those, the edges both triangles run the same way."),
            Metric("inconsistent_share", "1", "lower", "Their share of the shared edges."),
            Metric("closed", "bool", description="Whether every edge is shared by two triangles."),
            Metric("signed_volume", "m^3", description="The volume the faces enclose, negative when wound inward."),
        ),
        messages={
            "mixed": "{label} mesh {name} has faces wound against their neighbours: {inconsistent} of its {shared} "
            "shared edges ({share:.0%}) are run the same way by both triangles, so normals point in and out at random",
            "inside_out": "{label} mesh {name} is inside out: closed and wound alike, it encloses a negative volume "
            "({volume:.3g} m^3), every normal pointing into the part",
        },
    )
)

VISUAL_DRAWS_COLLISION_MESH = register(
    Rule(
        code="GC211",
        name="visual-draws-collision-mesh",
        severity=Severity.WARNING,
        summary="A visual draws a mesh from a collision folder while the visual mesh of that name lies beside it.",
        what=(
            "For a visual <mesh> whose file lies in a folder named `collision` (or `collisions`), looks for a file "
            "of the same name (any of the STL, COLLADA and OBJ extensions) in the sibling folder named `visual` "
            "(or `visuals`), as ROS-Industrial and most description packages lay their meshes out. Reported when "
            "one exists: the visual draws the coarse collision mesh instead of it."
        ),
        why=(
            "The collision mesh is coarse on purpose; drawn as the visual, the robot looks wrong in RViz and "
            "Gazebo, and every check of the collision geometry against the visual compares it with itself."
        ),
        example=(
            '<visual><geometry><mesh filename="package://r_support/meshes/collision/link_2.stl"/></geometry></visual>'
            "   <!-- meshes/visual/link_2.dae exists -->"
        ),
        fix="Point the visual at the visual mesh.",
        severity_reason=(
            "A warning: every consumer loads it, but the robot is drawn with the wrong mesh and the fit of its "
            "collision geometry is judged against the collision mesh itself; a maintainer would change the path."
        ),
        metrics=(
            FILENAME,
            Metric(
                "visual_mesh",
                "text",
                description="The visual mesh of the same name beside it, as the description would name it.",
            ),
        ),
        messages={
            "": "{label} draws {name} from a collision folder, while the visual mesh {visual} lies beside it",
        },
    )
)
