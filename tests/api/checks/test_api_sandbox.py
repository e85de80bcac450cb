"""The limited check processes: CPU, memory, wall clock, crashes, environment, stray children.

The targets are standard-library functions, importable in any child process.
"""

from __future__ import annotations

import ctypes
import importlib
import os
import subprocess
import time
from pathlib import Path

import pytest

from api.checks.sandbox import ProcessLimits, SandboxRunner, clean_environment

MiB = 1024 * 1024


def runner(cpu_s: int = 30, memory: int = 1024 * MiB, wall_s: float = 30.0) -> SandboxRunner:
    return SandboxRunner(ProcessLimits(cpu_s=cpu_s, memory_bytes=memory, wall_s=wall_s, file_bytes=16 * MiB))


def test_a_run_returns_its_value(tmp_path: Path) -> None:
    outcome = runner().run(divmod, (17, 5), tmp_path, clean_environment())
    assert outcome.ok is False  # divmod takes two arguments, not one tuple: a bug in the target
    assert outcome.status == 500 and "internal error in the check: TypeError" in outcome.reason
    outcome = runner().run(abs, -3, tmp_path, clean_environment())
    assert (outcome.ok, outcome.value) == (True, 3)


def test_cpu_time_limit_kills_the_run(tmp_path: Path) -> None:
    started = time.monotonic()
    outcome = runner(cpu_s=1).run(sum, range(10**13), tmp_path, clean_environment())
    assert not outcome.ok
    assert outcome.status == 422
    assert outcome.reason == "the check exceeded the CPU-time limit of 1 s"
    assert time.monotonic() - started < 10


def test_wall_clock_limit_kills_the_run(tmp_path: Path) -> None:
    outcome = runner(wall_s=0.5).run(time.sleep, 60, tmp_path, clean_environment())
    assert (outcome.ok, outcome.status) == (False, 422)
    assert outcome.reason == "the check exceeded the wall-clock limit of 0.5 s"
    assert outcome.seconds < 5


def test_memory_limit_is_a_memory_error(tmp_path: Path) -> None:
    outcome = runner(memory=768 * MiB).run(bytearray, 2048 * MiB, tmp_path, clean_environment())
    assert (outcome.ok, outcome.status) == (False, 422)
    assert outcome.reason == "the check exceeded the memory limit of 768 MiB"


def test_a_crash_is_reported_with_its_signal(tmp_path: Path) -> None:
    outcome = runner().run(ctypes.string_at, 0, tmp_path, clean_environment())
    assert (outcome.ok, outcome.status) == (False, 422)
    assert outcome.reason == "the check process died with SIGSEGV"


def test_the_environment_of_the_service_does_not_reach_a_check(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GEOMCHECK_DATABASE_URL", "postgresql+psycopg://user:secret@db/x")
    env = clean_environment()
    assert "GEOMCHECK_DATABASE_URL" not in env
    assert runner().run(os.getenv, "GEOMCHECK_DATABASE_URL", tmp_path, env).value is None
    assert runner().run(os.getenv, "HOME", tmp_path, env).value is None
    assert runner().run(os.getenv, "SOURCE_DATE_EPOCH", tmp_path, env).value == "1767225600"
    assert runner().run(os.path.realpath, ".", tmp_path, env).value == str(tmp_path.resolve())


def test_children_of_a_check_die_with_it(tmp_path: Path) -> None:
    pid_file = tmp_path / "pid"
    command = f"sleep 60 & echo $! > {pid_file}"
    outcome = runner().run(os.system, command, tmp_path, clean_environment())
    assert outcome.ok
    pid = int(pid_file.read_text())
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        state = subprocess.run(["ps", "-o", "stat=", "-p", str(pid)], capture_output=True, text=True).stdout.strip()
        if not state or state.startswith("Z"):
            break
        time.sleep(0.05)
    assert not state or state.startswith("Z"), f"grandchild {pid} still running ({state})"


def test_stop_kills_running_checks(tmp_path: Path) -> None:
    import threading

    sandbox = runner()
    result = {}
    thread = threading.Thread(target=lambda: result.update(o=sandbox.run(time.sleep, 60, tmp_path, {})))
    thread.start()
    deadline = time.monotonic() + 10
    while sandbox.running == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    sandbox.stop()
    thread.join(10)
    assert result["o"].status == 503 and result["o"].reason == "the service stopped while the check ran"
    assert sandbox.run(abs, 1, tmp_path, {}).status == 503


def test_a_check_has_its_own_session_and_no_relative_import_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """'' on ``sys.path`` is the check's folder once it runs there: an uploaded module of a
    name the library imports late would run. The check is in a session of its own."""
    import sys

    (tmp_path / "planted_by_upload.py").write_text(f"open({str(tmp_path / 'ran')!r}, 'w').close()\n")
    monkeypatch.setattr(sys, "path", ["", *sys.path])  # as under `python -c` or some launchers
    outcome = runner().run(importlib.import_module, "planted_by_upload", tmp_path, clean_environment())
    assert (outcome.ok, outcome.status) == (False, 500) and "ModuleNotFoundError" in outcome.reason
    assert not (tmp_path / "ran").exists()
    assert runner().run(os.getsid, 0, tmp_path, clean_environment()).value not in (None, os.getsid(0))


def _children(pid: int) -> list[int]:
    out = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True).stdout
    return [int(p) for p in out.split()]


