"""Every corpus robot's report, checked with the stage caches cold and then warm, equals the
report checked without them (reports as scripts/golden.py normalises them). The session's
shared report (``corpus_reports``) is the cold check of the default run's robots, with a store
of their own (a stage returns what it computed on a miss; test_golden holds those reports to
the goldens, recorded without caches), and this test reads it back warm; the example, and a
campaign's other robots, are checked here without a store, cold and warm. The default run
takes the first robot of each kind; ``pytest -m campaign`` every robot."""

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
    session = golden.normalised(corpus_reports[key])
    store, read_before = corpus_reports.store(key), 0
    if store is None:  # a robot the session checked without a store (a campaign's): cold here
        cold, warm, store = cached_twice(robot, tmp_path)
        assert_same(key, session, cold)
    else:  # the session's check was the cold one (a miss returns what was computed)
        read_before = store.hits
        with using_store(store):
            warm = golden.normalised_report(robot)
    assert_same(key, session, warm)
    stored = sum(1 for entry in store.root.rglob("*") if entry.is_file())
    assert store.hits - read_before >= (1 if stored else 0)  # the warm run read the stages the cold one stored
