"""Untrusted mode of the CLI: a pull request from a fork is as hostile as an upload.

``geomcheck check|diff|matrix --untrusted`` (the default where ``CI=true`` and in
``action.yml``) runs the command again in a child process that

* confines every bundle as the service does: files are read only inside the current folder
  (the repository) and the named package folders, the environment is read only for the
  variables listed with ``--allow-env`` (``$(optenv NAME default)`` takes its default, as on a
  fresh machine; ``$(env NAME)`` needs ``--env NAME=VALUE`` or ``--allow-env NAME``), xacro
  expressions run under the guards and the work budget of :mod:`geomcheck.load.xacro_eval`;
* runs under a CPU-time limit (``RLIMIT_CPU``), an address-space limit (``RLIMIT_AS``) and a
  wall-clock limit enforced by the parent, which kills the child's whole process group;
  the child, in a session of its own, is killed with the parent (``PR_SET_PDEATHSIG``).

A limit that is hit ends the command with one line on stderr and exit status 2.
``GEOMCHECK_UNTRUSTED=0|1`` overrides the ``CI`` default; ``--untrusted``/``--no-untrusted``
override both.
"""

from __future__ import annotations

import argparse
import os
import resource
import signal
import subprocess
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from geomcheck.errors import UsageError

if TYPE_CHECKING:
    from geomcheck.config import Config

ENV_SWITCH = "GEOMCHECK_UNTRUSTED"
CHILD_MARK = "GEOMCHECK_UNTRUSTED_CHILD"
ALLOW_ENV = "GEOMCHECK_ALLOW_ENV"
MiB = 1024 * 1024
_TRUE = ("1", "true", "yes", "on")
_FALSE = ("0", "false", "no", "off", "")
_GRACE_S = 5.0  # between RLIMIT_CPU's soft limit (SIGXCPU) and its hard limit (SIGKILL) [s]
_PR_SET_PDEATHSIG = 1  # prctl option: the signal a process gets when its parent dies


@dataclass(frozen=True)
class UntrustedLimits:
    """Resource limits of one untrusted command."""

    cpu_s: float = 600.0  # CPU time of the child process [s]
    memory_bytes: int = 4096 * MiB  # address space of the child process [bytes]
    wall_s: float = 900.0  # wall-clock time of the whole command [s]


def add_untrusted_options(p: argparse.ArgumentParser) -> None:
    """``--untrusted`` and its limits, on the commands that read a description."""
    group = p.add_argument_group("untrusted input (default on where CI=true; see docs/ci.md)")
    group.add_argument(
        "--untrusted",
        action=argparse.BooleanOptionalAction,
        help="confine reading to this folder and the packages, read no environment variable, and limit CPU, "
        "memory and time",
    )
    group.add_argument(
        "--allow-env",
        action="append",
        default=[],
        metavar="NAME",
        help="environment variable $(env) and $(optenv) may read (--env NAME=VALUE gives a value instead)",
    )
    defaults = UntrustedLimits()
    group.add_argument("--cpu-limit", type=float, metavar="S", help=f"CPU seconds (default {defaults.cpu_s:g})")
    group.add_argument(
        "--memory-limit", type=int, metavar="MB", help=f"memory in MiB (default {defaults.memory_bytes // MiB})"
    )
    group.add_argument(
        "--time-limit", type=float, metavar="S", help=f"wall-clock seconds (default {defaults.wall_s:g})"
    )


def _flag(text: str, name: str) -> bool:
    lowered = text.strip().lower()
    if lowered in _TRUE:
        return True
    if lowered in _FALSE:
        return False
    raise UsageError.bad_choice(name, text, ("1", "0", "true", "false"))


def untrusted_requested(flag: bool | None, environ: Mapping[str, str]) -> bool:
    """Whether to run untrusted: the flag when given, else ``GEOMCHECK_UNTRUSTED``, else ``CI=true``."""
    if flag is not None:
        return flag
    if ENV_SWITCH in environ:
        return _flag(environ[ENV_SWITCH], ENV_SWITCH)
    return environ.get("CI", "").strip().lower() == "true"


