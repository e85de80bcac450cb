"""The ``views`` section entry of a link kept in the cache: a warm check reads it back equal,
an edited mesh or changed view precision draws the link again."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import trimesh

from geomcheck.cache import Store, using_store
from geomcheck.checks.views_cache import NAMESPACE
from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions, Selection
from geomcheck.pipeline import run_check
from geomcheck.thresholds import Thresholds, ViewThresholds

URDF = """<robot name="r">
  <link name="base">
    <visual><geometry><mesh filename="part.stl"/></geometry></visual>
    <collision><geometry><box size="0.2 0.1 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <visual><geometry><cylinder radius="0.05" length="0.3"/></geometry></visual>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def views(root: Path, store: Store | None, pixels: int = 160) -> Any:
    thresholds = dataclasses.replace(Thresholds(), views=ViewThresholds(raster_pixels=pixels))
    options = CheckOptions(thresholds=thresholds, selection=Selection(select=("GC3",)))
    with using_store(store):
        return run_check(make_bundle(root, search=[]), options).sections["views"]


def entries(store: Store) -> set[str]:
    folder = store.root / NAMESPACE
    return {p.name for p in folder.rglob("*") if p.is_file()} if folder.is_dir() else set()


def test_a_link_drawing_is_read_back_equal_and_an_edit_draws_it_again(tmp_path: Path) -> None:
    trimesh.creation.box(extents=(0.2, 0.1, 0.1)).export(tmp_path / "part.stl")
    root = tmp_path / "robot.urdf"
    root.write_text(URDF)
    store = Store(tmp_path / "cache")
    uncached = views(root, None)
    assert [entry["link"] for entry in uncached] == ["base", "arm"]
    assert views(root, store) == uncached
    stored = entries(store)
    assert len(stored) == 2  # one entry per link
    hits = store.hits
    assert views(root, store) == uncached
    assert store.hits >= hits + 2 and entries(store) == stored

    trimesh.creation.box(extents=(0.3, 0.1, 0.1)).export(tmp_path / "part.stl")
    edited = views(root, None)
    assert edited[0] != uncached[0] and edited[1] == uncached[1]
    assert views(root, store) == edited
    assert len(entries(store) - stored) == 1  # the base drawn again; the arm has no mesh

    coarse = views(root, None, pixels=40)
    assert coarse != edited
    assert views(root, store, pixels=40) == coarse
    assert len(entries(store) - stored) == 3  # a threshold is part of every link's key


def test_a_link_whose_mesh_did_not_load_is_drawn_without_the_store(tmp_path: Path) -> None:
    root = tmp_path / "robot.urdf"
    root.write_text(URDF)  # part.stl is missing
    store = Store(tmp_path / "cache")
    uncached = views(root, None)
    assert "unavailable" in uncached[0]
    assert views(root, store) == uncached
    assert len(entries(store)) == 1  # only the arm
