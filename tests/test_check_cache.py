"""The whole check's cache (geomcheck.check_cache): a check of unedited files is read back, and
every edit a report could depend on (a mesh's bytes, a file appearing where the description
looks for one, a file added to the package, the environment) checks again."""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

from geomcheck.cache import open_store, using_store
from geomcheck.check_cache import NAMESPACE, VARIANTS_NAMESPACE, cached_check
from geomcheck.errors import InputError
from geomcheck.load import Bundle, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report import Report
from tests.packagetools import MESH_PACKAGE_ROOT, box_stl, mesh_package, write_package


class Checker:
    """``run_check`` counting its calls: a call is a miss of the cache."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self, bundle: Bundle, options: CheckOptions) -> Report:
        self.calls += 1
        return run_check(bundle, options)


@pytest.fixture
def package(tmp_path: Path) -> Path:
    return write_package(tmp_path / "robot", mesh_package())


def check(
    folder: Path, checker: Callable[[Bundle, CheckOptions], Report], cache: Path, options: CheckOptions | None = None
) -> Report:
    bundle = make_bundle(folder / MESH_PACKAGE_ROOT, display_root=folder)
    with using_store(open_store(cache)):
        return cached_check(bundle, options or CheckOptions(), checker)


def codes(report: Report) -> list[tuple[str, str]]:
    return [(d.code, d.subject) for d in report.diagnostics]


def test_an_unedited_check_is_read_back_with_the_same_report(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    first = check(package, checker, tmp_path / "cache")
    second = check(package, checker, tmp_path / "cache")
    assert checker.calls == 1
    assert ("GC303", "link arm") in codes(first) and codes(second) == codes(first)
    first_data, second_data = first.to_dict(), second.to_dict()
    first_data.pop("created"), second_data.pop("created")
    assert second_data == first_data
    assert (first.robot.meshes_total, first.robot.meshes_loaded) == (2, 2)


def test_a_touched_file_with_the_same_bytes_still_hits(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    check(package, checker, tmp_path / "cache")
    os.utime(package / "meshes/arm.stl", (1_000_000_000, 1_000_000_000))
    check(package, checker, tmp_path / "cache")
    assert checker.calls == 1


def test_a_mesh_edited_to_the_same_size_checks_again(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    first = check(package, checker, tmp_path / "cache")
    longer = box_stl((0.05, 0.05, 0.3))  # other coordinates, the same byte count
    assert len(longer) == (package / "meshes/arm.stl").stat().st_size
    (package / "meshes/arm.stl").write_bytes(longer)
    edited = check(package, checker, tmp_path / "cache")
    assert checker.calls == 2
    arm = [d.message for d in first.diagnostics if d.subject == "link arm"]
    assert arm and [d.message for d in edited.diagnostics if d.subject == "link arm"] != arm


def test_a_missing_mesh_that_appears_outside_the_root_folder_checks_again(package: Path, tmp_path: Path) -> None:
    # meshes/ lies beside urdf/, outside the root file's folder (no package.xml): the loader's
    # look for the file is what records it
    arm = (package / "meshes/arm.stl").read_bytes()
    (package / "meshes/arm.stl").unlink()
    checker = Checker()
    missing = check(package, checker, tmp_path / "cache")
    assert (missing.robot.meshes_total, missing.robot.meshes_loaded) == (2, 1)
    (package / "meshes/arm.stl").write_bytes(arm)
    found = check(package, checker, tmp_path / "cache")
    assert checker.calls == 2
    assert (found.robot.meshes_total, found.robot.meshes_loaded) == (2, 2)


def test_a_file_added_to_the_root_folder_checks_again(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    check(package, checker, tmp_path / "cache")
    (package / "urdf/notes.txt").write_text("a file no check reads", encoding="utf-8")
    check(package, checker, tmp_path / "cache")
    check(package, checker, tmp_path / "cache")
    assert checker.calls == 2  # the tree changed once


def test_the_same_files_in_another_folder_hit_the_same_entry(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    check(package, checker, tmp_path / "cache")
    moved = shutil.copytree(package, tmp_path / "checkout")
    report = check(moved, checker, tmp_path / "cache")
    assert checker.calls == 1
    assert report.robot.source == "urdf/boxed.urdf"


def test_other_options_are_another_entry(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    check(package, checker, tmp_path / "cache")
    seeded = check(package, checker, tmp_path / "cache", CheckOptions(seed=7))
    assert checker.calls == 2
    assert seeded.options["seed"] == 7


def test_a_check_without_drawings_is_another_entry_with_the_same_findings(package: Path, tmp_path: Path) -> None:
    """A CI gate's check draws nothing; a later check whose output shows drawings (JSON, HTML)
    is not read back from it, and both find the same."""
    checker = Checker()
    plain = check(package, checker, tmp_path / "cache", CheckOptions(drawings=False))
    drawn = check(package, checker, tmp_path / "cache")
    assert checker.calls == 2
    assert not {"views", "scene"} & set(plain.sections) and {"views", "scene"} <= set(drawn.sections)
    assert ("GC303", "link arm") in codes(plain) and codes(plain) == codes(drawn)
    assert plain.sections["links"] == drawn.sections["links"]


def test_an_expansion_that_reads_the_environment_is_keyed_by_the_values_it_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    folder = tmp_path / "robot"
    folder.mkdir()
    (folder / "robot.urdf.xacro").write_text(
        '<robot name="env" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<link name="$(optenv GEOMCHECK_TEST_LINK base)"/></robot>',
        encoding="utf-8",
    )
    checker = Checker()
    bundle = make_bundle(folder / "robot.urdf.xacro", display_root=folder)
    links = []
    with using_store(open_store(tmp_path / "cache")):
        for value in (None, None, "chassis", "chassis", None):
            if value is None:
                monkeypatch.delenv("GEOMCHECK_TEST_LINK", raising=False)
            else:
                monkeypatch.setenv("GEOMCHECK_TEST_LINK", value)
            report = cached_check(bundle, CheckOptions(), checker)
            links.append(report.sections["links"][0]["link"])
    assert links == ["base", "base", "chassis", "chassis", "base"]
    assert checker.calls == 2  # unset, then "chassis"; both read back after


def test_an_expansion_that_globs_its_includes_is_never_stored(tmp_path: Path) -> None:
    folder = tmp_path / "robot"
    (folder / "parts").mkdir(parents=True)
    (folder / "parts" / "base.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="base"/></robot>', encoding="utf-8"
    )
    (folder / "robot.urdf.xacro").write_text(
        '<robot name="globbed" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="parts/*.xacro"/></robot>',
        encoding="utf-8",
    )
    checker = Checker()
    bundle = make_bundle(folder / "robot.urdf.xacro", display_root=folder)
    with using_store(open_store(tmp_path / "cache")) as store:
        assert store is not None
        names = [cached_check(bundle, CheckOptions(), checker).robot.links for _ in range(2)]
        assert not (store.root / NAMESPACE).exists() and not (store.root / VARIANTS_NAMESPACE).exists()
    assert checker.calls == 2 and names == [1, 1]


def test_no_active_store_checks_every_time(package: Path) -> None:
    checker = Checker()
    bundle = make_bundle(package / MESH_PACKAGE_ROOT, display_root=package)
    for _ in range(2):
        cached_check(bundle, CheckOptions(), checker)
    assert checker.calls == 2


def test_the_cache_and_the_report_written_inside_the_package_are_not_edits(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    cache, output = package / "urdf" / ".geomcheck-cache", package / "urdf" / "report.json"
    bundle = make_bundle(package / MESH_PACKAGE_ROOT, display_root=package)
    with using_store(open_store(cache)):
        for size in (10, 2000):
            cached_check(bundle, CheckOptions(), checker, outputs=[output])
            output.write_text("x" * size, encoding="utf-8")
        # stored again with the cache's folder and the report already in the tree
        (package / "meshes/arm.stl").write_bytes(box_stl((0.05, 0.05, 0.3)))
        for size in (10, 2000):
            cached_check(bundle, CheckOptions(), checker, outputs=[output])
            output.write_text("x" * size, encoding="utf-8")
    assert checker.calls == 2


def test_a_mesh_too_large_to_read_is_looked_at_not_hashed(
    package: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import geomcheck.check_cache as check_cache
    from geomcheck.thresholds import LoadLimits, Thresholds

    hashed: list[str] = []
    sha256 = check_cache.file_sha256

    def recording(path: Path) -> str | None:
        hashed.append(path.name)
        return sha256(path)

    monkeypatch.setattr(check_cache, "file_sha256", recording)
    import trimesh

    # the base's mesh (a sphere of 80 triangles) is over the limit, the arm's (a box of 12) is
    # not: the loader refuses the base's after a stat, without reading it
    sphere = trimesh.creation.icosphere(subdivisions=1, radius=0.15).export(file_type="stl")
    (package / "meshes/base.stl").write_bytes(bytes(sphere))
    arm_size = (package / "meshes/arm.stl").stat().st_size
    options = CheckOptions(thresholds=Thresholds(limits=LoadLimits(max_mesh_bytes=arm_size)))
    checker = Checker()
    refused = check(package, checker, tmp_path / "cache", options)
    assert (refused.robot.meshes_total, refused.robot.meshes_loaded) == (2, 1)
    assert "arm.stl" in hashed and "base.stl" not in hashed
    check(package, checker, tmp_path / "cache", options)
    assert checker.calls == 1 and "base.stl" not in hashed
    (package / "meshes/base.stl").write_bytes(bytes(sphere) + b"\0")  # one byte longer
    check(package, checker, tmp_path / "cache", options)
    assert checker.calls == 2


def test_an_event_of_unexpected_shape_fails_nothing_and_is_not_stored(package: Path, tmp_path: Path) -> None:
    import sys

    checker = Checker()

    def odd(bundle: Bundle, options: CheckOptions) -> Report:
        sys.audit("open", "only-a-path")  # an "open" event without its mode and flags
        return checker(bundle, options)

    reports = [check(package, odd, tmp_path / "cache") for _ in range(2)]
    assert checker.calls == 2 and reports[0].robot.meshes_loaded == 2
    assert not (tmp_path / "cache" / NAMESPACE).exists()


def test_a_stored_entry_that_is_no_report_is_checked_again(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    first = check(package, checker, tmp_path / "cache")
    store = open_store(tmp_path / "cache")
    (entry,) = (store.root / NAMESPACE).glob("*/*")
    store.put_bytes(NAMESPACE, entry.name, b'{"robot": [], "diagnostics": 3}')  # a valid entry, not a report
    again = check(package, checker, tmp_path / "cache")
    assert checker.calls == 2 and codes(again) == codes(first)
    assert check(package, checker, tmp_path / "cache").robot == first.robot and checker.calls == 2


def test_a_mesh_edited_while_it_is_checked_is_not_stored(package: Path, tmp_path: Path) -> None:
    checker = Checker()

    def edited_midway(bundle: Bundle, options: CheckOptions) -> Report:
        report = checker(bundle, options)  # the arm's mesh was read as it was...
        (package / "meshes/arm.stl").write_bytes(box_stl((0.05, 0.05, 0.3)))  # ...then saved anew
        return report

    check(package, edited_midway, tmp_path / "cache")
    again = check(package, checker, tmp_path / "cache")  # not the report of the old mesh
    assert checker.calls == 2
    assert again.to_dict()["diagnostics"] != []


def test_packages_the_check_never_looked_into_are_not_watched(
    package: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import geomcheck.check_cache as check_cache

    # a workspace: the robot's package beside a large one it never uses
    (package / "package.xml").write_text("<package><name>boxed</name></package>", encoding="utf-8")
    other = tmp_path / "other_pkg"
    (other / "meshes").mkdir(parents=True)
    (other / "package.xml").write_text("<package><name>other</name></package>", encoding="utf-8")
    for k in range(60):
        (other / "meshes" / f"part{k}.stl").write_bytes(b"solid part\nendsolid part\n")
    monkeypatch.setattr(check_cache, "MAX_TREE_ENTRIES", 40)  # the robot's trees fit, the other package not
    checker = Checker()
    bundle = make_bundle(package / MESH_PACKAGE_ROOT, search=[tmp_path], display_root=tmp_path)
    assert set(bundle.packages) == {"boxed", "other"}
    with using_store(open_store(tmp_path / "cache")):
        for _ in range(2):
            cached_check(bundle, CheckOptions(), checker)
        (other / "meshes" / "part0.stl").write_bytes(b"solid edited\nendsolid edited\n")
        cached_check(bundle, CheckOptions(), checker)
    assert checker.calls == 1


def tetrahedron_stl(top: float) -> bytes:
    """A binary STL of a tetrahedron whose apex is ``top`` [m] above its base: the byte count
    never depends on ``top``."""
    import struct

    corners = ((0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.0, 0.0, top))
    faces = ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3))
    out = bytearray(b"\0" * 80 + struct.pack("<I", len(faces)))
    for face in faces:
        out += struct.pack("<12f", 0, 0, 0, *(c for i in face for c in corners[i])) + b"\0\0"
    return bytes(out)


MJCF_WITH_FILES_ONLY_MUJOCO_READS = """<mujoco model="m"><compiler meshdir="meshes"/>
  <asset><model name="hand" file="hand.xml"/></asset>
  <worldbody><body name="base"><geom type="box" size="0.1 0.1 0.1"/>
    <attach model="hand" body="palm" prefix="h_"/></body></worldbody></mujoco>
