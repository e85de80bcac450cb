"""Time and peak memory of a whole ``geomcheck check`` as meshes and link counts grow.

    python benchmarks/mesh_scaling.py [--sizes 5 6 7 8] [--chain 2000] [--arm] [--pr2]

Each case is written to a temporary folder and checked by ``geomcheck check --format json``
in its own process; the figures are that process's wall time and peak resident memory
(the process's own ``VmHWM``), so start-up and imports are included, as a user sees them.

Cases:
- one link whose visual is a trimesh icosphere of radius 0.1 m (subdivisions 5..8: 20 k to
  1.3 M triangles) in binary STL, with a collision box slightly too small (the fit runs in
  full: coverage, protrusion, suggestion, views);
- a 6-DoF arm whose seven links have COLLADA visual meshes of about 16 MB in all and
  collision cylinders;
- a chain of N small box links joined by revolute joints;
- the full 2009 PR2 from the corpus (``GEOMCHECK_CORPUS``), when present.

Targets: 1.3 M triangles under 3 s and 600 MB, growth from 82 k to 1.3 M no worse than
n log n; the arm under 3 s and 500 MB; the 2,000-link chain under 5 s and 500 MB.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

TARGETS = {"icosphere-8": (3.0, 600.0), "arm": (3.0, 500.0), "chain-2000": (5.0, 500.0)}


@dataclass(frozen=True)
class Run:
    name: str
    triangles: int
    seconds: float
    cpu_seconds: float
    peak_mb: float
    exit_code: int


# ``ru_maxrss`` of an exec'd child starts at its parent's size at fork, so the check process
# reads its own high-water mark (VmHWM of a fresh address space) as it exits.
RUNNER = """
import atexit, sys
def peak():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            sys.stderr.write("peak-kb " + line.split()[1] + "\\n")
atexit.register(peak)
from geomcheck.cli import main
sys.argv = ["geomcheck", *sys.argv[1:]]
sys.exit(main())
"""


def check(root: Path, out: Path, *extra: str) -> tuple[float, float, float, int]:
    """Wall time [s], CPU time [s], peak RSS [MB] and exit code of ``geomcheck check ROOT`` in
    its own process, the JSON report written to ``out``. CPU time (user + system) is the
    steadier figure on a shared machine."""
    cmd = [sys.executable, "-c", RUNNER, "check", str(root), "--format", "json", "-o", str(out), *extra]
    start, before = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    peak_kb = [int(line.split()[1]) for line in proc.stderr.splitlines() if line.startswith("peak-kb ")]
    if proc.returncode not in (0, 1):
        print(f"  {root.name}: exit {proc.returncode}: {proc.stderr.strip()[-500:]}", file=sys.stderr)
    return seconds, cpu, (peak_kb[-1] / 1024.0 if peak_kb else float("nan")), proc.returncode


def link(name: str, visual: str, collision: str, mass: float = 1.0, inertia: float = 0.01) -> str:
    return (
        f'<link name="{name}"><visual><geometry>{visual}</geometry></visual>'
        f"<collision>{collision}</collision>"
        f'<inertial><mass value="{mass}"/><inertia ixx="{inertia}" iyy="{inertia}" izz="{inertia}" '
        f'ixy="0" ixz="0" iyz="0"/></inertial></link>\n'
    )


def icosphere_case(folder: Path, subdivisions: int) -> tuple[Path, int]:
    mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.1)
    mesh.export(folder / "sphere.stl")
    box = '<origin xyz="0 0 0" rpy="0 0 0"/><geometry><box size="0.19 0.19 0.19"/></geometry>'
    urdf = folder / "sphere.urdf"
    body = link("ball", '<mesh filename="sphere.stl"/>', box)
    urdf.write_text(f'<robot name="sphere">\n{body}</robot>\n')
    return urdf, len(mesh.faces)


def arm_case(folder: Path, target_bytes: int = 16 * 1024 * 1024) -> tuple[Path, int]:
    """Seven capsule-like links of about ``target_bytes`` of COLLADA in all."""
    links, joints, triangles = [], [], 0
    sections = 128
    for i in range(7):
        length = 0.30 - 0.03 * i
        radius = 0.06 - 0.005 * i
        body = trimesh.creation.capsule(height=length, radius=radius, count=[sections, sections])
        body.apply_translation([0.0, 0.0, length / 2])
        path = folder / f"link{i}.dae"
        path.write_bytes(trimesh.exchange.dae.export_collada(body))
        triangles += len(body.faces)
        cyl = (
            f'<origin xyz="0 0 {length / 2:.4f}" rpy="0 0 0"/>'
            f'<geometry><cylinder radius="{radius:.4f}" length="{length + 2 * radius:.4f}"/></geometry>'
        )
        links.append(link(f"link{i}", f'<mesh filename="link{i}.dae"/>', cyl, mass=2.0 - 0.2 * i))
        if i:
            joints.append(
                f'<joint name="j{i}" type="revolute"><parent link="link{i - 1}"/><child link="link{i}"/>'
                f'<origin xyz="0 0 {0.30 - 0.03 * (i - 1):.4f}" rpy="0 {math.pi / 2 if i % 2 else 0:.6f} 0"/>'
                f'<axis xyz="0 0 1"/><limit lower="-2.9" upper="2.9" effort="10" velocity="1"/></joint>\n'
            )
    total = sum(p.stat().st_size for p in folder.glob("*.dae"))
    if total < target_bytes // 2:
        print(f"  arm: only {total / 1e6:.1f} MB of COLLADA", file=sys.stderr)
    urdf = folder / "arm.urdf"
    urdf.write_text('<robot name="arm">\n' + "".join(links) + "".join(joints) + "</robot>\n")
    return urdf, triangles


def chain_case(folder: Path, count: int) -> tuple[Path, int]:
    box = '<origin xyz="0 0 0" rpy="0 0 0"/><geometry><box size="0.02 0.02 0.05"/></geometry>'
    parts = [link(f"l{i}", '<box size="0.02 0.02 0.05"/>', box, mass=0.1, inertia=1.5e-5) for i in range(count)]
    for i in range(1, count):
        parts.append(
            f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
            '<origin xyz="0 0 0.05" rpy="0 0 0"/><axis xyz="1 0 0"/>'
            '<limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>\n'
        )
    urdf = folder / "chain.urdf"
    urdf.write_text('<robot name="chain">\n' + "".join(parts) + "</robot>\n")
    return urdf, 12 * count


def corpus_pr2() -> tuple[Path, list[str]] | None:
    env = os.environ.get("GEOMCHECK_CORPUS")
    if not env:
        return None
    root = Path(env) / "pr2_2009/pr2_description/robots/pr2.urdf.xacro"
    return (root, ["--search", str(Path(env) / "pr2_2009")]) if root.is_file() else None


def report(runs: list[Run]) -> None:
    print(f"{'case':<14} {'triangles':>10} {'time [s]':>9} {'cpu [s]':>8} {'peak [MB]':>10} {'exit':>5}  target")
    for r in runs:
        target = TARGETS.get(r.name)
        verdict = ""
        if target:
            ok = r.seconds <= target[0] and r.peak_mb <= target[1] and r.exit_code in (0, 1)
            verdict = f"{'met' if ok else 'MISSED'} (< {target[0]:g} s, < {target[1]:g} MB)"
        print(
            f"{r.name:<14} {r.triangles:>10} {r.seconds:>9.2f} {r.cpu_seconds:>8.2f} {r.peak_mb:>10.0f} "
            f"{r.exit_code:>5}  {verdict}"
        )
    # the curve the target speaks of: from the first mesh of at least 80 k triangles to the largest
    spheres = [r for r in runs if r.name.startswith("icosphere-") and r.triangles >= 80_000]
    if len(spheres) >= 2:
        a, b = spheres[0], spheres[-1]
        growth = b.triangles / a.triangles
        nlogn = growth * math.log(b.triangles) / math.log(a.triangles)
        print(
            f"growth {a.name} -> {b.name}: triangles x{growth:.2f}, time x{b.seconds / a.seconds:.2f}, "
            f"cpu x{b.cpu_seconds / a.cpu_seconds:.2f} "
            f"(n log n would be x{nlogn:.2f}), memory x{b.peak_mb / a.peak_mb:.2f}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[5, 6, 7, 8], help="icosphere subdivisions")
    parser.add_argument("--chain", type=int, nargs="*", default=[2000], help="chain lengths [links]")
    parser.add_argument("--no-arm", action="store_true")
    parser.add_argument("--no-pr2", action="store_true")
    parser.add_argument("--python-path", help="PYTHONPATH of the checked geomcheck (to measure another checkout)")
    args = parser.parse_args()
    if args.python_path:
        os.environ["PYTHONPATH"] = args.python_path
    runs: list[Run] = []
    with tempfile.TemporaryDirectory(prefix="geomcheck-scaling-") as tmp:
        for s in args.sizes:
            folder = Path(tmp) / f"sphere{s}"
            folder.mkdir()
            root, triangles = icosphere_case(folder, s)
            runs.append(Run(f"icosphere-{s}", triangles, *check(root, root.with_suffix(".json"))))
        if not args.no_arm:
            folder = Path(tmp) / "arm"
            folder.mkdir()
            root, triangles = arm_case(folder)
            mb = sum(p.stat().st_size for p in folder.glob("*.dae")) / 1e6
            print(f"arm: {mb:.1f} MB of COLLADA, {triangles} triangles")
            runs.append(Run("arm", triangles, *check(root, root.with_suffix(".json"))))
        for count in args.chain:
            folder = Path(tmp) / f"chain{count}"
            folder.mkdir()
            root, triangles = chain_case(folder, count)
            runs.append(Run(f"chain-{count}", triangles, *check(root, root.with_suffix(".json"))))
        pr2 = None if args.no_pr2 else corpus_pr2()
        if pr2 is not None:
            runs.append(Run("pr2", 0, *check(pr2[0], Path(tmp) / "pr2.json", *pr2[1])))
    np.set_printoptions(precision=3)
    report(runs)


if __name__ == "__main__":
    main()
