"""Time the full check of the 2009 PR2 (load, legacy xacro, meshes, every rule; no sweep).

    python benchmarks/check_speed.py [--repeat 5] [ROOT_FILE --search DIR]

The corpus is found through GEOMCHECK_CORPUS or ../shared/corpus next to the repository.
Prints the end-to-end ``run_check`` time (min and median over the repeats) and, from a
separately instrumented run of the same steps, the time of loading and of each family.
Target: under 2 s on a 2-core machine.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

from geomcheck.checks import CheckContext, family_runners
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check

TARGET_S = 2.0
PR2 = Path("pr2_2009/pr2_description/robots/pr2.urdf.xacro")


def corpus_dir() -> Path:
    env = os.environ.get("GEOMCHECK_CORPUS")
    path = Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / "corpus"
    if not path.is_dir():
        sys.exit(f"corpus not found at {path}: set GEOMCHECK_CORPUS")
    return path


def timed_steps(root: Path, search: list[Path], options: CheckOptions) -> dict[str, tuple[float, float]]:
    """Wall-clock and CPU seconds spent loading and in each family, for one check. CPU time
    is the steadier figure on a shared machine (other processes do not inflate it)."""
    bundle = make_bundle(root, search=search)
    times: dict[str, tuple[float, float]] = {}
    wall, cpu = time.perf_counter(), time.process_time()
    loaded = load_description(bundle, options.args, options.thresholds.limits)
    times["load"] = (time.perf_counter() - wall, time.process_time() - cpu)
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(loaded.bundle, options.thresholds.limits), options=options)
    for name, run in family_runners():
        wall, cpu = time.perf_counter(), time.process_time()
        run(ctx)
        times[name] = (time.perf_counter() - wall, time.process_time() - cpu)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", nargs="?", type=Path, help="root file (default: the corpus's full 2009 PR2)")
    parser.add_argument("--search", type=Path, action="append", default=[], help="package search root")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    if args.root is None:
        corpus = corpus_dir()
        args.root, args.search = corpus / PR2, [corpus / "pr2_2009"]
    options = CheckOptions(sweep=False)
    bundle = make_bundle(args.root, search=args.search)

    totals, cpus, report = [], [], None
    for _ in range(args.repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        report = run_check(bundle, options)
        totals.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    assert report is not None
    steps = [timed_steps(args.root, args.search, options) for _ in range(args.repeat)]

    counts = report.counts
    print(
        f"{report.robot.name}: {report.robot.links} links, {report.robot.joints} joints, "
        f"{report.robot.meshes_loaded}/{report.robot.meshes_total} meshes, "
        f"{counts['error']} errors, {counts['warning']} warnings, {counts['info']} info"
    )
    verdict = "met" if min(totals) < TARGET_S else "MISSED"
    print(
        f"run_check x{args.repeat}: min {min(totals):.3f} s, median {statistics.median(totals):.3f} s, "
        f"CPU min {min(cpus):.3f} s (target {TARGET_S:.1f} s: {verdict}; load average {os.getloadavg()[0]:.1f})"
    )
    print(f"{'step':<16}{'min [s]':>10}{'median [s]':>12}{'CPU min [s]':>13}")
    for name in steps[0]:
        walls = [s[name][0] for s in steps]
        print(f"{name:<16}{min(walls):>10.3f}{statistics.median(walls):>12.3f}{min(s[name][1] for s in steps):>13.3f}")


if __name__ == "__main__":
    main()