def _alive(pid: int) -> bool:
    state = subprocess.run(["ps", "-o", "stat=", "-p", str(pid)], capture_output=True, text=True).stdout.strip()
    return bool(state) and not state.startswith("Z")


def test_checks_die_with_a_killed_server(tmp_path: Path) -> None:
    """After a SIGKILL of the service its forkserver and running checks must not live on."""
    import signal
    import sys

    script = (
        "import time\nfrom pathlib import Path\n"
        "from api.checks.sandbox import ProcessLimits, SandboxRunner, clean_environment\n"
        "limits = ProcessLimits(cpu_s=60, memory_bytes=1 << 30, wall_s=60, file_bytes=1 << 24)\n"
        f"SandboxRunner(limits, preload=()).run(time.sleep, 60, Path({str(tmp_path)!r}), clean_environment())\n"
    )
    server = subprocess.Popen([sys.executable, "-c", script])
    try:
        deadline = time.monotonic() + 30
        checks: list[int] = []
        while not checks and time.monotonic() < deadline:
            checks = [c for f in _children(server.pid) for c in _children(f)]
            time.sleep(0.05)
        assert checks, "no check process started"
        forkservers = _children(server.pid)
    finally:
        server.send_signal(signal.SIGKILL)
        server.wait()
    deadline = time.monotonic() + 10
    while any(_alive(p) for p in (*checks, *forkservers)) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not [p for p in (*checks, *forkservers) if _alive(p)]


def test_a_check_imports_nothing_from_the_servers_start_folder(tmp_path: Path) -> None:
    """A server started with '' on ``sys.path`` (``python -c``, some launchers) from a folder
    holding a module: multiprocessing hands the check processes that folder as an absolute
    path, so a ``yaml.py`` lying there ran inside every check that imported yaml late."""
    import sys

    start, work = tmp_path / "start", tmp_path / "work"
    start.mkdir()
    work.mkdir()
    (start / "planted_in_start.py").write_text(f"open({str(tmp_path / 'ran')!r}, 'w').close()\n")
    script = (
        "import importlib, sys\nfrom pathlib import Path\n"
        "from api.checks.sandbox import ProcessLimits, SandboxRunner, clean_environment\n"
        "assert sys.path[0] == ''\n"
        "limits = ProcessLimits(cpu_s=30, memory_bytes=1 << 30, wall_s=30, file_bytes=1 << 24)\n"
        "runner = SandboxRunner(limits, preload=())\n"
        f"outcome = runner.run(importlib.import_module, 'planted_in_start', Path({str(work)!r}), clean_environment())\n"
        "print(outcome.ok, outcome.status, outcome.reason)\n"
        "runner.stop()\n"
    )
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[3])}
    command = [sys.executable, "-c", script]
    done = subprocess.run(command, cwd=start, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("False 500 ") and "ModuleNotFoundError" in done.stdout, done.stdout
    assert not (tmp_path / "ran").exists()
