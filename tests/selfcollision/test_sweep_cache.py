"""Each pair's sweep cached: warm results equal fresh ones; an edit re-sweeps only its pairs."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from geomcheck.cache import open_store, using_store
from geomcheck.selfcollision import sweep as sweep_module
from geomcheck.selfcollision.sweep_cache import NAMESPACE

# reuse the sweep tests' robots and runner
from tests.selfcollision.test_sweep import JointSweep
from tests.selfcollision.test_sweep import sweeps as sweeps_in


def two_casters(second_arm: float = 0.2) -> str:
    """A base plate with two posts, and a caster turning near each (arms reaching the posts)."""
    casters = []
    for name, x, arm in (("front", 0.3, 0.2), ("rear", -0.3, second_arm)):
        casters.append(f"""
  <joint name="{name}_caster_joint" type="continuous">
    <parent link="base_link"/><child link="{name}_caster_link"/><origin xyz="{x} 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <link name="{name}_caster_link">
    <collision><origin xyz="{arm / 2 - 0.02} 0 0.05"/><geometry><box size="{arm} 0.04 0.02"/></geometry></collision>
  </link>""")
    return f"""<?xml version="1.0"?>
<robot name="two_casters">
  <link name="base_link">
    <collision><origin xyz="0 0 0.3"/><geometry><box size="0.9 0.5 0.05"/></geometry></collision>
    <collision><origin xyz="0.45 0.1 0.05"/><geometry><box size="0.02 0.02 0.1"/></geometry></collision>
    <collision><origin xyz="-0.15 0.1 0.05"/><geometry><box size="0.02 0.02 0.1"/></geometry></collision>
  </link>{"".join(casters)}
</robot>
"""


def sweeps(folder: Path, text: str) -> tuple[dict[str, JointSweep], object, object]:
    folder.mkdir(parents=True)
    return sweeps_in(folder, text)


@pytest.fixture
def searched(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, str]]:
    """The pairs the sweep searches (not read from the cache), in order."""
    seen: list[tuple[str, str]] = []
    original = sweep_module._Sweeper.__init__

    def recording(self, kin, scene, q0, settings, group, plans):  # type: ignore[no-untyped-def]
        seen.extend(p.links for p in plans)
        original(self, kin, scene, q0, settings, group, plans)

    monkeypatch.setattr(sweep_module._Sweeper, "__init__", recording)
    return seen


def test_warm_sweeps_equal_fresh_ones_and_search_nothing(tmp_path: Path, searched: list[tuple[str, str]]) -> None:
    fresh, _, _ = sweeps(tmp_path / "fresh", two_casters())
    uncached = list(searched)
    assert len(uncached) >= 2
    store = open_store(tmp_path / "cache")
    with using_store(store):
        cold, _, _ = sweeps(tmp_path / "cold", two_casters())
        searched.clear()
        warm, _, _ = sweeps(tmp_path / "warm", two_casters())
    assert searched == []  # every pair from the store
    assert cold == fresh and warm == fresh
    assert store.hits == len(uncached)


def test_an_edited_link_re_sweeps_only_its_pairs(tmp_path: Path, searched: list[tuple[str, str]]) -> None:
    store = open_store(tmp_path / "cache")
    with using_store(store):
        before, _, _ = sweeps(tmp_path / "a", two_casters())
        every = sorted(searched)
        searched.clear()
        edited = two_casters(second_arm=0.25)
        after, _, _ = sweeps(tmp_path / "b", edited)
    assert searched and sorted(searched) != every
    assert all("rear_caster_link" in links for links in searched)
    assert {links for links in every if "rear_caster_link" in links} == set(searched)
    fresh, _, _ = sweeps(tmp_path / "c", edited)
    assert after == fresh and after != before


def test_a_corrupt_entry_is_searched_again_with_a_debug_line(
    tmp_path: Path, searched: list[tuple[str, str]], caplog: pytest.LogCaptureFixture
) -> None:
    store = open_store(tmp_path / "cache")
    with using_store(store):
        first, _, _ = sweeps(tmp_path / "a", two_casters())
        entries = sorted((tmp_path / "cache" / NAMESPACE).rglob("*"))
        victim = next(p for p in entries if p.is_file())
        victim.write_bytes(victim.read_bytes()[:-3] + b"xyz")
        searched.clear()
        with caplog.at_level(logging.DEBUG, logger="geomcheck.cache"):
            again, _, _ = sweeps(tmp_path / "b", two_casters())
    assert len(searched) == 1 and again == first
    assert any(NAMESPACE in r.getMessage() for r in caplog.records)
