"""A pose's narrow phase kept in the cache: read back equal, asked again for another pose,
shape or mesh."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

from geomcheck.cache import Store, using_store
from geomcheck.collision import CollisionScene, get_backend
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.selfcollision.contacts_cache import COLLISIONS_NAMESPACE, NAMESPACE
from geomcheck.selfcollision.default_pose import contacts_at, only_touching, pair_occupancy

ROBOT = """<robot name="r">
  <link name="base"><collision><geometry><mesh filename="base.stl"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <link name="arm">
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="j2" type="revolute"><parent link="arm"/><child link="hand"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <link name="hand">
    <collision><origin xyz="0 0 -0.3"/><geometry><box size="0.05 0.05 HAND"/></geometry></collision></link>
</robot>
"""


def contacts(folder: Path, store: Store | None, hand: float = 0.6, q: dict[str, float] | None = None) -> list:
    root = folder / "robot.urdf"
    root.write_text(ROBOT.replace("HAND", str(hand)))
    bundle = make_bundle(root, search=[])
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    with using_store(store):
        scene = CollisionScene(robot, MeshStore(bundle), get_backend("coal"))
        return contacts_at(kin, scene, kin.default_configuration(q or {}), {("arm", "base"), ("arm", "hand")})


def entries(store: Store) -> int:
    folder = store.root / NAMESPACE
    return sum(1 for p in folder.rglob("*") if p.is_file()) if folder.is_dir() else 0


def test_a_pose_contacts_are_read_back_equal_and_an_edit_asks_the_engine_again(tmp_path: Path) -> None:
    trimesh.creation.box(extents=(0.2, 0.2, 0.2)).export(tmp_path / "base.stl")
    store = Store(tmp_path / "cache")
    uncached = contacts(tmp_path, None)
    [contact] = uncached
    assert contact.links == ("base", "hand") and contact.depth > 0.1 and contact.shapes == (0, 0)
    assert contacts(tmp_path, store) == uncached
    hits = store.hits
    assert contacts(tmp_path, store) == uncached
    assert store.hits > hits and entries(store) == 1

    assert contacts(tmp_path, store, hand=0.18) == contacts(tmp_path, None, hand=0.18) == []
    assert entries(store) == 2  # another shape (apart by 1 cm: the narrow phase says so)
    bent = contacts(tmp_path, store, q={"j2": 0.05})
    assert bent != [] and bent != uncached
    assert bent == contacts(tmp_path, None, q={"j2": 0.05}) and entries(store) == 3  # another pose

    trimesh.creation.box(extents=(0.02, 0.02, 0.02)).export(tmp_path / "base.stl")
    smaller = contacts(tmp_path, store)
    assert smaller == contacts(tmp_path, None) and smaller != uncached  # another mesh, another depth
    assert entries(store) == 4
    assert np.isfinite(contact.depth)


def test_a_pair_occupancy_is_read_back_equal_and_another_seed_asks_again(tmp_path: Path) -> None:
    trimesh.creation.box(extents=(0.2, 0.2, 0.2)).export(tmp_path / "base.stl")
    root = tmp_path / "robot.urdf"
    root.write_text(ROBOT.replace("HAND", "0.6"))
    bundle = make_bundle(root, search=[])
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    q = kin.default_configuration()
    scene = CollisionScene(robot, MeshStore(bundle), get_backend("coal"))
    uncached = pair_occupancy(kin, scene, q, ("base", "hand"), 50, 7)
    assert 0 < uncached.collisions < 50 and uncached.tested == 50
    store = Store(tmp_path / "cache")
    with using_store(store):
        assert pair_occupancy(kin, scene, q, ("base", "hand"), 50, 7) == uncached
        assert pair_occupancy(kin, scene, q, ("base", "hand"), 50, 7) == uncached
        other = pair_occupancy(kin, scene, q, ("base", "hand"), 50, 8)
    assert other == pair_occupancy(kin, scene, q, ("base", "hand"), 50, 8)
    assert store.hits == 1
    assert sum(1 for p in (store.root / COLLISIONS_NAMESPACE).rglob("*") if p.is_file()) == 2


def test_only_touching_reads_its_six_shifts_from_the_store(tmp_path: Path) -> None:
    trimesh.creation.box(extents=(0.2, 0.2, 0.2)).export(tmp_path / "base.stl")
    root = tmp_path / "robot.urdf"
    root.write_text(ROBOT.replace("HAND", "0.6"))
    bundle = make_bundle(root, search=[])
    robot = load_description(bundle).robot
    kin = Kinematics(robot)
    frames = kin.link_transforms(kin.default_configuration()[None])[0]
    ta, tb = frames[kin.link_index("base")], frames[kin.link_index("hand")]
    scene = CollisionScene(robot, MeshStore(bundle), get_backend("coal"))
    store = Store(tmp_path / "cache")
    for shift, expected in ((0.001, False), (0.2, True)):  # the hand is 0.125 m deep in the base
        assert only_touching(scene, "base", ta, "hand", tb, shift) is expected
        with using_store(store):
            assert only_touching(scene, "base", ta, "hand", tb, shift) is expected
            assert only_touching(scene, "base", ta, "hand", tb, shift) is expected
    assert store.hits == 2
    assert sum(1 for p in (store.root / COLLISIONS_NAMESPACE).rglob("*") if p.is_file()) == 2
