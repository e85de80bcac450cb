"""What a check costs against the cost of reading the robot (the reading floor), per corpus robot.

The *reading floor* of a robot is one fresh Python process that imports numpy and lxml,
parses the URDF (a xacro root expanded by the ``xacro`` package first, its time counted
apart), and reads every referenced mesh into numpy arrays: binary STL with one
``numpy.frombuffer``, ASCII STL and OBJ with numpy's text parsing, COLLADA's number arrays
with lxml and ``numpy.fromstring``. No tool checks a robot faster than it reads it.

For every URDF robot of ``robots.toml`` (``scripts/corpus_robots.py``), each
measured in one run, one process per command:

- ``floor``: the reading floor (wall seconds, peak resident memory);
- ``cold``: ``geomcheck check`` with an empty stage cache;
- ``warm``: the same with the cache the cold run filled, nothing edited;
- ``gate``: a CI gate's cold check, ``--format github`` with an empty cache: its output shows
  no drawing, so it draws neither the views nor the 3D scene (the JSON report carries them);
- the ratios cold/floor, warm/floor, gate/floor and the memory ratio;
- with ``--profile``, where a cold check's time goes, in process: imports, loading (xacro,
  the model), meshes, and each check family.

    python benchmarks/start_speed.py [--robot NAME ...] [--repeat N] [--profile]
    python benchmarks/start_speed.py ROOT.urdf [ROOT.urdf.xacro ...] [--search DIR]

Root files given on the command line (robots outside the corpus) are measured instead of the
corpus, with the packages found under ``--search`` folders and above the root, and the folders
beside the root that ``package://`` names without a package (as geomcheck reads them).

Each figure is the median of ``--repeat`` runs (default 3). Run it on a quiet machine and
give the load average with the figures (printed first). geomcheck's modules are compiled to
bytecode first (:func:`compile_bytecode`), as an installed wheel's are. To measure another
checkout of geomcheck, put it first on ``PYTHONPATH``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
from corpus_robots import CorpusRobot, checked_robots, corpus_dir  # noqa: E402

FLOOR = r"""
import io, re, sys, time, json, contextlib, types
from pathlib import Path
started = time.perf_counter()
import numpy as np
from lxml import etree
urdf, root, packages, args = Path(sys.argv[1]), Path(sys.argv[2]), json.loads(sys.argv[3]), json.loads(sys.argv[4])
xacro_s = None
if root.suffix == ".xacro":  # the xacro package's own expansion, timed apart
    t = time.perf_counter()
    index = types.ModuleType("ament_index_python.packages")
    index.get_package_share_directory = lambda name: packages[name]
    sys.modules["ament_index_python"] = types.ModuleType("ament_index_python")
    sys.modules["ament_index_python.packages"] = index
    import xacro
    try:
        with contextlib.redirect_stderr(io.StringIO()):
            xacro.process_file(str(root), mappings=args).toxml()
        xacro_s = time.perf_counter() - t
    except Exception:
        pass  # current xacro cannot expand it (pre-2013 syntax)
    skipped = time.perf_counter() - t
else:
    skipped = 0.0
def resolve(name):
    if name.startswith("package://"):
        package, _, rest = name[len("package://"):].partition("/")
        return Path(packages.get(package, "/nonexistent")) / rest
    if name.startswith("file://"):
        return Path(name[len("file://"):])
    return root.parent / name
def stl(data):
    if data[:5].lower() == b"solid" and b"facet" in data[:4096]:
        numbers = re.findall(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)", data)
        return np.array(numbers, dtype=float).reshape(-1, 3, 3)
    n = int(np.frombuffer(data, "<u4", 1, 80)[0])
    rows = np.frombuffer(data, np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), n, 84)
    return rows["v"]
def dae(data):
    tree = etree.fromstring(data)
    arrays = [np.fromstring(e.text or "", sep=" ") for e in tree.iter("{*}float_array")]
    faces = [np.fromstring(e.text or "", sep=" ", dtype=np.int64) for e in tree.iter("{*}p")]
    return arrays, faces
def obj(data):
    lines = data.splitlines()
    v = np.array([l.split()[1:4] for l in lines if l.startswith(b"v ")], dtype=float)
    f = [l.split()[1:] for l in lines if l.startswith(b"f ")]
    return v, f
doc = etree.fromstring(urdf.read_bytes())
names = sorted({m.get("filename") for m in doc.iter("mesh") if m.get("filename")})
read = 0
for name in names:
    path = resolve(name)
    if not path.is_file():
        continue
    data = path.read_bytes()
    suffix = path.suffix.lower()
    (stl if suffix in (".stl", ".stlb") else dae if suffix == ".dae" else obj)(data)
    read += 1
