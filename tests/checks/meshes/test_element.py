"""GC2xx mesh and file checks (geomcheck.checks.meshes) on small robots built in the tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.meshes import MeshStats, run
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load import ExpandedDocument, LoadedDescription, MeshStore, make_bundle
from geomcheck.load.meshes import LoadedMesh
from geomcheck.model import Box, Cylinder, Geometry, Joint, Link, Mesh, Pose, Robot, Shape, SourceLocation
from geomcheck.options import CheckOptions

ROOT_FILE = "robot.urdf"
BOX_SIZE = (0.3, 0.2, 0.1)  # [m]
VISUAL_LINE = 5


@pytest.fixture
def bundle_dir(tmp_path: Path) -> Path:
    """A ROS package ``bot`` with the root file and a few meshes: a box in metres, the same
    box exported in millimetres and in inches-read-as-mm, a flat quad, a corrupt file."""
    (tmp_path / "package.xml").write_text("<package><name>bot</name></package>\n")
    (tmp_path / ROOT_FILE).write_text("<robot name='r'/>\n")
    meshes = tmp_path / "meshes"
    meshes.mkdir()
    box = trimesh.creation.box(extents=BOX_SIZE)
    box.export(meshes / "box.stl")
    box.copy().apply_scale(1000.0).export(meshes / "box_mm.stl")
    box.copy().apply_scale(25.4).export(meshes / "box_inch_as_mm.stl")
    box.copy().apply_scale(0.001).export(meshes / "box_tiny.stl")
    box.export(meshes / "Upper.STL")
    quad = trimesh.Trimesh(vertices=[[0, 0, 0], [0.1, 0, 0], [0.1, 0.1, 0], [0, 0.1, 0]], faces=[[0, 1, 2], [0, 2, 3]])
    quad.export(meshes / "flat.stl")
    (meshes / "empty.stl").write_bytes(b"solid x\nendsolid x\n")
    (meshes / "broken.dae").write_bytes(b"<COLLADA><library_geometries><oops")
    (meshes / "big.obj").write_text("v 0 0 0\nv 40 0 0\nv 0 40 0\nv 0 0 40\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
    (meshes / "nan.obj").write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
    return tmp_path


def visual(geometry: Geometry) -> Shape:
    return Shape("visual", 0, geometry, location=SourceLocation(ROOT_FILE, VISUAL_LINE))


def link(name: str, geometry: Geometry, collision: Geometry | None = Box(BOX_SIZE)) -> Link:
    collisions = (Shape("collision", 0, collision),) if collision is not None else ()
    return Link(name, visuals=(visual(geometry),), collisions=collisions)


def robot_of(*links: Link) -> Robot:
    """The links plus three ordinary 0.3 m box links, all fixed to ``base``."""
    ordinary = tuple(link(f"plain{i}", Mesh("package://bot/meshes/box.stl")) for i in range(3))
    everything = (*links, *ordinary)
    joints = tuple(
        Joint(f"{lk.name}_joint", "fixed", "base", lk.name, Pose((float(i), 0, 0))) for i, lk in enumerate(everything)
    )
    return Robot("r", links=(Link("base"), *everything), joints=joints)


def check(bundle_dir: Path, robot: Robot) -> tuple[FamilyResult, CheckContext]:
    bundle = make_bundle(bundle_dir / ROOT_FILE)
    document = ExpandedDocument(text="", root=ROOT_FILE, sources={}, is_xacro=False)
    loaded = LoadedDescription(bundle=bundle, robot=robot, document=document, diagnostics=())
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions(sweep=False))
    return run(ctx), ctx


def only(result: FamilyResult, code: str) -> Diagnostic:
    found = [d for d in result.diagnostics if d.code == code]
    assert len(found) == 1, sorted((d.code, d.link, d.about) for d in result.diagnostics)
    return found[0]


def test_sound_meshes_have_no_finding_and_stats_are_cached(bundle_dir: Path) -> None:
    result, ctx = check(bundle_dir, robot_of(link("body", Mesh("meshes/box.stl"))))
    assert result.diagnostics == []
    stats = ctx.analyses.mesh_stats[("meshes/box.stl", (1.0, 1.0, 1.0))]
    assert isinstance(stats, MeshStats)
    assert stats.extents == pytest.approx(BOX_SIZE) and stats.hull_volume == pytest.approx(0.006)
    assert stats.area == pytest.approx(0.22) and stats.finite and not stats.flat
    # every file read once, however many links use it and however it is named
    # (meshes/box.stl and package://bot/meshes/box.stl are one file)
    assert ctx.meshes.files_read == 1


def test_missing_file_names_the_case_only_match(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("package://bot/meshes/upper.stl"))))
    d = only(result, "GC201")
    assert (d.link, d.about, d.severity) == ("arm", "visual[0]", Severity.ERROR)
    assert d.location is not None and d.location.line == VISUAL_LINE
    assert d.data["suggestion"].endswith("meshes/Upper.STL")
    assert 'use filename="package://bot/meshes/Upper.STL"' in d.help


def test_missing_file_without_a_near_match(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/nowhere.stl"))))
    d = only(result, "GC201")
    assert d.data["suggestion"] is None and d.help.startswith("Correct the filename")


def test_missing_convex_build_product_is_one_note_per_package_and_analysed_as_its_source(bundle_dir: Path) -> None:
    # rosbuild-era packages generated meshes/X/convex/NAME_convex.stlb from meshes/X/NAME.stl at build time
    convex = Mesh("package://bot/meshes/convex/box_convex.stlb")
    arm = link("arm", Mesh("meshes/box.stl"), collision=convex)
    leg = link("leg", Mesh("meshes/box.stl"), collision=convex)
    result, ctx = check(bundle_dir, robot_of(leg, arm))
    d = only(result, "GC201")
    assert (d.severity, d.link, d.about) == (Severity.INFO, None, "package:bot")
    assert d.message == (
        "package 'bot' is not built: 1 convex decomposition (convex/NAME_convex.stlb) that its rosbuild build "
        "generates from NAME.stl is missing, used by 2 elements on 2 links (arm, leg); geomcheck analyses each "
        "source mesh in its place"
    )
    assert [(r["link"], r["about"]) for r in d.data["references"]] == [("arm", "collision[0]"), ("leg", "collision[0]")]
    assert d.data["references"][0]["generated_from"].endswith("meshes/box.stl")
    assert len(d.data["files"]) == 1 and d.data["files"][0].endswith("meshes/convex/box_convex.stlb")
    assert d.help.startswith("Build the package before checking it") and d.fix is None
    # the element's mesh is the source's: every analysis runs on it
    loaded = ctx.meshes.get(convex)
    assert isinstance(loaded, LoadedMesh) and loaded.path.endswith("meshes/box.stl")
    assert loaded.stands_for is not None and loaded.stands_for.endswith("meshes/convex/box_convex.stlb")
    assert loaded.mesh.extents == pytest.approx(BOX_SIZE)
    # without its source, the same name is an ordinary missing file: an error per element
    result, _ = check(bundle_dir, robot_of(link("arm", Box(BOX_SIZE), collision=Mesh("meshes/convex/arm_convex.stlb"))))
    d = only(result, "GC201")
    assert (d.severity, d.link, d.about, d.data["generated_from"]) == (Severity.ERROR, "arm", "collision[0]", None)


def test_build_product_stand_in_is_fitted_like_any_collision_mesh(tmp_path: Path) -> None:
    from geomcheck.pipeline import run_check

    (tmp_path / "meshes" / "convex").mkdir(parents=True)
    trimesh.creation.box(extents=BOX_SIZE).export(tmp_path / "meshes" / "body.stl")
    root = tmp_path / "robot.urdf"
    root.write_text(
        '<robot name="r"><link name="body">'
        '<visual><geometry><mesh filename="meshes/body.stl"/></geometry></visual>'
        '<collision><geometry><mesh filename="meshes/convex/body_convex.stlb"/></geometry></collision>'
        "</link></robot>"
    )
    report = run_check(make_bundle(root), CheckOptions(sweep=False))
    assert [(d.code, d.severity.value, d.about) for d in report.diagnostics] == [("GC201", "info", "build-products")]
    assert report.diagnostics[0].message.startswith("the description's folder is not built: 1 convex decomposition")
    assert not [s for s in report.skipped if s.subject == "body"]
    assert report.robot.meshes_loaded == report.robot.meshes_total == 2
    [entry] = report.sections["links"]
    assert entry["collisions"][0]["fit"]["coverage"] == 1.0


def test_binary_stl_under_the_stlb_extension_loads(bundle_dir: Path) -> None:
    trimesh.creation.box(extents=BOX_SIZE).export(bundle_dir / "meshes" / "hull.stlb", file_type="stl")
    result, ctx = check(bundle_dir, robot_of(link("arm", Mesh("meshes/hull.stlb"))))
    assert result.diagnostics == []
    stats = ctx.analyses.mesh_stats[("meshes/hull.stlb", (1.0, 1.0, 1.0))]
    assert stats.extents == pytest.approx(BOX_SIZE)


def test_unknown_package_is_one_finding_listing_its_references(bundle_dir: Path) -> None:
    gone, elsewhere = Mesh("package://nope/meshes/a.stl"), Mesh("package://nope/meshes/box.stl")
    robot = robot_of(link("arm", elsewhere, collision=gone), link("leg", Box(BOX_SIZE), collision=gone))
    result, _ = check(bundle_dir, robot)
    d = only(result, "GC202")
    assert (d.severity, d.link, d.about) == (Severity.ERROR, None, "package:nope")
    assert d.message == (
        "package 'nope' is not known (known packages: bot): 3 mesh references on 2 links (arm, leg) cannot be "
        "loaded; 1 of the files exists under the same name elsewhere, such as package://bot/meshes/box.stl"
    )
    assert d.data["count"] == 3 and d.data["links"] == ["arm", "leg"]
    assert d.data["references"] == [  # sorted by link, then element
        {"link": "arm", "about": "collision[0]", "filename": gone.filename, "alternative": None},
        {
            "link": "arm",
            "about": "visual[0]",
            "filename": elsewhere.filename,
            "alternative": "package://bot/meshes/box.stl",
        },
        {"link": "leg", "about": "collision[0]", "filename": gone.filename, "alternative": None},
    ]
    assert "--package nope=DIR" in d.help and d.fix is None
    # located at the first reference in document order
    assert d.location is not None and d.location.line == VISUAL_LINE


def test_unreadable_mesh(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/broken.dae"))))
    d = only(result, "GC203")
    assert (d.link, d.about, d.data["kind"]) == ("arm", "visual[0]", "unreadable")


def test_empty_mesh(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/empty.stl"))))
    d = only(result, "GC204")
    assert (d.link, d.about, d.data["kind"]) == ("arm", "visual[0]", "empty")


def test_millimetre_mesh_gets_the_scale(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/box_mm.stl"))))
    d = only(result, "GC205")
    assert (d.link, d.about, d.severity) == ("arm", "visual[0]", Severity.ERROR)
    assert d.data["factor"] == 1000.0 and d.data["suggested_scale"] == "0.001 0.001 0.001"
    assert d.data["size"] == pytest.approx(300.0) and d.data["link_reference"] == pytest.approx(0.3)
    assert "1000x too large (millimetres read as metres?)" in d.message
    assert 'scale="0.001 0.001 0.001"' in d.help


def test_millimetres_scaled_as_inches(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/box_inch_as_mm.stl"))))
    d = only(result, "GC205")
    assert d.data["factor"] == pytest.approx(25.4) and d.data["suggested_scale"] == "0.0393701 0.0393701 0.0393701"


def test_mesh_scaled_down_twice(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/box_tiny.stl"))))
    d = only(result, "GC205")
    assert d.data["factor"] == pytest.approx(0.001) and d.data["suggested_scale"] == "1000 1000 1000"
    assert "1000x too small (metres scaled as millimetres?)" in d.message


def test_scale_attribute_is_taken_into_account(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/box_mm.stl", (0.001, 0.001, 0.001)))))
    assert result.diagnostics == []


def test_absurd_size_without_a_unit_match(bundle_dir: Path) -> None:
    # a 40 m mesh whose link has no other geometry, on a robot of 0.3 m links
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/big.obj"), collision=None)))
    d = only(result, "GC206")
    assert d.data["size"] == pytest.approx(40.0) and d.data["suggested_scale"] == "0.01 0.01 0.01"
    assert "larger than any robot link should (5 m)" in d.message


def test_flat_collision_mesh_is_a_warning_and_a_flat_visual_information(bundle_dir: Path) -> None:
    flat = Mesh("meshes/flat.stl")
    panel = Link("panel", visuals=(visual(flat),), collisions=(Shape("collision", 0, flat),))
    result, _ = check(bundle_dir, robot_of(panel))
    found = {d.about: d for d in result.diagnostics if d.code == "GC208"}
    assert sorted(found) == ["collision[0]", "visual[0]"]
    assert found["collision[0]"].severity == Severity.WARNING and found["collision[0]"].data["hull_volume"] == 0.0
    # a flat label or screen is drawn as intended and never collides
    assert found["visual[0]"].severity == Severity.INFO
    assert found["visual[0]"].message.endswith("no volume (a visual: drawn as intended, it never collides)")


def test_non_finite_vertices(bundle_dir: Path) -> None:
    result, _ = check(bundle_dir, robot_of(link("arm", Mesh("meshes/nan.obj"), collision=Cylinder(0.1, 0.3))))
    d = only(result, "GC207")
    assert d.data["finite"] is False and "non-finite" in d.message


def test_one_finding_per_referencing_element(bundle_dir: Path) -> None:
    gone = Mesh("meshes/gone.stl")
    result, _ = check(bundle_dir, robot_of(link("a", gone, collision=gone), link("b", gone, collision=None)))
    assert sorted((d.code, d.link, d.about) for d in result.diagnostics) == [
        ("GC201", "a", "collision[0]"),
        ("GC201", "a", "visual[0]"),
        ("GC201", "b", "visual[0]"),
    ]


def test_the_2009_pr2_tilting_laser_is_not_a_unit_error(bundle_dir: Path) -> None:
    # a 0.3 m mesh with a 3 mm placeholder collision box, on a robot of 3 cm frame boxes
    # (the PR2: 0.11 m, 1 mm, 1 cm): the ratio to the box is near 100, the robot's only 10
    tiny = tuple(Link(f"frame{i}", visuals=(visual(Box((0.03, 0.03, 0.03))),)) for i in range(5))
    laser = link("laser", Mesh("meshes/box.stl"), collision=Box((0.003, 0.003, 0.003)))
    robot = Robot("r", links=(Link("base"), laser, *tiny), joints=())
    result, _ = check(bundle_dir, robot)
    assert result.diagnostics == []


def test_a_housing_among_screw_heads_is_not_a_unit_error(bundle_dir: Path) -> None:
    # a gripper of two links (no robot reference): a 0.3 m housing mesh with four 7 mm screw
    # heads at its corners, whose median (7 mm) puts the housing near 39.37x (inches); the
    # screws span the housing, which does not outgrow its link
    screws = tuple(
        Shape("visual", i + 1, Cylinder(0.0035, 0.007), origin=Pose((0.14 * sx, 0.09 * sy, 0.0)))
        for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1)))
    )
    housing = Link("housing", visuals=(visual(Mesh("meshes/box.stl")), *screws))
    robot = Robot("r", links=(Link("base"), housing), joints=(Joint("j", "fixed", "base", "housing"),))
    result, _ = check(bundle_dir, robot)
    assert result.diagnostics == []


def test_stats_of_scaled_meshes_are_kept_apart(bundle_dir: Path) -> None:
    a, b = Mesh("meshes/box.stl"), Mesh("meshes/box.stl", (2.0, 2.0, 2.0))
    _, ctx = check(bundle_dir, robot_of(link("x", a), link("y", b)))
    assert ctx.analyses.mesh_stats[("meshes/box.stl", (2.0, 2.0, 2.0))].extents == pytest.approx(2 * np.array(BOX_SIZE))


def box_in_package(folder: Path, package: str, filename: str, after: str) -> Path:
    """A robot file whose body's visual is a 0.3 x 0.2 x 0.1 m box mesh in ``package``'s folder
    (named ``filename``) and whose collision box is half as tall; ``after`` closes the body."""
    (folder / package / "meshes").mkdir(parents=True)
    trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(folder / package / "meshes" / "box.stl")
    root = folder / "robot.urdf"
    root.write_text(
        f'<robot name="r"><link name="body"><visual><geometry><mesh filename="{filename}"/></geometry></visual>'
        f'<collision><geometry><box size="0.3 0.2 0.05"/></geometry></collision>{after}</robot>'
    )
    return root


def test_three_slash_package_uri_is_an_error_and_loaded_as_pinocchio_does(tmp_path: Path) -> None:
    from geomcheck.pipeline import run_check

    root = box_in_package(tmp_path, "arm_description", "package:///arm_description/meshes/box.stl", "</link>")
    bundle = make_bundle(root, packages={"arm_description": tmp_path / "arm_description"})
    report = run_check(bundle, CheckOptions(sweep=False))
    by_code = {d.code: d for d in report.diagnostics}
    quirk = by_code["GC202"]
    # resource_retriever (RViz, Gazebo, MoveIt) refuses the empty package name: an error
    assert quirk.severity.value == "error" and quirk.about == "visual[0]"
    assert (
        "resource_retriever" in quirk.message and "pinocchio accepts it as package 'arm_description'" in quirk.message
    )
    assert quirk.data["alternative"] == "package://arm_description/meshes/box.stl"
    # the mesh is analysed: the half-height box is found not to cover it
    assert by_code["GC301"].link == "body"
    assert report.robot.meshes_loaded == report.robot.meshes_total == 1


def test_an_unknown_package_in_a_folder_beside_the_root_is_read_as_pybullet_reads_it(tmp_path: Path) -> None:
    """PyBullet's data: package://xarm_description/meshes/... with xarm_description/ beside the
    URDF and no package.xml. ROS tools cannot load it (GC202, an error, one per package), and
    the meshes are read from there so that every other check runs; a package with no such
    folder is still unknown and unread."""
    from geomcheck.pipeline import run_check

    tip = (
        '</link><joint name="j" type="fixed"><parent link="body"/><child link="tip"/></joint><link name="tip">'
        '<visual><geometry><mesh filename="package://gone/meshes/box.stl"/></geometry></visual></link>'
    )
    root = box_in_package(tmp_path, "arm_parts", "package://arm_parts/meshes/box.stl", tip)
    report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(sweep=False))
    packages = {d.data["package"]: d for d in report.diagnostics if d.code == "GC202"}
    beside, gone = packages["arm_parts"], packages["gone"]
    assert (beside.severity.value, beside.about, beside.data["kind"], beside.data["folder"]) == (
        "error",
        "package:arm_parts",
        "package-beside-root",
        "arm_parts",
    )
    assert beside.message == (
        "package 'arm_parts' is not known (known packages: none): its 1 mesh reference on 1 link (body) was read "
        "from the folder of that name beside the root file (arm_parts), as PyBullet reads package:// paths; ROS "
        "tools (RViz, Gazebo, MoveIt) cannot load them"
    )
    assert gone.data["kind"] == "unresolved-package"
    # the mesh is analysed: the half-height box is found not to cover it
    assert [d.link for d in report.diagnostics if d.code == "GC301"] == ["body"]
    assert (report.robot.meshes_loaded, report.robot.meshes_total) == (1, 2)


def test_the_folder_beside_the_root_comes_before_a_folder_of_that_name_in_the_workspace(tmp_path: Path) -> None:
    """PyBullet's Panda names package://meshes/...: with --search over a workspace, the first
    folder called meshes there (another robot's) is not it; the one beside the file is."""
    from geomcheck.pipeline import run_check

    robot_dir, other = tmp_path / "panda", tmp_path / "ws" / "abb_description" / "meshes"
    (robot_dir / "meshes").mkdir(parents=True)
    other.mkdir(parents=True)
    trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(robot_dir / "meshes" / "box.stl")
    trimesh.creation.box(extents=(3.0, 2.0, 1.0)).export(other / "box.stl")
    root = robot_dir / "robot.urdf"
    root.write_text(
        '<robot name="r"><link name="body">'
        '<visual><geometry><mesh filename="package://meshes/box.stl"/></geometry></visual>'
        '<collision><geometry><box size="0.3 0.2 0.1"/></geometry></collision></link></robot>'
    )
    bundle = make_bundle(root, search=[tmp_path / "ws"], display_root=tmp_path)
    report = run_check(bundle, CheckOptions(sweep=False))
    [gc202] = [d for d in report.diagnostics if d.code == "GC202"]
    assert (gc202.data["kind"], gc202.data["folder"]) == ("package-beside-root", "panda/meshes")
    assert [d.code for d in report.diagnostics if d.code.startswith("GC3")] == []  # the 0.3 m box fits it


def winding_test_meshes(folder: Path) -> None:
    """A sphere wound consistently, the same with every other face flipped, and inside out."""
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.1)
    sphere.export(folder / "sphere.stl")
    mixed = sphere.faces.copy()
    mixed[::2] = mixed[::2, ::-1]
    trimesh.Trimesh(sphere.vertices, mixed, process=False).export(folder / "mixed.stl")
    trimesh.Trimesh(sphere.vertices, sphere.faces[:, ::-1], process=False).export(folder / "inside_out.stl")