def limits_from(ns: argparse.Namespace) -> UntrustedLimits:
    """The limits asked for by ``--cpu-limit``, ``--memory-limit`` and ``--time-limit``."""
    defaults = UntrustedLimits()
    cpu = ns.cpu_limit if ns.cpu_limit is not None else defaults.cpu_s
    memory = ns.memory_limit * MiB if ns.memory_limit is not None else defaults.memory_bytes
    wall = ns.time_limit if ns.time_limit is not None else defaults.wall_s
    for name, value in (("--cpu-limit", cpu), ("--memory-limit", memory), ("--time-limit", wall)):
        if not value > 0:
            raise UsageError(f"{name} must be positive, got {value:g}")
    return UntrustedLimits(cpu_s=float(cpu), memory_bytes=int(memory), wall_s=float(wall))


def in_child() -> bool:
    """Whether this process is the confined child of an untrusted command."""
    return os.environ.get(CHILD_MARK) == "1"


def confine_this_process() -> None:
    """In the child: confine every bundle, with the variables of ``GEOMCHECK_ALLOW_ENV`` readable."""
    from geomcheck.load.bundle import Confinement, confine_process

    names = frozenset(n for n in os.environ.get(ALLOW_ENV, "").split(",") if n)
    confine_process(Confinement(allowed_env=names))


def narrow_file_config(config: Config, granted: Sequence[Path]) -> Config:
    """A configuration file read in untrusted mode, held to what the command line granted.

    The file comes from the same author as the description (a pull request edits both), so
    it may narrow what the check does but never widen what it reads: its ``packages``,
    ``search``, ``srdf`` and ``baseline`` must lie inside ``granted`` (the checked folder and
    the folders of ``--package``/``--search``), symbolic links resolved, and its
    ``thresholds.limits`` may only lower the loader's limits. A :class:`UsageError` naming
    the key otherwise: silently dropping it would check another robot than the author meant.
    """
    from geomcheck.thresholds import LoadLimits

    roots = tuple(p.resolve() for p in granted)
    where = config.path.name if config.path is not None else "configuration"

    def inside(key: str, path: Path) -> None:
        if not any(path.resolve().is_relative_to(r) for r in roots):
            raise UsageError(
                f"{where}: {key} names a folder outside the checked folder, which a configuration file "
                "may not grant in untrusted mode; pass it on the command line (--package, --search)"
            )

    for name, folder in config.packages.items():
        inside(f"packages.{name}", folder)
    for folder in config.search:
        inside("search", folder)
    for key in ("srdf", "baseline"):
        value = getattr(config, key)
        if value is not None:
            inside(key, Path(value))
    defaults = LoadLimits()
    for name, value in config.thresholds.get("limits", {}).items():
        default = getattr(defaults, name)
        if value > default:
            raise UsageError(
                f"{where}: thresholds.limits.{name} may only be lowered in untrusted mode "
                f"(at most {default:g}, got {value:g})"
            )
    return config


def within_hard_limits(limits: UntrustedLimits) -> UntrustedLimits:
    """``limits`` lowered to the hard limits this process already has (``ulimit -Hv``, a CI
    runner's cgroup wrapper): a process may not raise its hard limit, so asking for more made
    ``setrlimit`` fail in the child's ``preexec_fn`` (a traceback, exit 1)."""
    import resource

    def hard(which: int) -> float:
        value = resource.getrlimit(which)[1]
        return float("inf") if value == resource.RLIM_INFINITY else float(value)

    memory = int(min(limits.memory_bytes, hard(resource.RLIMIT_AS)))
    cpu_hard = hard(resource.RLIMIT_CPU)
    cpu = min(limits.cpu_s, max(1.0, cpu_hard - _GRACE_S)) if cpu_hard != float("inf") else limits.cpu_s
    return UntrustedLimits(cpu_s=cpu, memory_bytes=memory, wall_s=limits.wall_s)


