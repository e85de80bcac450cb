"""The collision matrix against pinocchio's ``computeCollisions`` on the same samples.

For the full 2009 PR2 and the Panda of the shared corpus: geomcheck's matrix (10,000 samples,
both cores), then the same samples through pinocchio (package ``pin``, the ``bench`` extra)
with every pair of collision geometries on different links, recorded per link pair. Both
results are classified the same way (Adjacent, Default, Always, Never, enabled) and
compared pair by pair; pairs that geomcheck's witness search moved out of Never (pinocchio
saw no collision in the samples) are listed apart. Certified pairs must be collision-free in
pinocchio too. Prints both times and the ratio.

    python benchmarks/matrix_vs_pinocchio.py [--samples N] [--robot pr2|panda] [--workers W] [--repeat R]

geomcheck runs ``--repeat`` times (default 3, results must be identical), each on a freshly
built scene (untimed, as pinocchio's model and geometry building is), and its median time is
compared with one pinocchio loop. Then ``geomcheck matrix`` is timed as a whole command (a
fresh interpreter: start-up, loading, scene building included), without the cache and with
the matrix cached by the run before, against the same pinocchio loop. The corpus is ``$GEOMCHECK_CORPUS`` or
``../shared/corpus`` beside the repository.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lxml import etree

from geomcheck.collision import CollisionScene, adjacent_pairs, get_backend
from geomcheck.kinematics import Kinematics
from geomcheck.load import LoadedDescription, MeshStore, load_description, make_bundle
from geomcheck.load.meshes import LoadedMesh
from geomcheck.model import Mesh
from geomcheck.selfcollision.compute import MatrixSettings, compute_matrix, draw_samples
from geomcheck.selfcollision.matrix import CollisionMatrix, PairClass, WitnessSource
from geomcheck.selfcollision.paths import drivers

REPO = Path(__file__).resolve().parents[1]


def corpus_dir() -> Path:
    path = Path(os.environ.get("GEOMCHECK_CORPUS") or REPO.parent / "shared" / "corpus").resolve()
    if not path.is_dir():
        sys.exit(f"corpus not found at {path}: set GEOMCHECK_CORPUS")
    return path


@dataclass(frozen=True)
class Robot:
    name: str
    root: Callable[[Path], Path]  # the description, in the corpus
    packages: Callable[[Path], dict[str, Path]]  # ROS packages for geomcheck
    package_dirs: Callable[[Path], list[Path]]  # parents of the packages, for pinocchio


ROBOTS = {
    "pr2": Robot(
        "full 2009 PR2",
        lambda c: c / "pr2_2009/pr2_description/robots/pr2.urdf.xacro",
        lambda c: {"pr2_description": c / "pr2_2009/pr2_description"},
        lambda c: [c / "pr2_2009"],
    ),
    "panda": Robot(
        "Panda",
        lambda c: c / "example-robot-data/robots/panda_description/urdf/panda.urdf",
        lambda c: {"example-robot-data": c / "example-robot-data"},
        lambda c: [c],
    ),
}


def pinocchio_urdf(loaded: LoadedDescription, scene: CollisionScene, kin: Kinematics, meshes: MeshStore) -> str:
    """The expanded URDF as pinocchio can read it, with exactly the collision shapes of
    geomcheck's scene: shapes it could not use are removed, a build product of a package that
    is not built replaced by the source mesh geomcheck analyses in its place, joints without a
    parent or child dropped, planar and floating joints fixed (geomcheck holds them at their
    origin), and an undeclared parent link (the 2009 PR2's ``world``) declared."""
    root = etree.fromstring(loaded.document.text.encode())
    unusable = {(u.link, u.shape.index) for u in scene.unusable}
    usable = {(s.link, s.shape.index): s.shape.geometry for name in scene.links for s in scene.scene_shapes(name)}
    reachable = set(kin.link_names)
    for link in root.findall("link"):
        for index, element in enumerate(link.findall("collision")):
            if (link.get("name"), index) in unusable or link.get("name") not in reachable:
                link.remove(element)
                continue
            geometry, mesh = usable.get((link.get("name"), index)), element.find("geometry/mesh")
            found = meshes.get(geometry) if isinstance(geometry, Mesh) and mesh is not None else None
            if isinstance(found, LoadedMesh) and found.stands_for is not None and mesh is not None:
                mesh.set("filename", str((meshes.bundle.display_root / found.path).resolve()))
    declared = {link.get("name") for link in root.findall("link")}
    for joint in root.findall("joint"):
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            root.remove(joint)
            continue
        if joint.get("type") in ("planar", "floating"):
            joint.set("type", "fixed")
        if parent.get("link") not in declared:
            root.insert(0, etree.Element("link", name=parent.get("link")))
            declared.add(parent.get("link"))
    return etree.tostring(root, encoding="unicode")


@dataclass
class PinocchioRun:
    seconds: float  # the whole loop: computeCollisions and recording the results per pair
    collide_seconds: float  # computeCollisions alone
    default: set[tuple[str, str]]
    hits: dict[tuple[str, str], int]  # collisions per link pair over the samples


def run_pinocchio(
    text: str, package_dirs: list[Path], kin: Kinematics, q0: np.ndarray, samples: np.ndarray
) -> PinocchioRun:
    import pinocchio as pin

    model = pin.buildModelFromXML(text)
    geom = pin.buildGeomFromUrdfString(model, text, pin.COLLISION, package_dirs=[str(p) for p in package_dirs])
    links = [model.frames[g.parentFrame].name for g in geom.geometryObjects]
    pair_of: list[tuple[str, str]] = []
    for i in range(geom.ngeoms):
        for j in range(i + 1, geom.ngeoms):
            if links[i] != links[j]:
                geom.addCollisionPair(pin.CollisionPair(i, j))
                a, b = sorted((links[i], links[j]))
                pair_of.append((a, b))
    link_pairs = sorted(set(pair_of))
    column = {p: k for k, p in enumerate(link_pairs)}
    geom_to_pair = np.array([column[p] for p in pair_of], dtype=int)
    data, gdata = model.createData(), pin.GeometryData(geom)

    driven = drivers(kin)
    slots = []  # (pinocchio q index, nq, our variable, multiplier, offset)
    for joint_name, (variable, mult, off) in driven.items():
        if not model.existJointName(joint_name):
            continue
        jid = model.getJointId(joint_name)
        slots.append((model.idx_qs[jid], model.nqs[jid], kin.index(variable), mult, off))

    def to_pin(q: np.ndarray) -> np.ndarray:
        out = pin.neutral(model)
        for idx, nq, var, mult, off in slots:
            v = mult * q[var] + off
            if nq == 2:
                out[idx], out[idx + 1] = np.cos(v), np.sin(v)
            else:
                out[idx] = v
        return out

    def record() -> np.ndarray:
        hits = np.fromiter((r.isCollision() for r in gdata.collisionResults), dtype=bool, count=len(pair_of))
        return np.bincount(geom_to_pair[hits], minlength=len(link_pairs)) > 0

    pin.computeCollisions(model, data, geom, gdata, to_pin(q0), False)
    default = {link_pairs[k] for k in np.nonzero(record())[0]}
    qs = [to_pin(q) for q in samples]
    counts = np.zeros(len(link_pairs), dtype=int)
    collide_seconds = 0.0
    started = time.perf_counter()
    for q in qs:
        before = time.perf_counter()
        pin.computeCollisions(model, data, geom, gdata, q, False)
        collide_seconds += time.perf_counter() - before
        counts += record()
    seconds = time.perf_counter() - started
    return PinocchioRun(seconds, collide_seconds, default, {p: int(c) for p, c in zip(link_pairs, counts, strict=True)})


def pinocchio_class(
    pair: tuple[str, str], run: PinocchioRun, adjacent: set[tuple[str, str]], n: int, always: float
) -> PairClass:
    if pair in adjacent:
        return PairClass.ADJACENT
    if pair in run.default:
        return PairClass.DEFAULT
    hits = run.hits.get(pair, 0)
    if hits >= always * n - 1e-9:
        return PairClass.ALWAYS
    return PairClass.NEVER if hits == 0 else PairClass.ENABLED


def compare(matrix: CollisionMatrix, run: PinocchioRun, adjacent: set[tuple[str, str]]) -> int:
    """Print the comparison; the number of disagreements."""
    disagreements, moved, broken = [], [], []
    for pair in matrix.pairs:
        theirs = pinocchio_class(pair.links, run, adjacent, matrix.samples, matrix.always_fraction)
        if pair.certified and run.hits.get(pair.links, 0):
            broken.append((pair.links, run.hits[pair.links]))
        if pair.cls is theirs:
            continue
        searched = pair.witness is not None and pair.witness.source is WitnessSource.SEARCH
        if searched and theirs is PairClass.NEVER:
            moved.append(pair)
        else:
            disagreements.append((pair.links, pair.cls.value, theirs.value))
    print(f"  same class on every pair except: {len(disagreements)} disagreements")
    for links, mine, other in disagreements:
        print(f"    {links[0]} / {links[1]}: geomcheck {mine}, pinocchio {other}")
    print(f"  moved out of Never by the witness search (no sample collided, pinocchio agrees): {len(moved)}")
    for p in moved:
        w = p.witness
        assert w is not None
        print(f"    {p.links[0]} / {p.links[1]}: {w.depth * 1000:.1f} mm deep at {w.describe(4)}")
    if broken:
        print(f"  CERTIFIED PAIRS IN COLLISION IN PINOCCHIO: {broken}")
    return len(disagreements) + len(broken)


def bench(key: str, corpus: Path, samples: int, workers: int, repeat: int) -> tuple[float, float, int]:
    spec = ROBOTS[key]
    bundle = make_bundle(spec.root(corpus), {k: str(v) for k, v in spec.packages(corpus).items()})
    loaded = load_description(bundle)
    kin = Kinematics(loaded.robot)
    meshes = MeshStore(bundle)
    settings = MatrixSettings(samples=samples, seed=0, workers=workers)
    q0 = kin.default_configuration()
    times, sections = [], set()
    for _ in range(repeat):  # the median is robust to a busy machine
        # a fresh scene each time, built untimed like pinocchio's GeometryModel: every timed run
        # computes everything the matrix derives from the shapes (sphere covers included)
        scene = CollisionScene(loaded.robot, meshes, get_backend("coal"))
        started = time.perf_counter()
        matrix = compute_matrix(kin, scene, q0, settings)
        times.append(time.perf_counter() - started)
        sections.add(repr(matrix.to_section()))
    ours = float(np.median(times))
    text = pinocchio_urdf(loaded, scene, kin, meshes)
    run = run_pinocchio(text, spec.package_dirs(corpus), kin, q0, draw_samples(kin, settings))
    counts = matrix.counts()
    print(
        f"{spec.name}: {len(matrix.links)} links with collision geometry, {len(matrix.pairs)} pairs, {samples} samples"
    )
    print("  geomcheck classes: " + ", ".join(f"{v} {k}" for k, v in counts.items()))
    adjacent = adjacent_pairs(loaded.robot, matrix.links)
    bad = compare(matrix, run, adjacent)
    queries = matrix.stats.narrow_phase_calls
    runs = ", ".join(f"{t:.2f}" for t in times)
    same = "identical" if len(sections) == 1 else "DIFFERENT"
    print(f"  geomcheck matrix:           {ours:8.2f} s  median of {repeat} runs ({runs} s; results {same})")
    print(
        f"    {workers} workers, {queries} collision/distance queries, {matrix.stats.witness_searches} witness searches"
    )
    print(
        f"  pinocchio computeCollisions: {run.seconds:8.2f} s  ({sum(1 for _ in run.hits)} link pairs, every sample; "
        f"pinocchio {versions()})"
    )
    print(f"    of which computeCollisions alone: {run.collide_seconds:.2f} s ({run.collide_seconds / ours:.1f}x ours)")
    print(f"  ratio: geomcheck is {run.seconds / ours:.1f}x faster than the pinocchio loop")
    print(f"    (fastest geomcheck run: {run.seconds / min(times):.1f}x)")
    with tempfile.TemporaryDirectory(prefix="geomcheck-matrix-bench-") as tmp:
        cold_wall, cold_cpu = whole_command(spec, corpus, samples, Path(tmp), cache=False)
        whole_command(spec, corpus, samples, Path(tmp), cache=True)  # fills the cache
        warm_wall, warm_cpu = whole_command(spec, corpus, samples, Path(tmp), cache=True)
    print(
        f"  geomcheck matrix as a whole command: {cold_wall:.2f} s wall ({cold_cpu:.2f} s CPU) without the cache, "
        f"{warm_wall:.2f} s wall ({warm_cpu:.2f} s CPU) cached"
    )
    print(
        f"  whole-command ratio: {run.seconds / cold_wall:.1f}x uncached, {run.seconds / warm_wall:.1f}x cached "
        f"(target: at least 10x)"
    )
    return ours, run.seconds, bad + (len(sections) != 1)


def versions() -> str:
    """The versions of pinocchio and of the collision library both engines use: the loop's time
    depends on them (figures measured with other versions are not comparable)."""
    import coal
    import pinocchio as pin

    return f"{pin.__version__}, coal {coal.__version__}"


def whole_command(spec: Robot, corpus: Path, samples: int, cache_dir: Path, cache: bool) -> tuple[float, float]:
    """Wall-clock and CPU seconds [s] of ``geomcheck matrix`` in a fresh interpreter."""
    packages = [a for name, d in spec.packages(corpus).items() for a in ("--package", f"{name}={d}")]
    argv = [sys.executable, "-m", "geomcheck", "matrix", str(spec.root(corpus)), *packages]
    argv += ["--samples", str(samples), "--srdf-out", str(cache_dir / "out.srdf"), *([] if cache else ["--no-cache"])]
    env = {**os.environ, "GEOMCHECK_CACHE_DIR": str(cache_dir / "cache"), "GEOMCHECK_UNTRUSTED": "0"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(argv, env=env, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--robot", choices=sorted(ROBOTS), action="append")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=3, help="geomcheck runs (the median is compared)")
    ns = parser.parse_args()
    corpus = corpus_dir()
    bad = 0
    for key in ns.robot or ["pr2", "panda"]:
        bad += bench(key, corpus, ns.samples, ns.workers, ns.repeat)[2]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