"""
HAND = """<mujoco><compiler meshdir="meshes"/><asset><mesh name="palm" file="palm.stl"/></asset>
  <worldbody><body name="palm" pos="0 0 0.2"><joint axis="0 1 0"/><geom type="mesh" mesh="palm"/></body></worldbody>
</mujoco>
"""


def test_a_file_mujoco_reads_edited_to_the_same_size_with_its_time_put_back_checks_again(tmp_path: Path) -> None:
    # the palm's mesh is read for MuJoCo only when the structure family alone runs (was: only its
    # size was recorded, and the old report came back)
    from geomcheck.options import Selection

    folder = tmp_path / "robot"
    write_package(
        folder,
        {
            "robot.xml": MJCF_WITH_FILES_ONLY_MUJOCO_READS.encode(),
            "hand.xml": HAND.encode(),
            "meshes/palm.stl": tetrahedron_stl(0.1),
        },
    )
    mesh = folder / "meshes" / "palm.stl"
    stamp = mesh.stat()
    options = CheckOptions(selection=Selection(select=("GC1",)))
    checker = Checker()
    bundle = make_bundle(folder / "robot.xml", display_root=folder)
    with using_store(open_store(tmp_path / "cache")) as store:
        assert store is not None
        first = cached_check(bundle, options, checker)
        assert first.robot.meshes_loaded == 0  # geomcheck's mesh store read nothing: MuJoCo's copy did
        (variants,) = (store.root / VARIANTS_NAMESPACE).glob("*/*")
        assert "meshes/palm.stl" in variants.read_text(errors="replace")
        cached_check(bundle, options, checker)
        assert checker.calls == 1
        mesh.write_bytes(tetrahedron_stl(0.0))  # flat: MuJoCo refuses a mesh of no volume
        os.utime(mesh, ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
        assert mesh.stat().st_size == stamp.st_size
        with pytest.raises(InputError, match=r"MuJoCo's compiler rejects the model: .*h_palm"):
            cached_check(bundle, options, checker)
    assert checker.calls == 2


def test_a_description_in_the_python_environments_prefix_is_hashed(
    package: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import sys

    # the package lies under the interpreter's prefix, as a description installed with pip or
    # conda does (was: never hashed, and an edit returned the old report)
    monkeypatch.setattr(sys, "prefix", str(package.parent))
    checker = Checker()
    first = check(package, checker, tmp_path / "cache")
    check(package, checker, tmp_path / "cache")
    assert checker.calls == 1
    urdf = package / MESH_PACKAGE_ROOT
    urdf.write_text(urdf.read_text().replace('<box size="0.3 0.3 0.1"/>', '<box size="0.3 0.3 0.2"/>'))
    edited = check(package, checker, tmp_path / "cache")
    assert checker.calls == 2
    assert ("GC301", "link base_link") in codes(first) and ("GC301", "link base_link") not in codes(edited)


def test_a_mesh_edited_while_checked_with_its_time_put_back_is_not_stored(package: Path, tmp_path: Path) -> None:
    checker = Checker()
    mesh = package / "meshes/arm.stl"
    stamp = mesh.stat()

    def edited_midway(bundle: Bundle, options: CheckOptions) -> Report:
        report = checker(bundle, options)  # the arm's mesh was read as it was...
        mesh.write_bytes(box_stl((0.05, 0.05, 0.3)))  # ...then saved anew, the same size and time
        os.utime(mesh, ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
        return report

    first = check(package, edited_midway, tmp_path / "cache")
    again = check(package, checker, tmp_path / "cache")  # was: the old report, stored under the new bytes
    assert checker.calls == 2
    arm = [d.message for d in first.diagnostics if d.subject == "link arm"]
    assert arm and [d.message for d in again.diagnostics if d.subject == "link arm"] != arm


def test_an_expansion_that_reads_its_folder_is_keyed_by_the_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    text = (
        '<robot name="where" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        "<xacro:if value=\"${'$(cwd)'.endswith('left')}\"><link name=\"left_base\"/></xacro:if>"
        "<xacro:unless value=\"${'$(cwd)'.endswith('left')}\"><link name=\"other_base\"/></xacro:unless></robot>"
    )
    links = []
    checker = Checker()
    for name in ("left", "right", "left"):
        folder = tmp_path / name
        folder.mkdir(exist_ok=True)
        (folder / "robot.urdf.xacro").write_text(text, encoding="utf-8")
        monkeypatch.chdir(folder)
        bundle = make_bundle(folder / "robot.urdf.xacro", display_root=folder)
        with using_store(open_store(tmp_path / "cache")):
            links.append(cached_check(bundle, CheckOptions(), checker).sections["links"][0]["link"])
    # was: the left folder's report in the right one (the same files, relative to their folder)
    assert links == ["left_base", "other_base", "left_base"]
    assert checker.calls == 2
