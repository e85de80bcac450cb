"""A link's coverage at rest kept in the cache: a warm check reads it back equal; an edited
mesh, a neighbour moved or a changed threshold measures it again."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import trimesh

from geomcheck.cache import Store, using_store
from geomcheck.checks.coverage_cache import NAMESPACE
from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions, Selection
from geomcheck.pipeline import run_check
from geomcheck.thresholds import FitThresholds, Thresholds

# the upper arm's mesh reaches past its box into the elbow, which the forearm's box covers at rest
URDF = """<robot name="r">
  <link name="upper">
    <visual><geometry><mesh filename="upper.stl"/></geometry></visual>
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.06 0.06 0.2"/></geometry></collision>
  </link>
  <link name="fore">
    <visual><origin xyz="0 0 0.1"/><geometry><box size="0.05 0.05 0.2"/></geometry></visual>
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.06 0.06 0.2"/></geometry></collision>
  </link>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 ELBOW"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def write(folder: Path, length: float = 0.26, elbow: float = 0.2) -> Path:
    mesh = trimesh.creation.box(extents=(0.05, 0.05, length))
    mesh.apply_translation((0.0, 0.0, length / 2))
    mesh.export(folder / "upper.stl")
    root = folder / "robot.urdf"
    root.write_text(URDF.replace("ELBOW", str(elbow)))
    return root


def at_rest(root: Path, store: Store | None, samples: int | None = None) -> Any:
    fit = FitThresholds() if samples is None else dataclasses.replace(FitThresholds(), surface_samples=samples)
    options = CheckOptions(thresholds=dataclasses.replace(Thresholds(), fit=fit), selection=Selection(select=("GC3",)))
    with using_store(store):
        links = run_check(make_bundle(root, search=[]), options).sections["links"]
    return {e["link"]: (e["union"]["coverage"], e["union"]["coverage_at_rest"]) for e in links if e["union"]}


def entries(store: Store) -> set[str]:
    folder = store.root / NAMESPACE
    return {p.name for p in folder.rglob("*") if p.is_file()} if folder.is_dir() else set()


def test_coverage_at_rest_is_read_back_equal_and_measured_again_after_an_edit(tmp_path: Path) -> None:
    root = write(tmp_path)
    store = Store(tmp_path / "cache")
    uncached = at_rest(root, None)
    coverage, resting = uncached["upper"]
    assert coverage < resting <= 1.0  # the forearm's box covers what the upper arm's leaves out
    assert at_rest(root, store) == uncached
    stored = entries(store)
    assert len(stored) >= 1
    hits = store.hits
    assert at_rest(root, store) == uncached
    assert store.hits > hits and entries(store) == stored

    longer = write(tmp_path, length=0.3)
    edited = at_rest(longer, None)
    assert edited["upper"] != uncached["upper"]
    assert at_rest(longer, store) == edited
    grown = entries(store) - stored
    assert len(grown) >= 1

    moved = write(tmp_path, length=0.3, elbow=0.24)
    assert at_rest(moved, store) == at_rest(moved, None)
    assert len(entries(store) - stored) > len(grown)  # the neighbour's place is part of the key

    before = entries(store)
    assert at_rest(moved, store, samples=500) == at_rest(moved, None, samples=500)
    assert entries(store) - before  # a threshold is part of the key
