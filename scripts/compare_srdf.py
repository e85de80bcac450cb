"""Compare geomcheck's collision matrix with the SRDFs shipped with the corpus robots.

For the Panda and Solo 12 of example-robot-data: every pair the SRDF disables or geomcheck
disables, where the two disagree, with geomcheck's evidence (collisions in the samples, the
witness configuration, a certified clearance).

Each SRDF is compared under the semantics it was written for: the Panda's comes from MoveIt's
Setup Assistant (``moveit``: every two links with geometry make a pair); the Solo's is written
for Pinocchio (``pinocchio``: links joined only by fixed joints are one body and make no pair,
so its feet and lower legs are not listed). ``--semantics`` compares under the other one.

    python scripts/compare_srdf.py [--samples N] [--seed S] [--robot panda|solo] [--semantics moveit|pinocchio]

The corpus is ``$GEOMCHECK_CORPUS`` or ``../shared/corpus`` beside the repository.
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
from pathlib import Path

from geomcheck.collision import SEMANTICS, CollisionScene, get_backend, rigid_pairs
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.load.srdf import read_srdf
from geomcheck.selfcollision.compute import MatrixSettings, compute_matrix
from geomcheck.selfcollision.matrix import PairClass, PairResult
from geomcheck.selfcollision.paths import ancestors, common_ancestor

REPO = Path(__file__).resolve().parents[1]
ROBOTS = {  # URDF, SRDF, the semantics the SRDF was written for
    "panda": ("robots/panda_description/urdf/panda.urdf", "robots/panda_description/srdf/panda.srdf", "moveit"),
    "solo": ("robots/solo_description/robots/solo12.urdf", "robots/solo_description/srdf/solo.srdf", "pinocchio"),
}


def say(text: str = "") -> None:
    sys.stdout.write(text + "\n")


def adjacency(pair: PairResult, kin: Kinematics, scene: CollisionScene) -> str:
    """How the two links of an Adjacent pair are joined and, when nothing moves between
    them, their constant overlap."""
    a, b = pair.links
    top = common_ancestor(kin, a, b)
    below_top = [frame for link in (a, b) for frame in itertools.takewhile(lambda f: f != top, ancestors(kin, link))]
    joints = [joint for frame in below_top if (joint := kin.parent_joint(frame)) is not None]
    how = ", ".join(f"{j.type} joint {j.name}" for j in joints)
    frames = kin.link_transforms(kin.default_configuration()[None])[0]
    hit, depth = scene.pair_collide(a, frames[kin.link_index(a)], b, frames[kin.link_index(b)])
    rigid = all(j.type == "fixed" for j in joints)
    overlap = f"; they overlap by {depth * 1000:.1f} mm" if hit else ""
    return f"joined by {how}{overlap}{' in every configuration' if rigid and hit else ''}"


def evidence(pair: PairResult) -> str:
    """geomcheck's reason for its class, in words."""
    if pair.certified:
        return f"certified clearance >= {(pair.clearance_bound or 0) * 1000:.1f} mm"
    w = pair.witness
    if w is not None:
        where = w.describe(4)
        if w.source.value == "search":
            return f"witness search: {w.depth * 1000:.1f} mm deep at {where}"
        if w.source.value == "sample":
            return f"in collision in {pair.collisions} of {pair.tested} samples, e.g. {where}"
        return f"in collision at the default pose, {w.depth * 1000:.1f} mm deep"
    if pair.min_distance is not None:
        return f"never in {pair.tested} samples, closest {pair.min_distance * 1000:.1f} mm"
    return ""


def compare(key: str, erd: Path, samples: int, seed: int, semantics: str | None) -> None:
    urdf, srdf_path, written_for = ROBOTS[key]
    semantics = semantics or written_for
    bundle = make_bundle(erd / urdf, {"example-robot-data": erd})
    loaded = load_description(bundle)
    kin = Kinematics(loaded.robot)
    scene = CollisionScene(loaded.robot, MeshStore(bundle), get_backend("coal"))
    settings = MatrixSettings(samples=samples, seed=seed, semantics=semantics)
    matrix = compute_matrix(kin, scene, kin.default_configuration(), settings)
    srdf = read_srdf(erd / srdf_path, srdf_path)
    say(f"== {loaded.robot.name} ({urdf}) against {srdf_path}: {samples} samples, seed {seed}")
    say(f"   {semantics} semantics (the SRDF is written for {written_for})")
    rigid = sorted(rigid_pairs(loaded.robot, matrix.links))
    if rigid:
        held = "not pairs under these semantics" if semantics == "pinocchio" else "pairs under these semantics"
        say(f"   joined only by fixed joints ({held}): " + ", ".join(f"{a} / {b}" for a, b in rigid))
    counts = matrix.counts()
    say("   geomcheck: " + ", ".join(f"{v} {k}" for k, v in counts.items()))
    listed = {d.pair: d.moveit_reason for d in srdf.disabled}
    agree, rows = 0, []
    for pair in matrix.pairs:
        theirs = listed.pop(pair.links, None)
        ours = pair.cls.srdf_reason
        if theirs == ours:
            agree += 1 if ours else 0
            continue
        why = adjacency(pair, kin, scene) if pair.cls is PairClass.ADJACENT else evidence(pair)
        rows.append((pair.links, theirs or "enabled", ours or "enabled", why))
    say(f"   same disabled pair and reason: {agree}; differences: {len(rows)}")
    for (a, b), theirs, ours, why in rows:
        say(f"   {a} / {b}: SRDF {theirs}, geomcheck {ours} ({why})")
    geometry = set(matrix.links)
    for (a, b), reason in sorted(listed.items()):
        if (a, b) in rigid and semantics == "pinocchio":
            say(f"   {a} / {b}: SRDF {reason}, not a pair: only fixed joints join them")
            continue
        missing = [n for n in (a, b) if n not in geometry]
        known = all(n in loaded.robot.link_map for n in (a, b))
        what = "has no collision geometry" if known else "is not a link of the URDF"
        say(f"   {a} / {b}: SRDF {reason}, not in the matrix: {', '.join(missing)} {what}")
    adjacent_ours = {p.links for p in matrix.pairs if p.cls is PairClass.ADJACENT}
    adjacent_theirs = {d.pair for d in srdf.disabled if d.moveit_reason == "Adjacent"}
    same = "equal" if adjacent_ours == adjacent_theirs else "differ"
    say(f"   Adjacent pairs {same}: SRDF {len(adjacent_theirs)}, geomcheck {len(adjacent_ours)}")
    say()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--robot", choices=sorted(ROBOTS), action="append")
    parser.add_argument("--semantics", choices=SEMANTICS, help="default: the one each SRDF is written for")
    ns = parser.parse_args()
    corpus = Path(os.environ.get("GEOMCHECK_CORPUS") or REPO.parent / "shared" / "corpus").resolve()
    erd = corpus / "example-robot-data"
    if not erd.is_dir():
        sys.exit(f"corpus not found at {corpus}: set GEOMCHECK_CORPUS")
    for key in ns.robot or ["panda", "solo"]:
        compare(key, erd, ns.samples, ns.seed, ns.semantics)
    return 0


if __name__ == "__main__":
    sys.exit(main())