def test_faces_wound_against_their_neighbours(bundle_dir: Path) -> None:
    winding_test_meshes(bundle_dir / "meshes")
    result, _ = check(bundle_dir, robot_of(link("ball", Mesh("package://bot/meshes/mixed.stl"), None)))
    d = only(result, "GC210")
    assert (d.link, d.about, d.severity) == ("ball", "visual[0]", Severity.WARNING)
    assert d.data["shared_edges"] == 480 and d.data["closed"] is True
    assert d.data["inconsistent_share"] >= 0.25
    assert d.message.startswith("visual[0] mesh mixed.stl has faces wound against their neighbours:")


def test_a_closed_mesh_inside_out(bundle_dir: Path) -> None:
    winding_test_meshes(bundle_dir / "meshes")
    result, _ = check(bundle_dir, robot_of(link("ball", Mesh("package://bot/meshes/inside_out.stl"), None)))
    d = only(result, "GC210")
    assert d.data["inconsistent_edges"] == 0 and d.data["signed_volume"] < 0
    assert "is inside out: closed and wound alike, it encloses a negative volume" in d.message
    result, _ = check(bundle_dir, robot_of(link("ball", Mesh("package://bot/meshes/sphere.stl"), None)))
    assert "GC210" not in [d.code for d in result.diagnostics]


def test_a_visual_drawing_the_collision_mesh_beside_its_visual_mesh(bundle_dir: Path) -> None:
    for folder in ("collision", "visual"):
        (bundle_dir / "meshes" / folder).mkdir()
        trimesh.creation.box(extents=BOX_SIZE).export(bundle_dir / "meshes" / folder / "link_2.stl")
    coarse = Mesh("package://bot/meshes/collision/link_2.stl")
    result, _ = check(bundle_dir, robot_of(link("arm", coarse)))
    d = only(result, "GC211")
    assert (d.link, d.about, d.severity) == ("arm", "visual[0]", Severity.WARNING)
    assert d.message == (
        "visual[0] draws link_2.stl from a collision folder, while the visual mesh "
        "package://bot/meshes/visual/link_2.stl lies beside it"
    )
    (bundle_dir / "meshes" / "visual" / "link_2.stl").unlink()
    result, _ = check(bundle_dir, robot_of(link("arm", coarse)))
    assert "GC211" not in [d.code for d in result.diagnostics]
