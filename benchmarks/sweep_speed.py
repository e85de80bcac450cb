"""Speed of the continuous-joint sweep on the shared 2009 PR2 (base alone and full robot) and
on MuJoCo's TIAGo (four casters whose non-round wheels make two-angle sweeps).

Usage: python benchmarks/sweep_speed.py [CORPUS_DIR] [--backend coal|fcl] [--repeat N]
(CORPUS_DIR defaults to $GEOMCHECK_CORPUS, then ../shared/corpus). Prints, per robot, the
time to build the kinematics and the collision scene, the time of the sweep itself, and per
swept joint the pairs searched, the pairs dropped by the broad phase and the distance queries.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.selfcollision.sweep import SweepSettings, sweep_joint
from geomcheck.selfcollision.sweep_plan import sweep_groups
from geomcheck.thresholds import SelfCollisionThresholds

ROBOTS = ("pr2_2009/pr2_description/robots/pr2_base.urdf.xacro", "pr2_2009/pr2_description/robots/pr2.urdf.xacro")
TIAGO = "mjcf/pal_tiago/tiago.xml"


def corpus_dir(given: str | None) -> Path:
    for candidate in (given, os.environ.get("GEOMCHECK_CORPUS"), "../shared/corpus"):
        if candidate and Path(candidate).is_dir():
            return Path(candidate)
    raise SystemExit("shared corpus not found: pass its folder or set GEOMCHECK_CORPUS")


def bench(corpus: Path, path: str, search: Path, backend: str, repeat: int) -> None:
    name = Path(path).name
    bundle = make_bundle(corpus / path, search=[search])
    loaded = load_description(bundle)
    t0 = time.perf_counter()
    kin = Kinematics(loaded.robot)
    scene = CollisionScene(loaded.robot, MeshStore(bundle), get_backend(backend))
    adjacent = adjacent_pairs(loaded.robot, scene.links)
    q0 = kin.default_configuration()
    setup = time.perf_counter() - t0
    settings = SweepSettings.from_thresholds(SelfCollisionThresholds())
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        results = [sweep_joint(kin, scene, q0, adjacent, settings, g) for g in sweep_groups(kin, scene, q0)]
        best = min(best, time.perf_counter() - t0)
    print(f"{name} [{backend}]: {len(kin.link_names)} links, {len(scene.links)} with collision geometry")
    print(f"  setup (kinematics + scene) {setup:.3f} s; sweep of {len(results)} joints {best:.3f} s (best of {repeat})")
    for r in results:
        queries = sum(p.queries for p in r.pairs)
        hits = [f"{'/'.join(p.links)}" for p in r.pairs if p.colliding and not (p.adjacent and p.whole_turn)]
        print(
            f"  {r.group.joint.name:32s} dims={len(r.group.dimensions)} pairs={len(r.pairs):3d} "
            f"far={r.far_pairs:3d} queries={queries:6d} proven={r.proven} contacts={hits}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("corpus", nargs="?")
    parser.add_argument("--backend", default="coal")
    parser.add_argument("--repeat", type=int, default=3)
    ns = parser.parse_args()
    corpus = corpus_dir(ns.corpus)
    for path in ROBOTS:
        bench(corpus, path, corpus / "pr2_2009", ns.backend, ns.repeat)
    if (corpus / TIAGO).is_file():
        bench(corpus, TIAGO, (corpus / TIAGO).parent, ns.backend, ns.repeat)


if __name__ == "__main__":
    main()
