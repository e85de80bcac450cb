"""What ``geomcheck fix --unsafe-fixes`` costs a user: wall and CPU seconds and peak memory.

    python benchmarks/fix_speed.py [--repeat 3] [ROBOT ...]

ROBOT is ``example`` (the bundled example, the default) or a table of ``robots.toml`` (the
corpus is ``$GEOMCHECK_CORPUS`` or ``../shared/corpus``). Every run is the whole command in a
fresh interpreter, in process (``GEOMCHECK_UNTRUSTED=0``), on a fresh copy of the robot's
folder (a fix writes its files) with an empty cache: what a user pays the first time. The
geomcheck package is compiled to bytecode first, as an installed wheel is. Each figure is the
median of ``--repeat`` runs; peak memory is the largest resident set of any run (the process
and what it waited for). Run it on a quiet machine and quote the load average printed first.
Target for the bundled example: at most 5 s and 400 MB.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
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
from start_speed import compile_bytecode  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

EXAMPLE = REPO / "examples" / "pr2_base"
EXAMPLE_ROOT = Path("robots/pr2_base.urdf.xacro")
TARGET_S = 5.0
TARGET_MB = 400.0


@dataclass(frozen=True)
class Run:
    wall_s: float
    cpu_s: float
    peak_mb: float
    fixed: int


@dataclass(frozen=True)
class Subject:
    """A robot as the fix command is given it, inside ``folder`` (copied afresh for every run)."""

    name: str
    folder: Path
    root: Path  # relative to folder
    packages: dict[str, Path]  # relative to folder
    args: dict[str, str]


def subjects(names: list[str]) -> list[Subject]:
    out = []
    robots: dict[str, CorpusRobot] = {}
    if any(name != "example" for name in names):
        corpus = corpus_dir()
        if corpus is None:
            sys.exit("corpus not found: set GEOMCHECK_CORPUS")
        robots = {r.name: r for r in checked_robots(corpus)}
    for name in names:
        if name == "example":
            out.append(Subject(name, EXAMPLE, EXAMPLE_ROOT, {}, {}))
            continue
        if name not in robots:
            sys.exit(f"unknown robot {name!r}: one of example, {', '.join(sorted(robots))}")
        robot = robots[name]
        folder = Path(os.path.commonpath([str(p) for p in robot.packages.values()] + [str(robot.root.parent)]))
        packages = {k: Path(v).relative_to(folder) for k, v in robot.packages.items()}
        out.append(Subject(name, folder, robot.root.relative_to(folder), packages, dict(robot.args)))
    return out


def run_once(subject: Subject, work: Path) -> Run:
    copy, cache = work / "robot", work / "cache"
    shutil.rmtree(copy, ignore_errors=True)
    shutil.rmtree(cache, ignore_errors=True)
    shutil.copytree(subject.folder, copy)
    argv = [sys.executable, "-m", "geomcheck", "fix", "--unsafe-fixes", "-q", str(copy / subject.root)]
    for name, path in subject.packages.items():
        argv += ["--package", f"{name}={copy / path}"]
    for name, value in subject.args.items():
        argv += ["--arg", f"{name}={value}"]
    env = {**os.environ, "GEOMCHECK_CACHE_DIR": str(cache), "GEOMCHECK_UNTRUSTED": "0"}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    start = time.perf_counter()
    proc = subprocess.Popen(argv, env=env, cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    stderr = proc.stderr.read() if proc.stderr else ""
    code = os.waitstatus_to_exitcode(status)
    if code not in (0, 1):
        sys.exit(f"{' '.join(argv)} exited {code}:\n{stderr}")
    found = re.search(r"^geomcheck: fixed (\d+) finding", stderr, re.MULTILINE)
    return Run(wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0, int(found.group(1)) if found else 0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["example"])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    chosen = subjects(args.robots)
    compile_bytecode()
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}, {os.cpu_count()} cores")
    print(f"{'robot':28s} {'wall s':>8s} {'CPU s':>8s} {'peak MB':>8s} {'fixed':>6s}  target")
    with tempfile.TemporaryDirectory(prefix="geomcheck-fix-bench-") as tmp:
        for subject in chosen:
            run_once(subject, Path(tmp))  # untimed: the bytecode of the libraries it imports
            runs = [run_once(subject, Path(tmp)) for _ in range(args.repeat)]
            wall = statistics.median(r.wall_s for r in runs)
            cpu = statistics.median(r.cpu_s for r in runs)
            peak = max(r.peak_mb for r in runs)
            verdict = ""
            if subject.name == "example":
                met = wall <= TARGET_S and peak <= TARGET_MB
                verdict = f"<= {TARGET_S:g} s, <= {TARGET_MB:g} MB: {'met' if met else 'MISSED'}"
            fixed = runs[0].fixed
            print(f"{subject.name:28s} {wall:8.2f} {cpu:8.2f} {peak:8.0f} {fixed:6d}  {verdict}")


if __name__ == "__main__":
    main()
