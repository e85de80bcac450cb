"""The collision matrix: MoveIt classes, certified-never pairs, witness search, determinism,
backends, and the corpus robots against their SRDFs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.errors import UsageError
from geomcheck.kinematics import Kinematics
from geomcheck.load import LoadedDescription, MeshStore, load_description, make_bundle
from geomcheck.load.srdf import read_srdf
from geomcheck.model import Joint, Limit, Link, Mimic, Pose, Robot
from geomcheck.report.srdf import render_srdf
from geomcheck.selfcollision.certify import reach
from geomcheck.selfcollision.compute import MatrixSettings, compute_matrix, draw_samples
from geomcheck.selfcollision.matrix import CollisionMatrix, PairClass, WitnessSource
from geomcheck.selfcollision.paths import pair_path

# A rig on which every class appears (lengths in metres):
# * base: two blocks 1.43 m long with a 0.14 m gap at x = 0; rail: a ball 1 m above.
# * slider: a 0.1 m block sliding in x over [-1, 1] m at the blocks' height: it fits the gap
#   only for |x| <= 0.02, so base / slider is in collision in 98 % of the samples: Always.
# * tag: fixed to the rail, inside the right block: base / tag is Default (and rigid); the
#   slider reaches it only for x > 0.925: slider / tag is enabled.
# * arm: a 1 cm ball on a 0.5 m arm turning about z above the base; post: a 2 cm ball that the
#   arm's ball grazes by 0.05 mm at 1 rad only (a window of +-3.5 mrad): arm / post collides in
#   no sample and is found by the witness search.
# * bracket has no geometry: post / rail are adjacent through it.
POST_ANGLE = 1.0  # [rad]
POST_RADIUS = 0.5 + 0.03 - 0.00005  # [m]
RIG = f"""<?xml version="1.0"?>
<robot name="rig">
  <link name="base">
    <collision><origin xyz="-0.785 0 0"/><geometry><box size="1.43 0.2 0.1"/></geometry></collision>
    <collision><origin xyz="0.785 0 0"/><geometry><box size="1.43 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="mount" type="fixed"><parent link="base"/><child link="rail"/><origin xyz="0 0 1"/></joint>
  <link name="rail"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="slide" type="prismatic">
    <parent link="rail"/><child link="slider"/><origin xyz="0 0 -1"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="slider"><collision><geometry><box size="0.1 0.1 0.05"/></geometry></collision></link>
  <joint name="tag_mount" type="fixed"><parent link="rail"/><child link="tag"/><origin xyz="1.0 0 -1"/></joint>
  <link name="tag"><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="swing" type="continuous"><parent link="rail"/><child link="arm"/><axis xyz="0 0 1"/></joint>
  <link name="arm">
    <collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.01"/></geometry></collision>
  </link>
  <joint name="bracket_mount" type="fixed"><parent link="rail"/><child link="bracket"/></joint>
  <link name="bracket"/>
  <joint name="post_mount" type="fixed">
    <parent link="bracket"/><child link="post"/>
    <origin xyz="{POST_RADIUS * math.cos(POST_ANGLE):.9f} {POST_RADIUS * math.sin(POST_ANGLE):.9f} 0"/>
  </joint>
  <link name="post"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
