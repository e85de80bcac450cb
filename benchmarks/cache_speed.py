"""Cold and warm figures side by side: start-up, a re-check after an edit, and diff against a base.

    python benchmarks/cache_speed.py [--repeat 3]

Every figure is a whole ``geomcheck`` command in a fresh interpreter (start-up, imports,
loading and checking included), run in process (``GEOMCHECK_UNTRUSTED=0``), with the cache
in a temporary folder. Python's byte code is compiled once, by an untimed first check, into
a temporary ``PYTHONPYCACHEPREFIX`` (as an installed geomcheck and its libraries have it;
under ``PYTHONDONTWRITEBYTECODE`` every command would compile geomcheck's sources anew).
Wall-clock seconds are the median of ``--repeat`` runs; CPU seconds (user + system of the
command and its worker processes) are the steadier figure on a shared machine. The full
2009 PR2 is copied from the corpus (``$GEOMCHECK_CORPUS`` or ``../shared/corpus``) into a
temporary folder, as a git repository for the diff figures.

1. ``geomcheck rules``, against a bare interpreter and against importing everything a check
   imports (what ``rules`` paid before the imports were made lazy). Target: under 0.3 s.
2. The full PR2 checked cold (empty cache), then again after one link's collision box was
   edited (warm cache). Target: the warm re-check at most 40% of the cold check.
3. ``geomcheck diff --base HEAD~1`` after one collision box was edited and committed, with the
   base revision's findings cached by an earlier run, against one warm check of the same
   tree, and the same diff without the cache. Target: at most 1.3 times the warm check.
4. ``geomcheck matrix`` of the full PR2 with 10,000 samples, without the cache and with the
   matrix cached.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

PR2 = Path("pr2_description/robots/pr2.urdf.xacro")
HEAD_URDF = Path("pr2_description/urdf/head_v0/head.urdf.xacro")
HEAD_BOX = '<box size="0.188 0.219 0.137" />'
EDITED_BOXES = ('<box size="0.198 0.219 0.137" />', '<box size="0.150 0.219 0.137" />')
# what `geomcheck check` imports, which `geomcheck rules` imported before the imports were lazy
EAGER_IMPORTS = (
    "import geomcheck.cli, geomcheck.pipeline, geomcheck.load.loader, geomcheck.checks.fit, "
    "geomcheck.checks.meshes, geomcheck.checks.selfcollision, geomcheck.checks.matrix, geomcheck.checks.views"
)
RULES_TARGET_S = 0.3
RECHECK_TARGET = 0.40
DIFF_TARGET = 1.3


@dataclass(frozen=True)
class Timing:
    wall: list[float]
    cpu: list[float]

    @property
    def wall_s(self) -> float:
        return statistics.median(self.wall)

    @property
    def cpu_s(self) -> float:
        return statistics.median(self.cpu)

    def show(self) -> str:
        return f"{self.wall_s:6.3f} s wall  {self.cpu_s:6.3f} s CPU"


def corpus_dir() -> Path:
    env = os.environ.get("GEOMCHECK_CORPUS")
    path = Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / "corpus"
    if not (path / "pr2_2009" / PR2).is_file():
        sys.exit(f"corpus not found at {path}: set GEOMCHECK_CORPUS")
    return path


def timed(argv: Sequence[str], env: dict[str, str], cwd: Path, allowed: Sequence[int] = (0, 1)) -> tuple[float, float]:
    """Wall-clock and CPU seconds of one command."""
    import time

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(list(argv), env=env, cwd=cwd, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode not in allowed:
        sys.exit(f"{' '.join(argv)} exited {proc.returncode}:\n{proc.stderr}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def repeat(n: int, argv: Sequence[str], env: dict[str, str], cwd: Path, before_each: object = None) -> Timing:
    walls, cpus = [], []
    for i in range(n):
        if callable(before_each):
            before_each(i)
        wall, cpu = timed(argv, env, cwd)
        walls.append(wall)
        cpus.append(cpu)
    return Timing(walls, cpus)


def geomcheck(*args: str) -> list[str]:
    return [sys.executable, "-m", "geomcheck", *args]


def git(repo: Path, *args: str) -> None:
    subprocess.run(
        ["git", "-c", "user.name=bench", "-c", "user.email=bench@example.invalid", "-c", "commit.gpgsign=false", *args],
        cwd=repo,
        check=True,
        capture_output=True,
    )


def set_head_box(repo: Path, box: str) -> None:
    path = repo / HEAD_URDF
    text = path.read_text()
    current = next(b for b in (HEAD_BOX, *EDITED_BOXES) if b in text)
    path.write_text(text.replace(current, box))


def ratio_line(name: str, value: float, target: float, better: str = "at most") -> str:
    verdict = "met" if value <= target else "MISSED"
    return f"  {name}: {value:.2f} (target {better} {target:.2f}: {verdict})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    corpus = corpus_dir()
    n = args.repeat

    with tempfile.TemporaryDirectory(prefix="geomcheck-cache-bench-") as tmp:
        work = Path(tmp)
        cache = work / "cache"
        env = {**os.environ, "GEOMCHECK_CACHE_DIR": str(cache), "GEOMCHECK_UNTRUSTED": "0"}
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(work / "pycache")
        package = Path(__file__).resolve().parents[1] / "geomcheck"
        subprocess.run([sys.executable, "-m", "compileall", "-q", str(package)], env=env, check=True)
        compile_env = {**env, "GEOMCHECK_CACHE_DIR": str(work / "compile-cache")}
        timed(geomcheck("check", str(corpus / "pr2_2009" / PR2), "--no-cache", "-o", os.devnull), compile_env, work)

        print("1. start-up")
        bare = repeat(n, [sys.executable, "-c", "pass"], env, work)
        rules = repeat(n, geomcheck("rules"), env, work)
        version = repeat(n, geomcheck("--version"), env, work)
        eager = repeat(n, [sys.executable, "-c", EAGER_IMPORTS], env, work)
        print(f"  python -c pass                       {bare.show()}")
        print(f"  geomcheck --version                  {version.show()}")
        print(f"  geomcheck rules                      {rules.show()}")
        print(f"  rules with every check import        {eager.show()}   (before: imports were eager)")
        print(f"  geomcheck rules under {RULES_TARGET_S} s: {'met' if rules.wall_s < RULES_TARGET_S else 'MISSED'}")

        repo = work / "repo"
        shutil.copytree(corpus / "pr2_2009", repo)
        git(repo, "init", "-q", "-b", "main")
        git(repo, "add", "-A")
        git(repo, "commit", "-q", "-m", "2009 PR2")
        check = geomcheck("check", str(PR2), "--search", ".", "--format", "concise", "-o", str(work / "out.txt"))

        print("\n2. full 2009 PR2: cold check, warm re-check after editing one link's collision box")

        def empty_cache(i: int) -> None:
            shutil.rmtree(cache, ignore_errors=True)

        def edit_box(i: int) -> None:
            set_head_box(repo, EDITED_BOXES[i % 2])

        cold = repeat(n, check, env, repo, before_each=empty_cache)
        unchanged = repeat(n, check, env, repo)
        edited = repeat(n, check, env, repo, before_each=edit_box)
        uncached = repeat(n, [*check, "--no-cache"], env, repo)
        print(f"  cold check (empty cache)             {cold.show()}")
        print(f"  --no-cache                           {uncached.show()}")
        print(f"  warm, nothing edited                 {unchanged.show()}")
        print(f"  warm, one link edited                {edited.show()}")
        print(ratio_line("edited / cold, wall", edited.wall_s / cold.wall_s, RECHECK_TARGET))
        print(ratio_line("edited / cold, CPU", edited.cpu_s / cold.cpu_s, RECHECK_TARGET))

        print("\n3. diff --base HEAD~1 after one collision box was edited and committed")
        set_head_box(repo, HEAD_BOX)
        git(repo, "commit", "-q", "--allow-empty", "-am", "the original box")
        set_head_box(repo, EDITED_BOXES[0])
        git(repo, "commit", "-q", "-am", "edit the head's collision box")
        diff = geomcheck("diff", "--base", "HEAD~1", str(PR2), "--search", ".", "--format", "concise")
        diff = [*diff, "-o", str(work / "diff.txt")]
        timed(diff, env, repo)  # the pull request's first run: fills the cache with the base's findings
        warm_check = repeat(n, check, env, repo)
        warm_diff = repeat(n, diff, env, repo)
        cold_diff = repeat(n, [*diff, "--no-cache"], env, repo)
        print(f"  one warm check                       {warm_check.show()}")
        print(f"  diff, base findings cached           {warm_diff.show()}")
        print(f"  diff --no-cache                      {cold_diff.show()}")
        print(ratio_line("cached diff / warm check, wall", warm_diff.wall_s / warm_check.wall_s, DIFF_TARGET))
        print(ratio_line("cached diff / warm check, CPU", warm_diff.cpu_s / warm_check.cpu_s, DIFF_TARGET))
        print(f"  uncached diff / warm check, CPU: {cold_diff.cpu_s / warm_check.cpu_s:.2f}")
        print("\n4. geomcheck matrix, 10,000 samples, as a whole command (start-up and loading included)")
        srdf = str(work / "pr2.srdf")
        matrix = geomcheck("matrix", str(PR2), "--search", ".", "--samples", "10000", "--srdf-out", srdf)
        uncached_matrix = repeat(1, [*matrix, "--no-cache"], env, repo)
        timed(matrix, env, repo)  # fills the cache
        warm_matrix = repeat(n, matrix, env, repo)
        print(f"  --no-cache                           {uncached_matrix.show()}")
        print(f"  matrix cached                        {warm_matrix.show()}")
        print("  (pinocchio's computeCollisions loop over the same samples: benchmarks/matrix_vs_pinocchio.py)")
        size = sum(p.stat().st_size for p in cache.rglob("*") if p.is_file())
        print(f"\ncache: {size / 1e6:.2f} MB in {cache}")


if __name__ == "__main__":
    main()
