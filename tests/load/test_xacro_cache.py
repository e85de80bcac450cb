"""The xacro expansion cache: a hit exactly when every file read (and every package found)
is as it was; results equal to an uncached expansion on every corpus robot."""

from __future__ import annotations

import dataclasses
import json
import logging
import shutil
from pathlib import Path

import pytest

from geomcheck.cache import Store, using_store
from geomcheck.check_cache import VARIANTS_NAMESPACE as CHECK_VARIANTS
from geomcheck.cli import main
from geomcheck.errors import InputError
from geomcheck.load import Bundle, ExpandedDocument, LoadedDescription, load_description, make_bundle
from geomcheck.load.xacro_cache import NAMESPACE, VARIANTS_NAMESPACE

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base"
NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def entries(store: Store, namespace: str) -> list[Path]:
    folder = store.root / namespace
    return sorted(folder.rglob("*")) if folder.is_dir() else []


def files(store: Store, namespace: str) -> list[Path]:
    return [p for p in entries(store, namespace) if p.is_file()]


def load(root: Path, store: Store | None, **args: str) -> LoadedDescription:
    with using_store(store):
        return load_description(make_bundle(root, display_root=root.parent), args)


def same_load(a: LoadedDescription, b: LoadedDescription) -> bool:
    return a.robot == b.robot and a.document == b.document and a.diagnostics == b.diagnostics


@pytest.fixture
def example(tmp_path: Path) -> Path:
    shutil.copytree(EXAMPLE, tmp_path / "pr2_base")
    return tmp_path / "pr2_base" / "robots" / "pr2_base.urdf.xacro"


def test_warm_expansion_equals_the_uncached_one(example: Path, tmp_path: Path) -> None:
    store = Store(tmp_path / "cache")
    uncached = load(example, None)
    cold = load(example, store)
    assert (store.hits, store.misses) == (0, 1)  # no variants yet
    warm = load(example, store)
    assert (store.hits, store.misses) == (2, 1)  # the variants, then the expansion
    assert same_load(uncached, cold) and same_load(uncached, warm)
    assert {d.code for d in warm.diagnostics} == {"GC103"}  # the legacy-syntax findings come from the cache too
    assert len(files(store, NAMESPACE)) == 1
    variants = json.loads(files(store, VARIANTS_NAMESPACE)[0].read_bytes().partition(b"\n")[2])
    read = {Path(p).name for p in variants[0]["files"]}
    assert read == {
        "pr2_base.urdf.xacro",
        "common.xacro",
        "materials.urdf.xacro",
        "base.urdf.xacro",
        "laser.urdf.xacro",
    }
    # paths relative to the display root (the robots folder): the entry serves a copy elsewhere
    assert variants[0]["packages"] == {"pr2_base_example": ".."}
    assert "../urdf/laser.urdf.xacro" in variants[0]["files"] and variants[0]["at"] is None


def test_a_copy_in_another_folder_hits_the_same_entry(example: Path, tmp_path: Path) -> None:
    store = Store(tmp_path / "cache")
    first = load(example, store)
    other = tmp_path / "upload-2"
    shutil.copytree(example.parents[1], other / "pr2_base")
    copy = other / "pr2_base" / "robots" / "pr2_base.urdf.xacro"
    hits = store.hits
    warm = load(copy, store)
    assert store.hits == hits + 2 and len(files(store, NAMESPACE)) == 1
    assert same_load(warm, load(copy, None)) and same_load(warm, first)


def test_an_expansion_naming_its_absolute_folder_holds_only_there(tmp_path: Path) -> None:
    for name in ("a", "b"):
        package = tmp_path / name / "arm"
        (package / "meshes").mkdir(parents=True)
        (package / "package.xml").write_text("<package><name>arm</name></package>")
        (package / "arm.urdf.xacro").write_text(
            f'<robot name="r" {NS}><link name="base"><visual><geometry>'
            '<mesh filename="$(find arm)/meshes/base.stl"/></geometry></visual></link></robot>'
        )
    store = Store(tmp_path / "cache")
    loads = {}
    for name in ("a", "b"):
        root = tmp_path / name / "arm" / "arm.urdf.xacro"
        with using_store(store):
            loads[name] = load_description(make_bundle(root, search=[root.parent], display_root=root.parent))
    meshes = {name: loaded.robot.links[0].visuals[0].geometry.filename for name, loaded in loads.items()}
    assert meshes == {name: f"{tmp_path / name / 'arm'}/meshes/base.stl" for name in ("a", "b")}
    assert len(files(store, NAMESPACE)) == 2  # the second folder expanded anew
    variants = json.loads(files(store, VARIANTS_NAMESPACE)[0].read_bytes().partition(b"\n")[2])
    assert [v["at"] for v in variants] == [str(tmp_path / "b" / "arm"), str(tmp_path / "a" / "arm")]


