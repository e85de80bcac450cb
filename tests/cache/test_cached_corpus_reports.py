"""Every corpus robot's report, checked with the stage caches cold and then warm, equals the
report checked without them (reports as scripts/golden.py normalises them). The uncached
report is the session's shared one (``corpus_reports``). The default run takes the first robot
of each kind; ``pytest -m campaign`` every robot."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from geomcheck.cache import open_store, using_store
from tests.corpus_robots import robot_params
from tests.corpustools import CorpusReports
from tests.goldentools import golden_script

REPO = Path(__file__).resolve().parents[2]


golden = golden_script()


def cached_twice(robot: Any, tmp_path: Path) -> tuple[dict[str, Any], dict[str, Any], Any]:
    store = open_store(tmp_path / "cache")
    with using_store(store):
        cold = golden.normalised_report(robot)
        warm = golden.normalised_report(robot)
    return cold, warm, store


def assert_same(key: str, uncached: dict[str, Any], cached: dict[str, Any]) -> None:
    assert golden.differences(key, golden.summary(uncached), cached) == []
    assert cached == uncached


def test_the_example_cached_equals_uncached(tmp_path: Path) -> None:
    (example,) = golden.robots(None)
    uncached = golden.normalised_report(example)
    cold, warm, store = cached_twice(example, tmp_path)
    assert_same(example.key, uncached, cold)
    assert_same(example.key, uncached, warm)
    assert store.hits > 0


@pytest.mark.corpus
@pytest.mark.parametrize("key", robot_params())
def test_a_corpus_robot_cached_equals_uncached(
    corpus: Path, corpus_reports: CorpusReports, key: str, tmp_path: Path
) -> None:
    (robot,) = [r for r in golden.robots(corpus) if r.key == key]
    uncached = golden.normalised(corpus_reports[key])
    cold, warm, store = cached_twice(robot, tmp_path)
    assert_same(key, uncached, cold)
    assert_same(key, uncached, warm)
    stored = sum(1 for entry in (tmp_path / "cache").rglob("*") if entry.is_file())
    assert store.hits >= (1 if stored else 0)  # the warm run read the stages the cold one stored
