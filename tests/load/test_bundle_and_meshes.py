"""Bundles (package discovery, folder-name fallback) and mesh loading (formats, scale, read once)."""

from __future__ import annotations

import builtins
from pathlib import Path

import pytest
import trimesh

from geomcheck.load import LoadedMesh, MeshProblem, MeshStore, make_bundle
from geomcheck.model import Mesh


def make_package(root: Path, folder: str, manifest: str | None = "package.xml", name: str | None = None) -> Path:
    directory = root / folder
    (directory / "meshes").mkdir(parents=True)
    if manifest == "package.xml":
        (directory / manifest).write_text(f"<package><name>{name or folder}</name></package>")
    elif manifest:
        (directory / manifest).write_text("<package/>")
    trimesh.creation.box(extents=(1.0, 2.0, 3.0)).export(directory / "meshes" / "box.stl")
    return directory


def test_discovery_by_package_xml_and_manifest(tmp_path: Path) -> None:
    make_package(tmp_path / "src", "a_dir", name="alpha")
    make_package(tmp_path / "src", "legacy_pkg", manifest="manifest.xml")
    root = tmp_path / "r.urdf"
    root.write_text("<robot name='r'/>")
    bundle = make_bundle(root, search=[tmp_path / "src"])
    assert sorted(bundle.packages) == ["alpha", "legacy_pkg"]
    assert bundle.package_dir("alpha") == (tmp_path / "src" / "a_dir").resolve()


def test_explicit_package_wins(tmp_path: Path) -> None:
    make_package(tmp_path / "src", "alpha")
    other = make_package(tmp_path, "elsewhere")
    root = tmp_path / "r.urdf"
    root.write_text("<robot name='r'/>")
    bundle = make_bundle(root, {"alpha": other}, search=[tmp_path / "src"])
    assert bundle.package_dir("alpha") == other.resolve()


def test_folder_named_like_the_package_is_the_fallback(tmp_path: Path) -> None:
    data = make_package(tmp_path / "corpus", "robot-data", manifest=None)
    root = data / "urdf" / "r.urdf"
    root.parent.mkdir()
    root.write_text("<robot name='r'/>")
    # found as an ancestor of the root file, and under a search root
    assert make_bundle(root).package_dir("robot-data") == data.resolve()
    assert make_bundle(root, search=[tmp_path / "corpus"]).package_dir("robot-data") == data.resolve()
    assert make_bundle(root).package_dir("unknown") is None
    store = MeshStore(make_bundle(root))
    assert isinstance(store.get(Mesh("package://robot-data/meshes/box.stl")), LoadedMesh)


def test_fallback_stays_inside_a_confined_bundle(tmp_path: Path) -> None:
    outer = tmp_path / "robot-data"
    upload = outer / "upload"
    upload.mkdir(parents=True)
    root = upload / "r.urdf"
    root.write_text("<robot name='r'/>")
    assert make_bundle(root, display_root=upload, confined=True).package_dir("robot-data") is None


def test_mesh_is_read_once_and_scaled(tmp_path: Path) -> None:
    make_package(tmp_path, "pkg")
    root = tmp_path / "r.urdf"
    root.write_text("<robot name='r'/>")
    store = MeshStore(make_bundle(root, search=[tmp_path]))
    plain = store.get(Mesh("package://pkg/meshes/box.stl"))
    scaled = store.get(Mesh("package://pkg/meshes/box.stl", (0.001, 0.001, 0.001)))
    relative = store.get(Mesh("pkg/meshes/box.stl"))
    assert isinstance(plain, LoadedMesh) and isinstance(scaled, LoadedMesh) and isinstance(relative, LoadedMesh)
    assert plain.mesh.extents == pytest.approx((1, 2, 3))
    assert scaled.mesh.extents == pytest.approx((0.001, 0.002, 0.003))
    assert store.files_read == 1


def test_textured_obj_loads_without_pillow(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    obj = tmp_path / "quad.obj"
    obj.write_text(
        "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "usemtl skin\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"
    )
    real_import = builtins.__import__

    def no_pil(name: str, *args, **kwargs):  # type: ignore[no-untyped-def]
        if name == "PIL" or name.startswith("PIL."):
            raise ModuleNotFoundError("No module named 'PIL'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pil)
    root = tmp_path / "r.urdf"
    root.write_text("<robot name='r'/>")
    result = MeshStore(make_bundle(root)).get(Mesh("quad.obj", (2.0, 2.0, 2.0)))
    assert isinstance(result, LoadedMesh), result
    assert len(result.mesh.faces) == 2
    assert result.mesh.extents[:2] == pytest.approx((2, 2))


def test_missing_mesh_and_unknown_package_are_problems(tmp_path: Path) -> None:
    root = tmp_path / "r.urdf"
    root.write_text("<robot name='r'/>")
    store = MeshStore(make_bundle(root))
    missing = store.get(Mesh("meshes/none.stl"))
    unknown = store.get(Mesh("package://nowhere/x.stl"))
    assert isinstance(missing, MeshProblem) and missing.kind == "missing-file"
    assert isinstance(unknown, MeshProblem) and unknown.kind == "unresolved-package"
    assert store.files_read == 0


def test_missing_package_points_at_a_mesh_of_the_same_name(tmp_path: Path) -> None:
    pkg = tmp_path / "new_pkg"
    (pkg / "meshes" / "arm").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>new_pkg</name></package>")
    trimesh.creation.box().export(pkg / "meshes" / "arm" / "finger.stl")
    root = pkg / "robot.urdf"
    root.write_text("<robot name='r'/>")
    store = MeshStore(make_bundle(root, display_root=tmp_path))
    problem = store.get(Mesh("package://old_pkg/meshes/finger.stl"))
    assert isinstance(problem, MeshProblem)
    assert problem.kind == "unresolved-package"
    assert problem.alternative == "package://new_pkg/meshes/arm/finger.stl"
    assert problem.message.endswith("a file of that name exists at package://new_pkg/meshes/arm/finger.stl")
    unrelated = store.get(Mesh("package://new_pkg/meshes/other.stl"))
    assert isinstance(unrelated, MeshProblem)
    assert unrelated.alternative is None


def test_missing_relative_mesh_points_at_a_file_of_its_name_under_the_root_folder(tmp_path: Path) -> None:
    # a package that moved its meshes from meshes/ to assets/ and kept the URDF's references
    (tmp_path / "assets").mkdir()
    trimesh.creation.box().export(tmp_path / "assets" / "Leg.STL")
    root = tmp_path / "robot.urdf"
    root.write_text("<robot name='r'/>")
    store = MeshStore(make_bundle(root, display_root=tmp_path))
    problem = store.get(Mesh("meshes/leg.stl"))
    assert isinstance(problem, MeshProblem) and problem.kind == "missing-file"
    assert problem.alternative == "assets/Leg.STL"  # relative to the root file, as the reference is
    assert problem.message.endswith("a file of that name exists at assets/Leg.STL")
    # a leading slash one too many: the path as written, and the file relative to the root file
    slashed = store.get(Mesh("/assets/Leg.STL"))
    assert isinstance(slashed, MeshProblem) and slashed.kind == "missing-file"
    assert slashed.message == (
        "mesh file not found: /assets/Leg.STL (an absolute path); a file of that name exists at assets/Leg.STL"
    )
    # a package:// reference is not answered with a path relative to the root file
    unknown = store.get(Mesh("package://gone/meshes/leg.stl"))
    assert isinstance(unknown, MeshProblem) and unknown.alternative is None