def _set_limits(limits: UntrustedLimits) -> None:
    import resource

    def capped(value: int, which: int) -> int:
        most = resource.getrlimit(which)[1]
        return value if most == resource.RLIM_INFINITY else min(value, most)

    cpu = max(1, int(limits.cpu_s + 0.999))
    resource.setrlimit(
        resource.RLIMIT_CPU,
        (capped(cpu, resource.RLIMIT_CPU), capped(cpu + int(_GRACE_S), resource.RLIMIT_CPU)),
    )
    memory = capped(limits.memory_bytes, resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def child_preparation(limits: UntrustedLimits) -> Callable[[], None]:
    """What the child runs between ``fork`` and ``exec``: the limits, and a SIGKILL when this
    process dies (``PR_SET_PDEATHSIG``), so a CI job killed with SIGKILL leaves no check running
    in its own session. ``prctl`` is looked up here, before the fork; elsewhere than on Linux
    the child only gets its limits."""
    parent = os.getpid()
    try:
        import ctypes

        prctl: Callable[..., int] | None = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        prctl = None

    def prepare() -> None:
        _set_limits(limits)
        if prctl is not None:
            prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
            if os.getppid() != parent:  # the parent died before the request took effect
                os.kill(os.getpid(), signal.SIGKILL)

    return prepare


def run_untrusted(argv: Sequence[str], limits: UntrustedLimits, allow_env: Sequence[str]) -> int:
    """Run ``geomcheck argv`` in a confined, limited child; its exit status, or 2 with one line
    on stderr when a limit stopped it."""
    limits = within_hard_limits(limits)
    env = dict(os.environ)
    env[CHILD_MARK] = "1"
    env[ALLOW_ENV] = ",".join(sorted({n.strip() for n in allow_env if n.strip()}))
    # the child never imports modules from the folder it was started in
    env.pop("PYTHONPATH", None)
    command = [sys.executable, "-P", "-c", _CHILD_MAIN, _package_folder(), *argv]
    child = subprocess.Popen(
        command,
        env=env,
        start_new_session=True,  # its own process group: killed as a whole at the limit
        preexec_fn=child_preparation(limits),  # the CLI has started no threads yet
    )

    def terminate(signum: int, frame: object) -> None:  # the CI job was cancelled: end the check too
        _kill_group(child)
        sys.exit(128 + signum)

    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        status = child.wait(timeout=limits.wall_s)
    except subprocess.TimeoutExpired:
        _kill_group(child)
        return _fail(f"wall-clock limit of {limits.wall_s:g} s exceeded (--time-limit)")
    except KeyboardInterrupt:
        _kill_group(child)
        raise
    finally:
        _kill_group(child)  # helpers the child left behind
        signal.signal(signal.SIGTERM, previous)
    if status >= 0:
        return status
    signum = -status
    if signum in (signal.SIGXCPU, signal.SIGKILL):
        return _fail(f"CPU time limit of {limits.cpu_s:g} s exceeded (--cpu-limit)")
    if signum in (signal.SIGSEGV, signal.SIGABRT, signal.SIGBUS):
        return _fail(
            f"the check process died of {signal.Signals(signum).name}, likely the memory limit of "
            f"{limits.memory_bytes // MiB} MiB (--memory-limit)"
        )
    return _fail(f"the check process was ended by {signal.Signals(signum).name}")


# the child runs the geomcheck this process runs (an editable copy named by PYTHONPATH too),
# from its folder given as an argument, never from the folder it was started in
_CHILD_MAIN = (
    "import sys; folder = sys.argv.pop(1); sys.path.insert(0, folder) if folder else None; "
    "from geomcheck.cli import main; sys.argv[0] = 'geomcheck'; sys.exit(main())"
)


def _package_folder() -> str:
    """The folder holding this geomcheck package; empty when it is the current folder (the
    checked repository's own modules must never be importable in the child)."""
    folder = Path(__file__).resolve().parent.parent
    return "" if folder == Path.cwd().resolve() else str(folder)


def _kill_group(child: subprocess.Popen[bytes]) -> None:
    try:
        os.killpg(child.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        return
    child.wait()


def _fail(message: str) -> int:
    sys.stderr.write(f"geomcheck: error: {message}\n")
    return 2


def memory_message() -> str:
    """The one line a :class:`MemoryError` in the confined child becomes (``resource`` is
    imported with this module: at the limit, mapping its library then fails)."""

    limit = resource.getrlimit(resource.RLIMIT_AS)[0]
    if limit == resource.RLIM_INFINITY:
        return "out of memory"
    # the confined child's limit is --memory-limit; outside it, one set by the caller (ulimit -v)
    origin = "--memory-limit" if in_child() else "address-space limit"
    return f"memory limit of {limit // MiB} MiB exceeded ({origin})"


def out_of_memory(err: BaseException) -> bool:
    """Whether ``err`` is the address-space limit biting: a :class:`MemoryError`, or a shared
    library that could not be mapped while a module was imported."""
    text = str(err)
    return isinstance(err, MemoryError) or (
        isinstance(err, ImportError | OSError) and ("failed to map segment" in text or "Cannot allocate" in text)
    )