</robot>
"""
RIG_CLASSES = {
    ("arm", "base"): "never",
    ("arm", "post"): "enabled",
    ("arm", "rail"): "adjacent",
    ("arm", "slider"): "never",
    ("arm", "tag"): "never",
    ("base", "post"): "never",
    ("base", "rail"): "adjacent",
    ("base", "slider"): "always",
    ("base", "tag"): "default",
    ("post", "rail"): "adjacent",
    ("post", "slider"): "never",
    ("post", "tag"): "never",
    ("rail", "slider"): "adjacent",
    ("rail", "tag"): "adjacent",
    ("slider", "tag"): "enabled",
}


def load(tmp_path: Path, text: str = RIG) -> LoadedDescription:
    root = tmp_path / "robot.urdf"
    root.write_text(text)
    return load_description(make_bundle(root, display_root=tmp_path))


def matrix_of(
    loaded: LoadedDescription,
    backend: str = "coal",
    samples: int = 300,
    seed: int = 0,
    workers: int = 1,
    semantics: str = "moveit",
) -> CollisionMatrix:
    kin = Kinematics(loaded.robot)
    scene = CollisionScene(loaded.robot, MeshStore(loaded.bundle), get_backend(backend))
    settings = MatrixSettings(samples=samples, seed=seed, workers=workers, semantics=semantics)
    return compute_matrix(kin, scene, kin.default_configuration(), settings)


def classes(matrix: CollisionMatrix) -> dict[tuple[str, str], str]:
    return {p.links: p.cls.value for p in matrix.pairs}


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> LoadedDescription:
    return load(tmp_path_factory.mktemp("rig"))


@pytest.fixture(scope="module")
def rig_matrix(rig: LoadedDescription) -> CollisionMatrix:
    return matrix_of(rig)


def test_every_moveit_class_with_its_evidence(rig_matrix: CollisionMatrix) -> None:
    m = rig_matrix
    assert classes(m) == RIG_CLASSES
    assert m.links == ("base", "rail", "slider", "tag", "arm", "post")  # document order, bracket has no geometry
    always = m.pair("slider", "base")
    assert always is not None and always.tested == 300
    assert always.fraction == pytest.approx(0.98, abs=0.02)
    assert always.min_distance == pytest.approx(-0.075, abs=1e-6)  # the slider's half width + gap
    default = m.pair("base", "tag")
    assert default is not None and default.witness is not None
    assert default.witness.source is WitnessSource.DEFAULT and default.witness.depth == pytest.approx(0.075, abs=1e-6)
    sometimes = m.pair("slider", "tag")
    assert sometimes is not None and sometimes.witness is not None
    assert sometimes.witness.source is WitnessSource.SAMPLE
    assert sometimes.witness.configuration["slide"] > 0.925
    # settled as enabled once free in more than 5 % of the samples: sampling stopped early
    assert sometimes.collisions > 0 and sometimes.tested < 300


def test_a_pair_colliding_only_in_a_narrow_window_is_found_by_the_witness_search(rig_matrix: CollisionMatrix) -> None:
    pair = rig_matrix.pair("arm", "post")
    assert pair is not None and pair.cls is PairClass.ENABLED
    assert pair.collisions == 0 and pair.tested == 300  # no sample hit the window
    assert pair.min_distance is not None and 0 < pair.min_distance < 0.05
    assert pair.witness is not None and pair.witness.source is WitnessSource.SEARCH
    assert list(pair.witness.configuration) == ["swing"]
    assert pair.witness.configuration["swing"] == pytest.approx(POST_ANGLE, abs=0.0036)
    assert 0 <= pair.witness.depth <= 0.00005 + 1e-9


def test_certified_pairs_never_collide_and_carry_a_clearance(
    rig: LoadedDescription, rig_matrix: CollisionMatrix
) -> None:
    certified = {p.links: p for p in rig_matrix.pairs if p.certified}
    assert set(certified) == {k for k, v in RIG_CLASSES.items() if v == "never"}
    rigid = certified[("base", "post")]
    assert rigid.tested == 0 and rigid.clearance_bound == pytest.approx(0.991 - 0.0, abs=0.01)
    kin = Kinematics(rig.robot)
    scene = CollisionScene(rig.robot, MeshStore(rig.bundle), get_backend("coal"))
    q = kin.sample(2000, np.random.default_rng(7))
    frames = kin.link_transforms(q)
    for (a, b), pair in certified.items():
        ia, ib = kin.link_index(a), kin.link_index(b)
        distances = [scene.pair_distance(a, frames[i, ia], b, frames[i, ib]) for i in range(len(q))]
        assert min(distances) >= (pair.clearance_bound or 0.0) - 1e-9, (a, b)


def test_same_seed_same_bytes_whatever_the_workers(rig: LoadedDescription, rig_matrix: CollisionMatrix) -> None:
    again = matrix_of(rig, workers=2)
    first = json.dumps(rig_matrix.to_section(), sort_keys=True)
    assert json.dumps(again.to_section(), sort_keys=True) == first
    assert render_srdf(again, "rig") == render_srdf(rig_matrix, "rig")
    other = matrix_of(rig, seed=1)
    assert json.dumps(other.to_section(), sort_keys=True) != first  # the samples do change


def test_fcl_gives_the_same_classes_as_coal(rig: LoadedDescription, rig_matrix: CollisionMatrix) -> None:
    fcl = matrix_of(rig, backend="fcl")
    assert fcl.backend == "fcl" and classes(fcl) == classes(rig_matrix)


def test_pinocchio_semantics_drops_the_pairs_of_one_rigid_body(
    rig: LoadedDescription, rig_matrix: CollisionMatrix
) -> None:
    # base, rail, tag and post hang together on fixed joints: Pinocchio never pairs them
    pinocchio = matrix_of(rig, semantics="pinocchio")
    body = {"base", "rail", "tag", "post"}
    expected = {pair: cls for pair, cls in RIG_CLASSES.items() if not set(pair) <= body}
    assert classes(pinocchio) == expected and len(expected) == len(RIG_CLASSES) - 6
    assert pinocchio.semantics == "pinocchio" and pinocchio.pair("base", "tag") is None
    assert "Pinocchio semantics: links joined only by fixed joints" in render_srdf(pinocchio, "rig")
    with pytest.raises(UsageError, match="invalid semantics 'drake'; valid choices: moveit, pinocchio"):
        matrix_of(rig, semantics="drake")


def test_section_follows_the_report_schema(rig_matrix: CollisionMatrix) -> None:
    section = rig_matrix.to_section()
    assert list(section) == ["samples", "seed", "backend", "semantics", "always_fraction", "links", "counts", "pairs"]
    assert section["semantics"] == "moveit"
    assert section["counts"] == {
        "adjacent": 5,
        "default": 1,
        "always": 1,
        "never": 6,
        "enabled": 2,
        "certified": 6,
    }
    arm_post = next(p for p in section["pairs"] if p["links"] == ["arm", "post"])
    assert list(arm_post) == [
        "links",
        "class",
        "fraction",
        "tested",
        "min_distance",
        "certified",
        "clearance_bound",
        "witness",
    ]
    assert arm_post["class"] == "enabled" and arm_post["fraction"] == 0.0 and arm_post["certified"] is False
    assert arm_post["witness"]["source"] == "search" and set(arm_post["witness"]) == {
        "configuration",
        "depth",
        "source",
    }


def _chain_robot(rng: np.random.Generator) -> Robot:
    """Six links in a tree with revolute, prismatic, continuous, fixed and mimic joints."""

    def pose() -> Pose:
        xyz = rng.uniform(-0.3, 0.3, 3)
        rpy = rng.uniform(-3, 3, 3)
        return Pose((float(xyz[0]), float(xyz[1]), float(xyz[2])), (float(rpy[0]), float(rpy[1]), float(rpy[2])))

    def axis() -> tuple[float, float, float]:
        a = rng.normal(size=3)
        return float(a[0]), float(a[1]), float(a[2])

    kinds = ["revolute", "prismatic", "fixed", "continuous", "revolute", "revolute"]
    parents = [None, 0, 1, 2, 1, 4, 5]
    joints = []
    for i, kind in enumerate(kinds, start=1):
        limit = Limit(-0.7, 1.1) if kind in ("revolute", "prismatic") else None
        mimic = Mimic("j5", -2.0, 0.3) if i == 6 else None
        joints.append(Joint(f"j{i}", kind, f"l{parents[i]}", f"l{i}", pose(), axis(), limit, mimic))
    return Robot("chain", tuple(Link(f"l{i}") for i in range(7)), tuple(joints))


def test_reach_balls_hold_every_reachable_position() -> None:
    rng = np.random.default_rng(1)
    robot = _chain_robot(rng)
    kin = Kinematics(robot)
    q = kin.sample(5000, rng)
    frames = kin.link_transforms(q)
    point = np.array([0.1, -0.2, 0.05])
    for a, b in [("l3", "l6"), ("l5", "l2"), ("l6", "l0")]:
        path = pair_path(kin, a, b)
        rel = np.linalg.inv(frames[:, kin.link_index(a)]) @ frames[:, kin.link_index(b)]
        ta, tb = path.transforms(q)
        assert np.allclose(np.linalg.inv(ta) @ tb, rel, atol=1e-9)  # the chains agree with the kinematics
        for chain, link in ((path.first, a), (path.second, b)):
            lo = np.array([[s.lower for s in chain.steps]])
            hi = np.array([[s.upper for s in chain.steps]])
            ball = reach(chain, point[None, :], lo, hi)
            top = ta if chain is path.first else tb
            positions = (top @ np.append(point, 1.0))[:, :3]
            assert (np.linalg.norm(positions - ball.centre[0], axis=1) <= ball.radius[0] + 1e-9).all(), link


def test_settings_are_validated() -> None:
    from geomcheck.errors import UsageError

    with pytest.raises(UsageError, match="at least 1"):
        MatrixSettings(samples=0).validate()
    with pytest.raises(UsageError, match="always_fraction"):
        MatrixSettings(always_fraction=1.5).validate()


# ---------------------------------------------------------------------------- corpus
def erd_robot(erd_root: Path, relative: str) -> LoadedDescription:
    bundle = make_bundle(erd_root / relative, {"example-robot-data": erd_root})
    return load_description(bundle)


def adjacent_of(matrix: CollisionMatrix) -> set[tuple[str, str]]:
    return {p.links for p in matrix.pairs if p.cls is PairClass.ADJACENT}


def srdf_adjacent(path: Path) -> set[tuple[str, str]]:
    return {d.pair for d in read_srdf(path).disabled if d.reason == "Adjacent"}


@pytest.mark.corpus
def test_panda_adjacent_pairs_equal_the_srdf(erd_root: Path) -> None:
    panda = erd_robot(erd_root, "robots/panda_description/urdf/panda.urdf")
    coal = matrix_of(panda, samples=200)
    srdf = erd_root / "robots/panda_description/srdf/panda.srdf"
    assert adjacent_of(coal) == srdf_adjacent(srdf)
    assert len(adjacent_of(coal)) == 10  # link7 / hand through link8, which has no geometry
    fcl = matrix_of(panda, backend="fcl", samples=200)
    assert classes(fcl) == classes(coal)


@pytest.mark.corpus
def test_solo_adjacent_pairs_are_the_srdf_ones_plus_the_fixed_feet(erd_root: Path) -> None:
    solo = erd_robot(erd_root, "robots/solo_description/robots/solo12.urdf")
    kin = Kinematics(solo.robot)
    scene = CollisionScene(solo.robot, MeshStore(solo.bundle), get_backend("coal"))
    ours = adjacent_pairs(solo.robot, scene.links)
    theirs = srdf_adjacent(erd_root / "robots/solo_description/srdf/solo.srdf")
    # The hand-written Solo SRDF lists only the 12 joint-connected pairs; each foot hangs from its
    # lower leg by a fixed joint and has its own collision mesh, so MoveIt's rule makes those
    # pairs adjacent too.
    feet = {(f"{leg}_FOOT", f"{leg}_LOWER_LEG") for leg in ("FL", "FR", "HL", "HR")}
    assert theirs <= ours and ours - theirs == feet
    assert all(kin.parent_joint(a).type == "fixed" for a, _ in feet)  # type: ignore[union-attr]


@pytest.mark.corpus
def test_solo_adjacent_pairs_equal_the_srdf_under_pinocchio_semantics(erd_root: Path) -> None:
    """solo.srdf is written for Pinocchio, which never pairs links joined only by fixed joints."""
    solo = erd_robot(erd_root, "robots/solo_description/robots/solo12.urdf")
    matrix = matrix_of(solo, samples=200, semantics="pinocchio")
    srdf = erd_root / "robots/solo_description/srdf/solo.srdf"
    assert adjacent_of(matrix) == srdf_adjacent(srdf) and len(adjacent_of(matrix)) == 12
    assert len(matrix.pairs) == 136 - 4 and matrix.pair("FL_FOOT", "FL_LOWER_LEG") is None
    assert matrix.to_section()["semantics"] == "pinocchio"


@pytest.mark.corpus
def test_panda_certified_pairs_and_samples_are_reproducible(erd_root: Path) -> None:
    panda = erd_robot(erd_root, "robots/panda_description/urdf/panda.urdf")
    first, second = matrix_of(panda, samples=200), matrix_of(panda, samples=200, workers=2)
    assert json.dumps(first.to_section()) == json.dumps(second.to_section())
    kin = Kinematics(panda.robot)
    samples = draw_samples(kin, MatrixSettings(samples=200))
    assert samples.shape == (200, len(kin.joints))
    certified = [p.links for p in first.pairs if p.certified]
    assert ("panda_hand", "panda_link6") in certified
