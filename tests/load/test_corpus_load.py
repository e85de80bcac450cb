"""The real robots of the shared corpus: the 2009 PR2 (legacy xacro) and example-robot-data."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.load import LoadedDescription, LoadedMesh, MeshProblem, MeshStore, load_description, make_bundle
from geomcheck.model import Mesh

pytestmark = pytest.mark.corpus

PR2_LEGACY_FILES = {
    "robots/pr2.urdf.xacro",
    "urdf/common.xacro",
    "urdf/base_v0/base.urdf.xacro",
    "urdf/shoulder_v0/shoulder.urdf.xacro",
    "urdf/upper_arm_v0/upper_arm.urdf.xacro",
    "urdf/gripper_v0/gripper.urdf.xacro",
    "urdf/head_v0/head.urdf.xacro",
    "urdf/torso_v0/torso.urdf.xacro",
}


def mesh_results(loaded: LoadedDescription) -> dict[str, LoadedMesh | MeshProblem]:
    store = MeshStore(loaded.bundle)
    return {
        shape.geometry.filename: store.get(shape.geometry)
        for link in loaded.robot.links
        for shape in (*link.visuals, *link.collisions)
        if isinstance(shape.geometry, Mesh)
    }


def pr2(pr2_root: Path, robot: str) -> LoadedDescription:
    root = pr2_root / "pr2_description" / "robots" / robot
    return load_description(make_bundle(root, search=[pr2_root], display_root=pr2_root / "pr2_description"))


def test_full_pr2_loads_with_legacy_warnings_per_file(pr2_root: Path) -> None:
    loaded = pr2(pr2_root, "pr2.urdf.xacro")
    robot = loaded.robot
    assert (len(robot.links), len(robot.joints)) == (72, 74)
    assert robot.name == "pr2"
    legacy = {d.location.file: d for d in loaded.diagnostics if d.code == "GC103"}
    assert set(legacy) >= PR2_LEGACY_FILES
    assert all(d.location.file in d.message and d.location.line for d in legacy.values())
    assert legacy["urdf/common.xacro"].message == (
        "legacy xacro syntax in urdf/common.xacro: <property> x40; no xmlns:xacro declaration"
    )
    assert "xmlns:xacro is bound to 'http://playerstage" in legacy["robots/pr2.urdf.xacro"].message
    # no other load-time finding: the 2009 URDF is clean apart from its legacy syntax
    assert {d.code for d in loaded.diagnostics} == {"GC103"}
    wheel = robot.link_map["fl_caster_l_wheel_link"]
    assert wheel.inertial is not None and wheel.inertial.mass == pytest.approx(0.44036)
    assert wheel.location is not None
    assert (wheel.location.file, wheel.location.line) == ("urdf/base_v0/base.urdf.xacro", 59)
    assert robot.joint_map["base_joint"].parent == "world"
    assert (robot.joint_map["r_gripper_joint"].parent, robot.joint_map["r_gripper_joint"].child) == ("", "")


def test_full_pr2_meshes_load_when_the_files_exist(pr2_root: Path) -> None:
    loaded = pr2(pr2_root, "pr2.urdf.xacro")
    results = mesh_results(loaded)
    assert len(results) == 32
    loaded_files = [f for f, r in results.items() if isinstance(r, LoadedMesh)]
    assert len(loaded_files) == 22
    # the 6 convex .stlb files its build generated are absent, and stand in as their sources
    stand_ins = {f: r for f, r in results.items() if isinstance(r, LoadedMesh) and r.stands_for is not None}
    assert len(stand_ins) == 6 and all(f.endswith("_convex.stlb") for f in stand_ins)
    assert all(r.path.endswith(".stl") and (pr2_root / "pr2_description" / r.path).exists() for r in stand_ins.values())
    # every mesh that does not load is absent from the 2009 package: pr2_defs (the package's pre-rename name)
    for filename, result in results.items():
        if isinstance(result, MeshProblem):
            assert "package://pr2_defs/" in filename, filename
            assert result.path is None


def test_pr2_base_loads_with_all_meshes(pr2_root: Path) -> None:
    loaded = pr2(pr2_root, "pr2_base.urdf.xacro")
    assert len(loaded.robot.links) == 14
    assert {f for f, r in mesh_results(loaded).items() if isinstance(r, LoadedMesh)} == {
        "package://pr2_description/meshes/base_v0/base.stl",
        "package://pr2_description/meshes/base_v0/caster.stl",
        "package://pr2_description/meshes/base_v0/pr2_wheel.stl",
    }
    legacy = {d.location.file for d in loaded.diagnostics if d.code == "GC103"}
    assert legacy == {
        "robots/pr2_base.urdf.xacro",
        "urdf/common.xacro",
        "urdf/base_v0/base.urdf.xacro",
        "urdf/sensors/hokuyo_lx30_laser.urdf.xacro",
    }


def erd_urdfs(erd_root: Path) -> list[Path]:
    return sorted((erd_root / "robots").rglob("*.urdf"))


@pytest.mark.parametrize("how", ["package", "search"])
def test_every_example_robot_data_urdf_loads_with_all_meshes(erd_root: Path, how: str) -> None:
    files = erd_urdfs(erd_root)
    assert len(files) >= 10
    for path in files:
        if how == "package":
            bundle = make_bundle(path, {"example-robot-data": erd_root})
        else:
            bundle = make_bundle(path, search=[erd_root])
        loaded = load_description(bundle)
        assert loaded.robot.links, path
        results = mesh_results(loaded)
        problems = {f: r.message for f, r in results.items() if isinstance(r, MeshProblem)}
        assert problems == {}, path
        assert not [d for d in loaded.diagnostics if d.severity.value == "error"], path
