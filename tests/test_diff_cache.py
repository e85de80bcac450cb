"""``geomcheck diff --base REV``: the base revision's findings come from the cache when the
commit, the paths and the options are the same, and equal a fresh check."""

from __future__ import annotations

import logging
import re
import shutil
from dataclasses import replace
from pathlib import Path

import pytest

from geomcheck.cache import Store, using_store
from geomcheck.cli import main
from geomcheck.config import Config
from geomcheck.diff import check_base_revision
from geomcheck.diff_cache import NAMESPACE
from geomcheck.options import CheckOptions, Selection
from tests.gittools import git

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pr2_base"
ROOT_FILE = Path("pr2_base") / "robots" / "pr2_base.urdf.xacro"
OPTIONS = CheckOptions(sweep=False)


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The bundled example in a git repository (the cwd): the original, then a commit that
    shrinks the laser's collision box."""
    root = tmp_path / "repo"
    shutil.copytree(EXAMPLE, root / "pr2_base")
    git(root, "init", "-q", "-b", "main")
    git(root, "add", "-A")
    git(root, "commit", "-q", "-m", "example")
    laser = root / "pr2_base" / "urdf" / "laser.urdf.xacro"
    text, count = re.subn(
        r'<property name="laser_size_x" value="[^"]*" />',
        '<property name="laser_size_x" value="0.01" />',
        laser.read_text(),
    )
    assert count == 1
    laser.write_text(text)
    git(root, "commit", "-q", "-am", "shrink the laser box")
    monkeypatch.chdir(root)
    return root


def entries(store: Store) -> list[Path]:
    folder = store.root / NAMESPACE
    return sorted(p for p in folder.rglob("*") if p.is_file()) if folder.is_dir() else []


def base_side(store: Store | None, options: CheckOptions = OPTIONS, config: Config | None = None, rev: str = "HEAD~1"):  # type: ignore[no-untyped-def]
    with using_store(store):
        return check_base_revision(rev, ROOT_FILE, config or Config(), options)


def test_base_findings_are_cached_and_equal_a_fresh_check(repo: Path, tmp_path: Path) -> None:
    store = Store(tmp_path / "cache")
    fresh = base_side(None)
    cold = base_side(store)
    assert (store.hits, store.misses) == (0, 1)
    warm = base_side(store)
    assert (store.hits, store.misses) == (1, 1)
    assert fresh == cold == warm
    findings, label, note = warm
    assert findings and note is None and label.startswith("HEAD~1 (")
    assert {d.code for d in findings} >= {"GC103"}
    assert len(entries(store)) == 1
    assert sorted(p.name for p in store.root.iterdir()) == [NAMESPACE]  # the exported tree caches nothing


def test_options_and_commits_are_in_the_key(repo: Path, tmp_path: Path) -> None:
    store = Store(tmp_path / "cache")
    base_side(store)
    base_side(store, replace(OPTIONS, samples=77))
    thresholds = OPTIONS.thresholds.with_overrides({"fit": {"min_coverage": 0.5}})
    base_side(store, replace(OPTIONS, thresholds=thresholds))
    structure_only = base_side(store, replace(OPTIONS, selection=Selection(select=("GC1",))))
    base_side(store, rev="HEAD")
    assert store.hits == 0 and len(entries(store)) == 5
    assert structure_only[0] and {d.code[:3] for d in structure_only[0]} == {"GC1"}
    assert base_side(store, rev="HEAD~1") == base_side(None)
    assert store.hits == 1


def test_a_file_missing_at_the_base_is_cached_too(repo: Path, tmp_path: Path) -> None:
    shutil.copy(ROOT_FILE, ROOT_FILE.with_name("new.urdf.xacro"))
    store = Store(tmp_path / "cache")
    for _ in range(2):
        with using_store(store):
            assert check_base_revision("HEAD", ROOT_FILE.with_name("new.urdf.xacro"), Config(), OPTIONS)[0] is None
    assert (store.hits, store.misses) == (1, 1)


def test_packages_outside_the_repository_are_never_cached(repo: Path, tmp_path: Path) -> None:
    outside = tmp_path / "outside" / "pr2_base"
    shutil.copytree(repo / "pr2_base", outside)
    store = Store(tmp_path / "cache")
    config = Config(packages={"pr2_base_example": outside})
    first, second = base_side(store, config=config), base_side(store, config=config)
    assert first == second
    assert entries(store) == [] and (store.hits, store.misses) == (0, 0)


def test_a_corrupt_entry_is_recomputed_with_a_debug_line(
    repo: Path, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    store = Store(tmp_path / "cache")
    first = base_side(store)
    (entry,) = entries(store)
    entry.write_bytes(entry.read_bytes()[:-40])
    with caplog.at_level(logging.DEBUG, logger="geomcheck.cache"):
        assert base_side(store) == first
    assert [r.getMessage() for r in caplog.records] == [
        f"cache: entry {entry} is corrupt (payload digest mismatch); recomputing it"
    ]


def test_cli_diff_cached_equals_uncached(
    repo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("GEOMCHECK_CACHE_DIR", str(tmp_path / "cache"))
    command = ["diff", "--base", "HEAD~1", str(ROOT_FILE), "--format", "json", "--no-sweep"]
    outputs = []
    for extra in (["--no-cache"], [], []):
        assert main([*command, *extra]) == 0  # the smaller box is a warning
        outputs.append(capsys.readouterr().out)
    assert outputs[0] == outputs[1] == outputs[2]
    assert '"new": 1,' in outputs[0] and '"unchanged": 9' in outputs[0]
    assert len(entries(Store(tmp_path / "cache"))) == 1


def test_cli_diff_reads_an_unedited_head_back(
    repo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The working tree's check of ``diff --base`` comes from the whole check's cache while its
    files are as they were (the CI gate on every push of a pull request)."""
    import geomcheck.pipeline

    heads = []
    run_check = geomcheck.pipeline.run_check

    def counted(*args, **kwargs):  # type: ignore[no-untyped-def]
        heads.append(args[0].root_file.name)
        return run_check(*args, **kwargs)

    monkeypatch.setattr(geomcheck.pipeline, "run_check", counted)
    monkeypatch.setenv("GEOMCHECK_CACHE_DIR", str(tmp_path / "cache"))
    command = ["diff", "--base", "HEAD~1", str(ROOT_FILE), "--format", "json", "--no-sweep"]
    outputs = []
    for _ in range(2):
        assert main(command) == 0
        outputs.append(capsys.readouterr().out)
    assert heads == ["pr2_base.urdf.xacro"]  # the second run read the head back
    assert outputs[0] == outputs[1] and '"new": 1,' in outputs[0]
    (repo / "pr2_base" / "notes.txt").write_text("an edit beside the description")
    assert main(command) == 0
    assert heads == ["pr2_base.urdf.xacro"] * 2 and capsys.readouterr().out == outputs[0]