print(json.dumps({"seconds": time.perf_counter() - started - skipped, "xacro_s": xacro_s, "meshes": read}))
"""


@dataclass
class Run:
    seconds: float
    peak_mb: float
    detail: dict[str, object]


def measured(command: list[str], env: dict[str, str], cwd: Path) -> Run:
    """``command`` with its own rusage (``os.wait4`` on its pid)."""
    started = time.perf_counter()
    process = subprocess.Popen(command, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert process.stdout is not None and process.stderr is not None
    out = process.stdout.read()
    err = process.stderr.read()
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.perf_counter() - started
    if process.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(command[:4])} exited {process.returncode}: {err.decode()[-500:]}")
    detail = json.loads(out) if out.strip().startswith(b"{") else {}
    return Run(seconds, usage.ru_maxrss / 1024, detail)


def check_command(robot: CorpusRobot, fmt: str = "json") -> list[str]:
    command = [sys.executable, "-m", "geomcheck", "check", str(robot.root), "--format", fmt, "-o", os.devnull]
    for name, folder in robot.packages.items():
        command += ["--package", f"{name}={folder}"]
    for name, value in robot.args.items():
        command += ["--arg", f"{name}={value}"]
    if robot.srdf is not None:
        command += ["--srdf", str(robot.srdf)]
    return [*command, "--no-untrusted", "--no-config"]


def expanded_urdf(robot: CorpusRobot, folder: Path) -> Path:
    """The robot's URDF text (a xacro root expanded by geomcheck, untimed) in ``folder``: what
    the floor parses, also for a root current xacro cannot expand."""
    from geomcheck.load import load_description, make_bundle

    loaded = load_description(make_bundle(robot.root, robot.packages, display_root=robot.corpus), robot.args)
    path = folder / f"{robot.name}.urdf"
    path.write_text(loaded.document.text, encoding="utf-8")
    return path


def floor_command(robot: CorpusRobot, urdf: Path) -> list[str]:
    packages = {k: str(v) for k, v in robot.packages.items()}
    return [sys.executable, "-c", FLOOR, str(urdf), str(robot.root), json.dumps(packages), json.dumps(dict(robot.args))]


def median(runs: list[Run]) -> Run:
    seconds = statistics.median(r.seconds for r in runs)
    peak = statistics.median(r.peak_mb for r in runs)
    return Run(seconds, peak, runs[0].detail)


def profile(robot: CorpusRobot) -> dict[str, float]:
    """Where a cold check's time goes, in a fresh process: imports, loading, each family."""
    code = r"""
import json, sys, time
t0 = time.perf_counter()
from geomcheck.checks import CheckContext, family_runners
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.options import CheckOptions, Selection
from pathlib import Path
robot = json.loads(sys.argv[1])
out = {"imports": time.perf_counter() - t0}
t = time.perf_counter()
bundle = make_bundle(robot["root"], robot["packages"], display_root=robot["corpus"])
options = CheckOptions(args=robot["args"], srdf=Path(robot["srdf"]) if robot["srdf"] else None)
loaded = load_description(bundle, options.args, options.thresholds.limits)
out["load"] = time.perf_counter() - t
ctx = CheckContext(loaded=loaded, meshes=MeshStore(loaded.bundle, options.thresholds.limits), options=options)
for name, run in family_runners(options.selection):
    t = time.perf_counter()
    run(ctx)
    out[name] = time.perf_counter() - t
print(json.dumps(out))
"""
    spec = {
        "root": str(robot.root),
        "packages": {k: str(v) for k, v in robot.packages.items()},
        "args": dict(robot.args),
        "srdf": str(robot.srdf) if robot.srdf else None,
        "corpus": str(robot.corpus),
    }
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "GEOMCHECK_CACHE_DIR": cache}
        result = measured([sys.executable, "-c", code, json.dumps(spec)], env, robot.corpus)
    return {k: float(v) for k, v in result.detail.items()}  # type: ignore[arg-type]


def compile_bytecode() -> Path:
    """Compile the geomcheck package that ``python -m geomcheck`` runs to bytecode, as
    installing a wheel does (pip compiles every module), so each measured process reads
    ``.pyc`` files as the floor's numpy and lxml do. An editable checkout run under
    ``PYTHONDONTWRITEBYTECODE=1`` would otherwise compile some 150 modules in every process
    (about 0.1 s of each check here). Returns the package's folder."""
    import compileall

    import geomcheck

    folder = Path(geomcheck.__file__).resolve().parent
    compileall.compile_dir(folder, quiet=1)
    return folder


