"""Golden reports do not depend on the CPU: ``scripts/golden.py`` compares equal with numpy's
OpenBLAS forced onto other kernels (``OPENBLAS_CORETYPE``) than the machine's own, which
recorded them. Haswell (AVX2) and Prescott (SSE3 only, reported as Katmai) sum and solve in
other orders than the AVX-512 kernel, as another machine's CPU would.

The default run compares the bundled example; ``pytest -m campaign`` compares every corpus
robot (about two minutes per kernel on an idle two-core machine).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.goldentools import golden_script

REPO = Path(__file__).resolve().parents[1]
KERNELS = ("Haswell", "Prescott")


def golden_under(kernel: str, robots: list[str], corpus: Path | None) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "OPENBLAS_CORETYPE": kernel, "OPENBLAS_VERBOSE": "2"}
    if corpus is not None:
        env["GEOMCHECK_CORPUS"] = str(corpus)
    command = [sys.executable, str(REPO / "scripts" / "golden.py"), *(f"--robot={r}" for r in robots)]
    return subprocess.run(command, capture_output=True, text=True, env=env, cwd=REPO, timeout=1800, check=False)


def assert_identical(run: subprocess.CompletedProcess[str], kernel: str, expected: int) -> None:
    assert "Core: " in run.stdout + run.stderr, "OpenBLAS did not say which kernel it took"
    lines = [line for line in run.stdout.splitlines() if line and not line.startswith(("Core:", " "))]
    assert run.returncode == 0, f"under {kernel}:\n{run.stdout}{run.stderr}"
    assert len(lines) == expected and all(line.endswith(": identical") for line in lines), run.stdout


@pytest.mark.parametrize("kernel", KERNELS)
def test_the_example_reports_as_recorded_on_another_kernel(kernel: str) -> None:
    golden = golden_script()
    run = golden_under(kernel, [golden.EXAMPLE], None)
    assert_identical(run, kernel, 1)


@pytest.mark.campaign
@pytest.mark.corpus
@pytest.mark.parametrize("kernel", KERNELS)
def test_every_corpus_robot_reports_as_recorded_on_another_kernel(corpus: Path, kernel: str) -> None:
    golden = golden_script()
    run = golden_under(kernel, [], corpus)
    assert_identical(run, kernel, len(golden.load_golden()))
