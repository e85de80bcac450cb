"""A robot whose own package's meshes the upload lacks is not the robot uploaded: a tree
trimmed to an arm keeps the full robot's xacro, which still names the body's meshes. What a
robot reads is what it reads with its default arguments: accessories switched on by an
argument or an environment variable are not read."""

from __future__ import annotations

from pathlib import Path

from api.uploads.completeness import default_references, file_reads
from api.uploads.roots import choose, root_candidates
from api.uploads.xml_elements import parsed_root

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
PACKAGE_XML = "<package><name>legged_description</name></package>"


def write(folder: Path, rel: str, text: str | bytes) -> None:
    path = folder / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(text if isinstance(text, bytes) else text.encode())


def mesh(name: str) -> str:
    return f'<visual><geometry><mesh filename="package://legged_description/meshes/{name}"/></geometry></visual>'


def macro_file(name: str, meshes: list[str], extra: str = "") -> str:
    links = "".join(f'<link name="${{p}}{i}">{mesh(m)}</link>' for i, m in enumerate(meshes))
    return f'<robot {NS}><xacro:macro name="{name}" params="p">{links}{extra}</xacro:macro></robot>'


def trimmed_tree(folder: Path) -> Path:
    """Spot's shape: a body macro calling an arm macro, a full robot and a standalone arm, with
    only the arm's meshes in the tree; the body's lidar is switched on by an environment variable."""
    write(folder, "package.xml", PACKAGE_XML)
    lidar = f'<xacro:if value="$(optenv LIDAR 0)"><link name="lidar">{mesh("lidar.stl")}</link></xacro:if>'
    write(folder, "urdf/arm_macro.urdf", macro_file("arm", ["arm.stl", "gripper.stl"]))
    body = macro_file("body", ["body.stl", "leg.stl"], extra=f'{lidar}<xacro:arm p="a"/>')
    write(folder, "urdf/body_macro.xacro", body.replace("<xacro:macro", _include("arm_macro.urdf") + "<xacro:macro"))
    robot = f'<robot name="robot" {NS}>{_include("body_macro.xacro")}<xacro:body p="b"/></robot>'
    write(folder, "urdf/robot.urdf.xacro", robot)
    arm = f'<robot name="arm" {NS}>{_include("arm_macro.urdf")}<link name="root"/><xacro:arm p="a"/></robot>'
    write(folder, "urdf/standalone_arm.urdf.xacro", arm)
    for name in ("arm.stl", "gripper.stl"):
        write(folder, f"meshes/{name}", b"solid x\nendsolid x\n")
    return folder


def _include(name: str) -> str:
    return f'<xacro:include filename="$(find legged_description)/urdf/{name}"/>'


def test_a_robot_reads_its_macros_meshes_and_not_its_switched_off_accessories(tmp_path: Path) -> None:
    tree = trimmed_tree(tmp_path)
    texts = {p.relative_to(tree).as_posix(): p.read_bytes() for p in (tree / "urdf").iterdir()}
    reads = {rel: file_reads(parsed_root(text)) for rel, text in texts.items()}
    prefix = "package://legged_description/meshes/"
    assert default_references("urdf/robot.urdf.xacro", reads) == {
        prefix + name for name in ("body.stl", "leg.stl", "arm.stl", "gripper.stl")
    }
    assert default_references("urdf/standalone_arm.urdf.xacro", reads) == {prefix + "arm.stl", prefix + "gripper.stl"}


def test_the_robot_the_upload_holds_whole_is_chosen_over_the_one_including_it(tmp_path: Path) -> None:
    found = {c.path: c for c in root_candidates(trimmed_tree(tmp_path))}
    assert found["urdf/robot.urdf.xacro"].missing == (
        "package://legged_description/meshes/body.stl",
        "package://legged_description/meshes/leg.stl",
    )
    assert found["urdf/standalone_arm.urdf.xacro"].missing == ()
    # the arm is no sub-assembly of a robot whose files are not here
    assert found["urdf/standalone_arm.urdf.xacro"].dominated is False
    chosen = choose(root_candidates(tmp_path))
    assert chosen is not None and chosen.path == "urdf/standalone_arm.urdf.xacro"
    assert chosen.reason == (
        "the robot the upload holds whole: urdf/robot.urdf.xacro names 2 files of the upload's own packages that "
        "it lacks (package://legged_description/meshes/body.stl, ...)"
    )


def test_with_every_mesh_present_the_whole_robot_is_chosen(tmp_path: Path) -> None:
    tree = trimmed_tree(tmp_path)
    for name in ("body.stl", "leg.stl"):
        write(tree, f"meshes/{name}", b"solid x\nendsolid x\n")
    chosen = choose(root_candidates(tree))
    assert chosen is not None and chosen.path == "urdf/robot.urdf.xacro"
    assert chosen.reason.startswith("the whole robot: it includes what urdf/standalone_arm.urdf.xacro includes")


def test_a_package_the_upload_does_not_hold_and_a_built_path_count_for_nothing(tmp_path: Path) -> None:
    write(tmp_path, "package.xml", PACKAGE_XML)
    other = '<mesh filename="package://other_description/meshes/x.stl"/>'
    built = '<mesh filename="package://legged_description/meshes/${name}.stl"/>'
    write(
        tmp_path,
        "urdf/a.urdf",
        f'<robot name="a"><link name="l"><visual><geometry>{other}</geometry></visual>'
        f"<collision><geometry>{built}</geometry></collision></link></robot>",
    )
    (candidate,) = root_candidates(tmp_path)
    assert candidate.missing == ()