def outside_robot(root: Path, search: list[Path]) -> CorpusRobot:
    """A robot outside the corpus, by its root file: its packages are those found under
    ``search`` and above the root, and the folders beside the root that its ``package://``
    filenames name without a package."""
    from geomcheck.load import load_description, make_bundle

    root = root.resolve()
    bundle = make_bundle(root, search=search, display_root=root.parent)
    packages = dict(bundle.packages)
    text = load_description(bundle).document.text
    for name in sorted(set(re.findall(r"package://([^/\"'\s]+)/", text)) - set(packages)):
        if (root.parent / name).is_dir():
            packages[name] = root.parent / name
    return CorpusRobot(name=root.name.split(".")[0], root=root, corpus=root.parent, packages=packages)


def selected_robots(args: argparse.Namespace) -> list[CorpusRobot] | None:
    """The URDF robots to measure: the root files given, else the corpus's (``None``: no corpus)."""
    if args.roots:
        return [outside_robot(Path(r), [Path(s) for s in args.search]) for r in args.roots]
    corpus = corpus_dir()
    if corpus is None:
        return None
    return [
        r for r in checked_robots(corpus) if r.format == "urdf" and (not args.robot or r.name in args.robot)
    ]  # the floor parses URDF: MJCF and SDFormat robots have no floor here yet


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("roots", nargs="*", help="root files of robots outside the corpus (URDF or xacro)")
    parser.add_argument("--search", action="append", default=[], help="folder to find their packages in")
    parser.add_argument("--robot", action="append", default=[], help="only this robots.toml table (repeatable)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per figure; the median is printed")
    parser.add_argument("--profile", action="store_true", help="also where a cold check's time goes")
    args = parser.parse_args(argv)
    robots = selected_robots(args)
    if robots is None:
        print("no corpus: set GEOMCHECK_CORPUS, or give root files")
        return 2
    print(f"geomcheck from {compile_bytecode()} (compiled to bytecode, as an installed wheel is)")
    print(f"load average at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}; repeat {args.repeat}")
    header = (
        f"{'robot':32s} {'floor s':>8s} {'xacro s':>8s} {'cold s':>8s} {'warm s':>8s} {'cold/fl':>8s} {'warm/fl':>8s}"
    )
    header += f" {'gate s':>7s} {'gate/fl':>8s} {'floor MB':>9s} {'cold MB':>8s} {'mem x':>6s} {'gate MB':>8s}"
    print(header)
    cold_ratios, warm_ratios, gate_ratios = [], [], []
    for robot in robots:
        floors, colds, warms, gates = [], [], [], []
        scratch = tempfile.TemporaryDirectory()
        urdf = expanded_urdf(robot, Path(scratch.name))
        for _ in range(args.repeat):
            floors.append(measured(floor_command(robot, urdf), dict(os.environ), robot.corpus))
            with tempfile.TemporaryDirectory() as cache:
                env = {**os.environ, "GEOMCHECK_CACHE_DIR": cache}
                colds.append(measured(check_command(robot), env, robot.corpus))
                warms.append(measured(check_command(robot), env, robot.corpus))
            with tempfile.TemporaryDirectory() as cache:
                env = {**os.environ, "GEOMCHECK_CACHE_DIR": cache}
                gates.append(measured(check_command(robot, "github"), env, robot.corpus))
        scratch.cleanup()
        floor, cold, warm, gate = median(floors), median(colds), median(warms), median(gates)
        expansions = [float(str(f.detail["xacro_s"])) for f in floors if f.detail.get("xacro_s") is not None]
        xacro_s = statistics.median(expansions) if expansions else 0.0
        base = floor.seconds + xacro_s  # a xacro robot's floor includes xacro's own expansion
        cold_ratios.append(cold.seconds / base)
        warm_ratios.append(warm.seconds / base)
        gate_ratios.append(gate.seconds / base)
        shown_xacro = f"{xacro_s:8.2f}" if expansions or robot.root.suffix != ".xacro" else f"{'n/a':>8s}"
        print(
            f"{robot.name:32s} {floor.seconds:8.2f} {shown_xacro} {cold.seconds:8.2f} {warm.seconds:8.2f} "
            f"{cold.seconds / base:8.1f} {warm.seconds / base:8.1f} {gate.seconds:7.2f} {gate.seconds / base:8.1f} "
            f"{floor.peak_mb:9.0f} {cold.peak_mb:8.0f} {cold.peak_mb / floor.peak_mb:6.1f} {gate.peak_mb:8.0f}",
            flush=True,
        )
        if args.profile:
            parts = profile(robot)
            print("    profile: " + ", ".join(f"{k} {v:.2f} s" for k, v in parts.items()), flush=True)
    if cold_ratios:
        print(
            f"median cold/floor {statistics.median(cold_ratios):.1f} (max {max(cold_ratios):.1f}); "
            f"median warm/floor {statistics.median(warm_ratios):.1f}; "
            f"median gate/floor {statistics.median(gate_ratios):.1f} (max {max(gate_ratios):.1f})"
        )
    print(f"load average at end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