def test_editing_an_included_file_expands_again_and_going_back_hits(example: Path, tmp_path: Path) -> None:
    store = Store(tmp_path / "cache")
    original = load(example, store)
    laser = example.parents[1] / "urdf" / "laser.urdf.xacro"
    text = laser.read_text()
    assert 'name="${name}_link"' in text
    laser.write_text(text.replace('name="${name}_link"', 'name="${name}_link_renamed"'))
    edited = load(example, store)
    assert "base_laser_link_renamed" in edited.robot.link_map
    assert "base_laser_link" not in edited.robot.link_map
    assert same_load(edited, load(example, None))
    assert len(files(store, NAMESPACE)) == 2
    laser.write_text(text)  # back to the first version: its entry is still there
    hits = store.hits
    again = load(example, store)
    assert same_load(again, original)
    assert store.hits == hits + 2 and len(files(store, NAMESPACE)) == 2


def test_args_are_in_the_key(tmp_path: Path) -> None:
    root = tmp_path / "arm.urdf.xacro"
    root.write_text(f'<robot name="arm" {NS}><xacro:arg name="n" default="a"/><link name="link_$(arg n)"/></robot>')
    store = Store(tmp_path / "cache")
    assert [link.name for link in load(root, store).robot.links] == ["link_a"]
    assert [link.name for link in load(root, store, n="b").robot.links] == ["link_b"]
    assert [link.name for link in load(root, store).robot.links] == ["link_a"]
    assert len(files(store, NAMESPACE)) == 2


def test_an_optional_include_that_appears_is_read(tmp_path: Path) -> None:
    root = tmp_path / "robot.urdf.xacro"
    root.write_text(
        f'<robot name="r" {NS}><link name="base"/><xacro:include filename="extra.xacro" optional="true"/></robot>'
    )
    store = Store(tmp_path / "cache")
    assert [link.name for link in load(root, store).robot.links] == ["base"]
    (tmp_path / "extra.xacro").write_text(f'<robot {NS}><link name="extra"/></robot>')
    assert [link.name for link in load(root, store).robot.links] == ["base", "extra"]


@pytest.mark.parametrize(
    "include",
    [
        pytest.param('<link name="$(env GEOMCHECK_TEST_LINK)"/>', id="env"),
        pytest.param('<link name="$(optenv GEOMCHECK_TEST_LINK fallback)"/>', id="optenv"),
        pytest.param('<xacro:include filename="parts/*.xacro"/>', id="glob"),
    ],
)
def test_volatile_expansions_are_never_stored(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, include: str) -> None:
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "a.xacro").write_text(f'<robot {NS}><link name="part_a"/></robot>')
    root = tmp_path / "robot.urdf.xacro"
    root.write_text(f'<robot name="r" {NS}><link name="base"/>{include}</robot>')
    store = Store(tmp_path / "cache")
    monkeypatch.setenv("GEOMCHECK_TEST_LINK", "first")
    first = [link.name for link in load(root, store).robot.links]
    monkeypatch.setenv("GEOMCHECK_TEST_LINK", "second")
    (tmp_path / "parts" / "b.xacro").write_text(f'<robot {NS}><link name="part_b"/></robot>')
    second = [link.name for link in load(root, store).robot.links]
    assert first != second
    assert files(store, NAMESPACE) == [] and files(store, VARIANTS_NAMESPACE) == []


