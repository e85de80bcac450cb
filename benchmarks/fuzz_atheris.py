"""Coverage-guided fuzzing of the loader, the xacro layer and the mesh readers with atheris.

    pip install -e '.[fuzz]'
    GEOMCHECK_CORPUS=../shared/corpus python benchmarks/fuzz_atheris.py --target urdf --seconds 600
    python benchmarks/fuzz_atheris.py --target mesh --seconds 600 --seed 1

Targets: ``urdf`` (bytes as a plain URDF), ``xacro`` (bytes as a xacro document, confined as
an upload), ``mesh`` (bytes as an STL, OBJ or DAE file chosen by the first byte, loaded and
checked). The seed inputs are the corpus's URDF and xacro files (when GEOMCHECK_CORPUS is
set) and a small robot. An input fails the harness when it raises anything but a
:class:`GeomcheckError`, warns, takes more than ``--max-seconds``, or grows the process by
more than 1 GiB. Prints the executions, the distinct failures and the seconds spent.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
import warnings
from pathlib import Path

SMALL_ROBOT = b"""<?xml version="1.0"?>
<robot name="seed" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="r" value="0.05"/>
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="arm"><visual><geometry><cylinder radius="${r}" length="0.3"/></geometry></visual></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""
MESH_URDF = """<robot name="m"><link name="a"><visual><geometry><mesh filename="{name}"/></geometry></visual>
<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link></robot>"""
MESH_SUFFIXES = (".stl", ".obj", ".dae")


def seeds(target: str) -> list[bytes]:
    found = [SMALL_ROBOT]
    corpus = os.environ.get("GEOMCHECK_CORPUS")
    if corpus and target != "mesh":
        pattern = "*.urdf" if target == "urdf" else "*.xacro"
        found += [p.read_bytes() for p in sorted(Path(corpus).rglob(pattern)) if p.stat().st_size < 100_000]
    if target == "mesh":
        found = [b"\0solid x\nendsolid x\n", b"\1v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"]
    return found


def run_one(target: str, data: bytes, folder: Path) -> None:
    from geomcheck.errors import GeomcheckError
    from geomcheck.load import load_description, make_bundle

    try:
        if target == "mesh":
            from geomcheck.options import CheckOptions
            from geomcheck.pipeline import run_check

            name = f"part{MESH_SUFFIXES[data[0] % 3] if data else '.stl'}"
            (folder / name).write_bytes(data[1:])
            (folder / "robot.urdf").write_text(MESH_URDF.format(name=name))
            run_check(make_bundle(folder / "robot.urdf", display_root=folder), CheckOptions(sweep=False))
        else:
            root = folder / ("robot.urdf" if target == "urdf" else "robot.urdf.xacro")
            root.write_bytes(data)
            load_description(make_bundle(root, display_root=folder, confined=True))
    except GeomcheckError:
        pass


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", choices=("urdf", "xacro", "mesh"), default="urdf")
    parser.add_argument("--seconds", type=float, default=60.0, help="campaign length [s]")
    parser.add_argument("--max-seconds", type=float, default=10.0, help="longest one input may take [s]")
    parser.add_argument("--seed", type=int, default=0)
    ns = parser.parse_args()

    import atheris

    with atheris.instrument_imports():
        import geomcheck.load.meshes
        import geomcheck.load.urdf
        import geomcheck.load.xacro_expand
        import geomcheck.load.xmlsafe  # noqa: F401

    folder = Path(tempfile.mkdtemp(prefix="geomcheck-fuzz-"))
    corpus_dir = folder / "corpus"
    corpus_dir.mkdir()
    for index, data in enumerate(seeds(ns.target)):
        (corpus_dir / f"seed{index}").write_bytes(data)
    work = folder / "work"
    work.mkdir()
    baseline_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    stats = {"executions": 0, "failures": 0}
    started = time.monotonic()

    def test_one(data: bytes) -> None:
        stats["executions"] += 1
        begin = time.monotonic()
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            run_one(ns.target, data, work)
        elapsed = time.monotonic() - begin
        grown_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - baseline_kb
        if elapsed > ns.max_seconds or grown_kb > 1024 * 1024:
            raise RuntimeError(f"input took {elapsed:.1f} s and grew the process by {grown_kb // 1024} MiB")
        if time.monotonic() - started > ns.seconds:
            print(f"{ns.target}: {stats['executions']} executions in {time.monotonic() - started:.0f} s, no failure")
            sys.stdout.flush()
            os._exit(0)

    atheris.Setup([sys.argv[0], str(corpus_dir), f"-seed={ns.seed}", "-rss_limit_mb=2048"], test_one)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
