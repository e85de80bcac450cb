"""The collision matrix against pinocchio's ``computeCollisions`` on the same samples, per robot.

For every URDF robot of ``robots.toml`` (``scripts/corpus_robots.py``; ``--robot NAME`` picks
some): geomcheck's matrix (10,000 samples, both cores), then the same samples through
pinocchio (package ``pin``, the ``bench`` extra) with every pair of collision geometries on
different links, recorded per link pair. Both results are classified the same way (Adjacent,
Default, Always, Never, enabled) and compared pair by pair; pairs that geomcheck's witness
search moved out of Never (pinocchio saw no collision in the samples) are counted apart
(listed with ``--details``). Certified pairs must be collision-free in pinocchio too.

    python benchmarks/matrix_vs_pinocchio.py [--samples N] [--robot NAME ...] [--workers W] [--repeat R] [--details]

geomcheck runs ``--repeat`` times in process (default 1, results must be identical), each on a
freshly built scene (untimed, as pinocchio's model and geometry building is), and its median
time is compared with one pinocchio loop. Then ``geomcheck matrix`` is timed as a whole command
(a fresh interpreter, an empty cache: start-up, loading, scene building included; geomcheck's
bytecode compiled by an untimed run before, as an installed geomcheck's is) against the
same pinocchio loop (the issue's target: at least 1x on every robot, 15x at the median). One
table row per robot, then the median ratios; a robot pinocchio cannot read is a row with the
reason. The load average is printed first: give it with the figures. The corpus is
``$GEOMCHECK_CORPUS`` or ``../shared/corpus`` beside the repository.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import statistics
import subprocess
import sys
import tempfile
import time
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
sys.path.insert(0, str(REPO / "scripts"))
from corpus_robots import CorpusRobot, checked_robots, corpus_dir  # noqa: E402


def package_dirs(robot: CorpusRobot) -> list[Path]:
    """Where pinocchio looks for ``package://NAME/...``: the parent of each package folder
    named NAME, and the package folders themselves (the Panda's example-robot-data is a package
    whose folder has another name); meshes geomcheck resolved itself are written as absolute
    paths by :func:`pinocchio_urdf`."""
    dirs: list[Path] = []
    for path in robot.packages.values():
        for d in (path.parent, path):
            if d not in dirs:
                dirs.append(d)
    return dirs or [robot.root.parent]


def pinocchio_urdf(loaded: LoadedDescription, scene: CollisionScene, kin: Kinematics, meshes: MeshStore) -> str:
    """The expanded URDF as pinocchio can read it, with exactly the collision shapes of
    geomcheck's scene: shapes it could not use are removed, each mesh named by the absolute path
    of the file geomcheck read (a build product of a package that
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
            if isinstance(found, LoadedMesh) and mesh is not None:  # the very file geomcheck read
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


@dataclass
class Agreement:
    pairs: int  # link pairs of the matrix
    disagreements: list[tuple[tuple[str, str], str, str]]  # pair, geomcheck's class, pinocchio's
    moved: list[str]  # pairs the witness search moved out of Never (no sample collided), described
    broken: list[tuple[tuple[str, str], int]]  # certified pairs pinocchio found in collision, and how often

    @property
    def bad(self) -> int:
        return len(self.disagreements) + len(self.broken)

    def summary(self) -> str:
        same = self.pairs - len(self.disagreements) - len(self.moved)
        text = f"{same}/{self.pairs} same, {len(self.moved)} witness"
        return text + (f", {len(self.broken)} CERTIFIED HIT" if self.broken else "")


def compare(matrix: CollisionMatrix, run: PinocchioRun, adjacent: set[tuple[str, str]]) -> Agreement:
    """The pair-by-pair comparison of the two classifications."""
    result = Agreement(len(matrix.pairs), [], [], [])
    for pair in matrix.pairs:
        theirs = pinocchio_class(pair.links, run, adjacent, matrix.samples, matrix.always_fraction)
        if pair.certified and run.hits.get(pair.links, 0):
            result.broken.append((pair.links, run.hits[pair.links]))
        if pair.cls is theirs:
            continue
        searched = pair.witness is not None and pair.witness.source is WitnessSource.SEARCH
        if searched and theirs is PairClass.NEVER:
            w = pair.witness
            assert w is not None
            result.moved.append(f"{pair.links[0]} / {pair.links[1]}: {w.depth * 1000:.1f} mm deep at {w.describe(4)}")
        else:
            result.disagreements.append((pair.links, pair.cls.value, theirs.value))
    return result


def print_details(agreement: Agreement) -> None:
    for links, mine, other in agreement.disagreements:
        print(f"    {links[0]} / {links[1]}: geomcheck {mine}, pinocchio {other}")
    for text in agreement.moved:
        print(f"    moved out of Never by the witness search (no sample collided): {text}")
    for links, hits in agreement.broken:
        print(f"    CERTIFIED PAIR IN COLLISION IN PINOCCHIO: {links[0]} / {links[1]} ({hits} samples)")


@dataclass
class Row:
    name: str
    links: int = 0
    pairs: int = 0
    samples: int = 0
    ours: float = float("nan")  # in-process matrix, median of the runs [s]
    whole: float = float("nan")  # geomcheck matrix, fresh interpreter, empty cache [s]
    pinocchio: float = float("nan")  # the computeCollisions loop [s]
    agreement: str = ""
    bad: int = 0
    reason: str = ""  # why the robot has no comparison

    def line(self) -> str:
        head = f"{self.name:32.32s} {self.links:5d} {self.pairs:6d} {self.samples:7d}"
        if self.reason:
            return f"{head} {self.ours:8.2f} {self.whole:8.2f}  -- {self.reason}"
        return (
            f"{head} {self.ours:8.2f} {self.whole:8.2f} {self.pinocchio:8.2f} {self.pinocchio / self.ours:8.1f}x "
            f"{self.pinocchio / self.whole:7.1f}x  {self.agreement}"
        )


HEADER = (
    f"{'robot':32s} {'links':>5s} {'pairs':>6s} {'samples':>7s} {'ours s':>8s} {'whole s':>8s} {'pin s':>8s} "
    f"{'pin/ours':>9s} {'pin/whole':>8s}  agreement (pairs of the same class; moved by the witness search)"
)


def bench(robot: CorpusRobot, samples: int, workers: int, repeat: int, details: bool, pycache: Path) -> Row:
    row = Row(robot.name, samples=samples)
    bundle = make_bundle(robot.root, {k: str(v) for k, v in robot.packages.items()})
    with contextlib.redirect_stderr(io.StringIO()):  # xacro's warnings
        loaded = load_description(bundle, dict(robot.args))
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
    row.links, row.pairs, row.ours = len(matrix.links), len(matrix.pairs), float(np.median(times))
    with tempfile.TemporaryDirectory(prefix="geomcheck-matrix-bench-") as tmp:
        row.whole = whole_command(robot, samples, Path(tmp), pycache)
    if len(sections) != 1:
        row.reason, row.bad = "geomcheck's runs gave DIFFERENT results", 1
        return row
    if not matrix.pairs:
        row.reason = "no pair of links with collision geometry"
        return row
    try:
        text = pinocchio_urdf(loaded, scene, kin, meshes)
        run = run_pinocchio(text, package_dirs(robot), kin, q0, draw_samples(kin, settings))
    except Exception as error:  # pinocchio cannot read the robot: a row with the reason, not a crash
        first = (str(error).strip().splitlines() or [""])[0]
        row.reason = f"pinocchio: {type(error).__name__}: {first[:80]}"
        return row
    row.pinocchio = run.seconds
    agreement = compare(matrix, run, adjacent_pairs(loaded.robot, matrix.links))
    row.agreement, row.bad = agreement.summary(), agreement.bad
    if details:
        print_details(agreement)
    return row


def versions() -> str:
    """The versions of pinocchio and of the collision library both engines use: the loop's time
    depends on them (figures measured with other versions are not comparable)."""
    import coal
    import pinocchio as pin

    return f"{pin.__version__}, coal {coal.__version__}"


def whole_command(robot: CorpusRobot, samples: int, cache_dir: Path, pycache: Path) -> float:
    """Wall-clock seconds [s] of ``geomcheck matrix`` in a fresh interpreter, with an empty cache.

    geomcheck's modules are compiled to bytecode first (into ``pycache``, by an untimed run on
    one sample without the cache), as an installed geomcheck's are: the figure does not count
    compiling the sources, which ``PYTHONDONTWRITEBYTECODE`` would otherwise make every run pay."""
    packages = [a for name, d in robot.packages.items() for a in ("--package", f"{name}={d}")]
    args = [a for name, value in robot.args.items() for a in ("--arg", f"{name}={value}")]
    argv = [sys.executable, "-m", "geomcheck", "matrix", str(robot.root), *packages, *args]
    argv += ["--srdf-out", str(cache_dir / "out.srdf")]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env |= {"GEOMCHECK_CACHE_DIR": str(cache_dir / "cache"), "GEOMCHECK_UNTRUSTED": "0"}
    env["PYTHONPYCACHEPREFIX"] = str(pycache)
    subprocess.run([*argv, "--samples", "1", "--no-cache"], env=env, check=True, capture_output=True)
    started = time.perf_counter()
    subprocess.run([*argv, "--samples", str(samples)], env=env, check=True, capture_output=True)
    return time.perf_counter() - started


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--robot", action="append", metavar="NAME", help="a table of robots.toml (repeatable)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=1, help="geomcheck runs in process (the median is compared)")
    parser.add_argument("--details", action="store_true", help="list the pairs whose classes differ")
    ns = parser.parse_args()
    corpus = corpus_dir()
    if corpus is None:
        sys.exit("corpus not found: set GEOMCHECK_CORPUS")
    chosen = [r for r in checked_robots(corpus) if r.format == "urdf" and (not ns.robot or r.name in ns.robot)]
    unknown = set(ns.robot or ()) - {r.name for r in chosen}
    if unknown:
        sys.exit(f"not a URDF robot of robots.toml: {', '.join(sorted(unknown))}")
    print("load average (1, 5, 15 min): " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    print(f"pinocchio {versions()}; {ns.workers} workers in process, {ns.samples} samples")
    print(HEADER, flush=True)
    rows = []
    pycache_dir = tempfile.TemporaryDirectory(prefix="geomcheck-matrix-bench-pycache-")
    pycache = Path(pycache_dir.name)
    for robot in chosen:
        try:
            row = bench(robot, ns.samples, ns.workers, ns.repeat, ns.details, pycache)
        except Exception as error:  # geomcheck itself failed: reported, the run goes on
            row = Row(robot.name, samples=ns.samples, reason=f"geomcheck: {type(error).__name__}: {error}"[:100], bad=1)
        rows.append(row)
        print(row.line(), flush=True)
    compared = [r for r in rows if not r.reason]
    if compared:
        inproc = [r.pinocchio / r.ours for r in compared]
        whole = [r.pinocchio / r.whole for r in compared]
        print(
            f"median ratio over {len(compared)} robots: pinocchio/ours {statistics.median(inproc):.1f}x, "
            f"pinocchio/whole command {statistics.median(whole):.1f}x (target 15x; least {min(whole):.2f}x, "
            f"target 1x); {sum(r.bad for r in rows)} disagreements or certified pairs hit"
        )
    print("load average at the end: " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    pycache_dir.cleanup()
    return 1 if any(r.bad for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