def test_a_corrupt_expansion_is_recomputed_with_a_debug_line(
    example: Path, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    store = Store(tmp_path / "cache")
    first = load(example, store)
    (entry,) = files(store, NAMESPACE)
    raw = bytearray(entry.read_bytes())
    raw[len(raw) // 2] ^= 0x20  # one bit of the stored document
    entry.write_bytes(bytes(raw))
    with caplog.at_level(logging.DEBUG, logger="geomcheck.cache"):
        again = load(example, store)
    assert same_load(first, again)
    messages = [r.getMessage() for r in caplog.records if r.name == "geomcheck.cache"]
    assert messages == [f"cache: entry {entry} is corrupt (payload digest mismatch); recomputing it"]
    assert load(example, store).document == first.document  # and stored again, verified


def outcome(bundle: Bundle) -> tuple[object, ...]:
    """What loading ``bundle`` gives: the robot, document and findings, or the error."""
    try:
        loaded = load_description(bundle)
    except InputError as err:
        return ("error", str(err))
    return (loaded.robot, loaded.document, loaded.diagnostics)


@pytest.mark.corpus
def test_every_corpus_robot_loads_the_same_cached(corpus: Path, tmp_path: Path) -> None:
    roots = sorted(corpus.glob("pr2_2009/pr2_description/robots/*.urdf.xacro")) + sorted(
        corpus.glob("example-robot-data/robots/*/*/*.urdf")
    )
    assert len(roots) >= 20
    store = Store(tmp_path / "cache")
    expanded = 0
    for root in roots:
        bundle = make_bundle(root, search=[corpus / "pr2_2009"], display_root=corpus)
        uncached = outcome(bundle)
        with using_store(store):
            cold, warm = outcome(bundle), outcome(bundle)
        assert uncached == cold == warm, root
        document = uncached[1]
        expanded += isinstance(document, ExpandedDocument) and document.is_xacro
    assert expanded >= 9
    assert len(files(store, NAMESPACE)) == expanded  # one entry each; failed expansions are not stored


@pytest.mark.corpus
def test_full_pr2_report_cached_equals_uncached(
    pr2_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("GEOMCHECK_CACHE_DIR", str(tmp_path / "cache"))
    root = pr2_root / "pr2_description" / "robots" / "pr2.urdf.xacro"
    command = ["check", str(root), "--search", str(pr2_root), "--format", "json", "--exit-zero"]
    reports = []
    for extra in (["--no-cache"], [], []):  # uncached, cold, warm
        assert main([*command, *extra]) == 0
        reports.append(capsys.readouterr().out)
    assert reports[0] == reports[1] == reports[2]
    report = json.loads(reports[2])
    assert report["robot"]["links"] == 72 and report["summary"]["error"] > 0
    assert len(files(Store(tmp_path / "cache"), NAMESPACE)) == 1


def test_cli_shows_the_corrupt_entry_with_geomcheck_debug(
    example: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("GEOMCHECK_CACHE_DIR", str(tmp_path / "cache"))
    command = ["check", str(example), "--select", "GC1", "--format", "concise", "--exit-zero", "--no-sweep"]
    assert main(command) == 0
    first = capsys.readouterr().out
    (entry,) = files(Store(tmp_path / "cache"), NAMESPACE)
    entry.write_bytes(entry.read_bytes().replace(b"base_laser", b"base_LASER", 1))
    # the whole report would be read back (geomcheck.check_cache): the expansion is looked up
    # once that cache forgets it
    shutil.rmtree(tmp_path / "cache" / CHECK_VARIANTS)
    monkeypatch.setenv("GEOMCHECK_DEBUG", "1")
    assert main(command) == 0
    captured = capsys.readouterr()
    assert captured.out == first
    assert (
        captured.err == f"geomcheck: debug: cache: entry {entry} is corrupt (payload digest mismatch); recomputing it\n"
    )
    assert main([*command, "--no-cache"]) == 0
    assert capsys.readouterr().out == first


def test_confinement_and_allowed_variables_are_in_the_key(tmp_path: Path) -> None:
    """A confined (upload, untrusted CI) expansion never reuses an unconfined one, nor one
    made with other variables allowed, and the other way round: they differ ($(find) gives
    the machine's folder only to trusted runs; $(env) reads only allowed variables)."""
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "package.xml").write_text("<package><name>pkg</name></package>")
    root = tmp_path / "r.urdf.xacro"
    root.write_text(f'<robot name="r" {NS}><link name="base"/><link name="in_$(find pkg)"/></robot>')
    store = Store(tmp_path / "cache")
    trusted = make_bundle(root, search=[tmp_path], display_root=tmp_path)
    confined = make_bundle(root, search=[tmp_path], display_root=tmp_path, confined=True)
    allowing = dataclasses.replace(confined, allowed_env=frozenset({"HOME"}))
    names = []
    for bundle in (trusted, confined, allowing, trusted, confined, allowing):
        with using_store(store):
            names.append(load_description(bundle).robot.links[1].name)
    assert names == [f"in_{tmp_path / 'pkg'}", "in_pkg", "in_pkg"] * 2
    assert (store.misses, len(files(store, NAMESPACE))) == (3, 3)  # one expansion each, then three hits


def test_a_confined_upload_with_find_is_reused_in_another_folder(tmp_path: Path) -> None:
    """An upload's ``$(find)`` paths are written relative to its root file: nothing absolute
    in the output, so the service's next folder with the same files hits."""
    store = Store(tmp_path / "cache")
    loads = []
    for name in ("upload-1", "upload-2"):
        package = tmp_path / name / "arm"
        package.mkdir(parents=True)
        (package / "package.xml").write_text("<package><name>arm</name></package>")
        root = package / "arm.urdf.xacro"
        root.write_text(
            f'<robot name="r" {NS}><link name="base"><visual><geometry>'
            '<mesh filename="$(find arm)/meshes/base.stl"/></geometry></visual></link></robot>'
        )
        with using_store(store):
            bundle = make_bundle(root, search=[package], display_root=package, confined=True)
            loads.append(load_description(bundle))
    assert [loaded.robot.links[0].visuals[0].geometry.filename for loaded in loads] == ["./meshes/base.stl"] * 2
    assert len(files(store, NAMESPACE)) == 1 and store.hits == 2
