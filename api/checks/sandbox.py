"""Running one function in a separate, resource-limited process.

Each run forks a fresh process from a *forkserver* that has already imported the library
(:mod:`api.checks.preload`), so a run starts warm in a few milliseconds, shares nothing with
earlier runs, and can be killed without harming anything else. The process gets its own
session and process group, no relative entry on ``sys.path`` (none resolves into the
check's folder), CPU-time, address-space and file-size limits (``setrlimit``), an emptied
environment and the check's folder as working directory; the parent enforces the
wall-clock limit and kills the whole group when it is exceeded, the run is cancelled or it
ends. A run dies with the forkserver (``PR_SET_PDEATHSIG``) and with the process that
started it (it watches that process's sentinel), and the forkserver exits once no run is
left, so a service or worker killed with SIGKILL leaves no check running behind it.
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
import multiprocessing
import os
import re
import resource
import signal
import sys
import tempfile
import threading
import time
import traceback
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any, Protocol

import geomcheck.progress as progress
from api.errors import one_line
from geomcheck.errors import GeomcheckError

log = logging.getLogger("geomcheck.api")

PRELOAD = ("api.checks.preload",)
_SECRET = re.compile(r"^GEOMCHECK_|TOKEN|SECRET|PASSWORD|CREDENTIAL", re.IGNORECASE)
SAFE_ENV = ("PATH", "LANG", "LC_ALL", "SOURCE_DATE_EPOCH", "TZ")
KILLED_STATUS = 422  # a check stopped at a limit: the input cannot be processed within them
CANCELLED_STATUS = 409
CANCELLED_REASON = "cancelled by a DELETE request"
POLL_S = 0.25  # how often a waiting run looks at its cancel event and flushes its progress [s]
PROGRESS_SEND_S = 0.2  # a run sends its progress to the parent at most this often, new stages aside [s]
_PR_SET_PDEATHSIG = 1


@dataclass(frozen=True)
class ProcessLimits:
    """Limits of one run: CPU time [s], address space [bytes], wall clock [s], written file size [bytes]."""

    cpu_s: int
    memory_bytes: int
    wall_s: float
    file_bytes: int


@dataclass(frozen=True)
class Outcome:
    """How a run ended: ``value`` when ``ok``; otherwise an HTTP ``status`` and a one-line ``reason``."""

    ok: bool
    value: Any = None
    status: int = 200
    reason: str = ""
    seconds: float = 0.0


class ProgressSink(Protocol):
    """Where the parent puts a run's progress: :meth:`report` for each message of the run
    (a :meth:`geomcheck.progress.StageProgress.to_dict`), :meth:`flush` while it waits."""

    def report(self, stage: dict[str, Any]) -> None: ...
    def flush(self) -> None: ...


_EARLY: list[Callable[[Any], None]] = []  # in a run's process: hands an early result to its parent


def deliver(value: Any) -> None:
    """In a run's process, hand ``value`` to the parent before the run ends (a check's report,
    before the verification of its fixes): the parent's ``early`` callback gets it at once.
    Outside a run (a test calling the target itself) it is dropped."""
    if _EARLY:
        _EARLY[0](value)


def clean_environment(extra: Mapping[str, str] | None = None) -> dict[str, str]:
    """The environment of a run: the few harmless variables of this process plus ``extra``.

    Secrets of the service (database URL, tokens) never reach a check, and ``$(env ...)``
    in a hostile xacro finds nothing worth reading even if it got through.
    """
    env = {k: os.environ[k] for k in SAFE_ENV if k in os.environ}
    env.setdefault("PATH", "/usr/local/bin:/usr/bin:/bin")
    env.setdefault("LANG", "C.UTF-8")
    env.update({"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"})
    env.update(extra or {})
    return env


def _set_limit(kind: int, soft: int, hard: int) -> None:
    _, current_hard = resource.getrlimit(kind)
    if current_hard != resource.RLIM_INFINITY:
        soft, hard = min(soft, current_hard), min(hard, current_hard)
    resource.setrlimit(kind, (soft, hard))


def _die_with_parent() -> None:
    """Ask Linux to SIGKILL this process when its parent (the forkserver) exits; elsewhere a no-op."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):
        return


def _die_with_server() -> None:
    """End this run's whole process group as soon as the process that started it (the service
    or worker) is gone, even by SIGKILL: the run holds the forkserver's liveness pipe open, so
    the forkserver (and ``PR_SET_PDEATHSIG`` with it) would outlive a service killed mid-run."""
    parent = multiprocessing.parent_process()
    sentinel = parent.sentinel if parent is not None else None
    if sentinel is None:
        return

    def watch() -> None:
        multiprocessing.connection.wait([sentinel])
        os.killpg(0, signal.SIGKILL)

    threading.Thread(target=watch, name="geomcheck-service-watch", daemon=True).start()


def start_folders() -> tuple[str, ...]:
    """The folders ``''`` on this process's ``sys.path`` stands for, which a check must not
    import from: the current folder, and the folder the process started in (multiprocessing
    hands its children that one as an absolute path in place of ``''``). The folder holding
    the service's own packages is kept: it is the code, not a stranger's file."""
    if "" not in sys.path:
        return ()
    import multiprocessing.process

    own = {str(Path(__file__).resolve().parents[2])}
    found = {os.path.abspath(""), os.path.abspath(getattr(multiprocessing.process, "ORIGINAL_DIR", None) or "")}
    return tuple(sorted(found - own))


def _child_main(
    target: Callable[[Any], Any],
    payload: Any,
    limits: ProcessLimits,
    env: Mapping[str, str],
    workdir: str,
    conn: Connection,
    foreign: tuple[str, ...] = (),
    tell_progress: bool = False,
) -> None:
    try:
        os.setsid()  # its own session and process group: killed as a whole, no terminal's signals
    except OSError:  # already a group leader
        os.setpgid(0, 0)
    _die_with_parent()
    _die_with_server()
    # '' and other relative entries would name the check's folder (the upload) after the chdir below:
    # an uploaded yaml.py must never be imported
    # an uploaded yaml.py must never be imported; nor a module lying in the server's start folder
    sys.path[:] = [p for p in sys.path if os.path.isabs(p) and os.path.abspath(p) not in foreign]
    _set_limit(resource.RLIMIT_CPU, limits.cpu_s, limits.cpu_s + 2)
    _set_limit(resource.RLIMIT_AS, limits.memory_bytes, limits.memory_bytes)
    _set_limit(resource.RLIMIT_FSIZE, limits.file_bytes, limits.file_bytes)
    _set_limit(resource.RLIMIT_CORE, 0, 0)
    os.environ.clear()
    os.environ.update(env)
    os.chdir(workdir)
    message: tuple[Any, ...]
    # the run's stages go up the result pipe as ("progress", {...}) before its answer, and an
    # early result as ("early", value)
    listener = progress.Throttled(lambda p: conn.send(("progress", p.to_dict())), PROGRESS_SEND_S)
    _EARLY[:] = [lambda value: conn.send(("early", value))]
    try:
        with progress.listening(listener if tell_progress else None):
            message = ("ok", target(payload))
    except GeomcheckError as err:
        message = ("error", err.http_status, one_line(err))
    except MemoryError as err:
        hint = f" ({err})" if str(err) else ""
        message = (
            "error",
            KILLED_STATUS,
            f"the check exceeded the memory limit of {limits.memory_bytes >> 20} MiB{hint}",
        )
    except RecursionError:
        message = ("error", KILLED_STATUS, "the check recursed too deeply (an endlessly recursive macro?)")
    except Exception as err:  # a bug in a check: keep the traceback in the log, one line for the client
        traceback.print_exc()
        message = ("error", 500, one_line(f"internal error in the check: {type(err).__name__}: {err}"))
    try:
        conn.send(message)
    except MemoryError:
        conn.send(("error", KILLED_STATUS, f"the check exceeded the memory limit of {limits.memory_bytes >> 20} MiB"))
    conn.close()


def describe_death(exitcode: int | None, limits: ProcessLimits) -> str:
    """Why a run ended without an answer, from its exit code."""
    if exitcode is not None and exitcode < 0:
        signum = -exitcode
        if signum == signal.SIGXCPU:
            return f"the check exceeded the CPU-time limit of {limits.cpu_s} s"
        if signum == signal.SIGKILL:
            return (
                f"the check process was killed (CPU-time limit of {limits.cpu_s} s "
                f"or memory limit of {limits.memory_bytes >> 20} MiB)"
            )
        if signum == signal.SIGXFSZ:
            return f"the check tried to write a file over the limit of {limits.file_bytes >> 20} MiB"
        return f"the check process died with {signal.Signals(signum).name}"
    return f"the check process ended without an answer (exit status {exitcode})"


def _watch(
    receiver: Connection,
    deadline: float,
    cancel: threading.Event | None,
    sink: ProgressSink | None,
    early: Callable[[Any], None] | None,
) -> tuple[Any, str]:
    """Wait for a run's answer until ``deadline`` (monotonic), passing its progress to ``sink``
    and what it hands over early to ``early`` on the way. The answer (None when the pipe closed
    without one) and how the wait ended: ``answered``, ``timed out`` or ``cancelled``."""
    waits = cancel is not None or sink is not None
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return None, "timed out"
        if receiver.poll(min(remaining, POLL_S) if waits else remaining):
            try:
                message = receiver.recv()
            except (EOFError, OSError):
                message = None
            if message is None or message[0] not in ("progress", "early"):
                return message, "answered"
            if message[0] == "early":
                if early is not None:
                    early(message[1])
            elif sink is not None:
                sink.report(message[1])
        if sink is not None:
            sink.flush()
        if cancel is not None and cancel.is_set():
            return None, "cancelled"


class SandboxRunner:
    """Runs functions in limited processes (blocking, one per call); any thread may call :meth:`run`."""

    def __init__(self, limits: ProcessLimits, preload: tuple[str, ...] = PRELOAD) -> None:
        self.limits = limits
        self._context = multiprocessing.get_context("forkserver")
        self._context.set_forkserver_preload(list(preload))
        self._lock = threading.Lock()
        self._live: dict[int, Any] = {}
        self._stopping = False

    def run(
        self,
        target: Callable[[Any], Any],
        payload: Any,
        workdir: Path,
        env: Mapping[str, str],
        cancel: threading.Event | None = None,
        sink: ProgressSink | None = None,
        early: Callable[[Any], None] | None = None,
    ) -> Outcome:
        """``target(payload)`` in a fresh limited process with ``workdir`` as working directory.

        Setting ``cancel`` kills the run within :data:`POLL_S` and gives a 409 outcome. With a
        ``sink`` the run reports its stages (:mod:`geomcheck.progress`) to it while it runs;
        ``early`` gets what the run hands over before it ends (:func:`deliver`), at once, in
        this thread, while the run goes on.
        """
        if self._stopping:
            return Outcome(False, status=503, reason="the service is stopping")
        started = time.monotonic()
        receiver, sender = self._context.Pipe(duplex=False)
        process = self._context.Process(
            target=_child_main,
            args=(target, payload, self.limits, dict(env), str(workdir), sender, start_folders(), sink is not None),
            name="geomcheck-check",
        )
        process.start()  # outside the lock: the first start waits for the forkserver's imports
        with self._lock:
            self._live[id(process)] = process
            stopping = self._stopping
        sender.close()
        if stopping:
            self._kill(process)
        try:
            message, ended = _watch(receiver, started + self.limits.wall_s, cancel, sink, early)
        finally:
            self._kill(process)
            process.join()
            receiver.close()
            with self._lock:
                self._live.pop(id(process), None)
        return self._outcome(message, ended, process.exitcode, time.monotonic() - started)

    def _outcome(self, message: Any, ended: str, exitcode: int | None, seconds: float) -> Outcome:
        """The outcome of a run that sent ``message`` (None: nothing) and ended as ``ended``
        (``answered``, ``timed out`` or ``cancelled``), its process with ``exitcode``."""
        if message is not None and message[0] == "ok":
            return Outcome(True, value=message[1], seconds=seconds)
        if message is not None:
            return Outcome(False, status=int(message[1]), reason=str(message[2]), seconds=seconds)
        if self._stopping:
            return Outcome(False, status=503, reason="the service stopped while the check ran", seconds=seconds)
        if ended == "cancelled":
            return Outcome(False, status=CANCELLED_STATUS, reason=CANCELLED_REASON, seconds=seconds)
        if ended == "timed out":
            reason = f"the check exceeded the wall-clock limit of {self.limits.wall_s:g} s"
        else:
            reason = describe_death(exitcode, self.limits)
        return Outcome(False, status=KILLED_STATUS, reason=reason, seconds=seconds)

    @staticmethod
    def _kill(process: Any) -> None:
        """Kill the run's process group (its own children included), then the process itself."""
        if process.pid is None:
            return
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(process.pid, signal.SIGKILL)
        if process.exitcode is None:
            process.kill()

    def warm(self) -> None:
        """Start the forkserver and wait until it has imported the library, so the first check starts warm.

        It starts without the service's secrets in its environment, so not even the initial
        environment block of a check process (``/proc/self/environ``) holds them.
        """
        from multiprocessing import forkserver

        hidden = {k: os.environ.pop(k) for k in list(os.environ) if _SECRET.search(k)}
        try:
            forkserver.ensure_running()
        finally:
            os.environ.update(hidden)
        # the forkserver answers once it has imported the library: one trivial run waits for that
        self.run(abs, 0, Path(tempfile.gettempdir()), clean_environment())

    @property
    def stopping(self) -> bool:
        """True once :meth:`stop` was called."""
        return self._stopping

    @property
    def running(self) -> int:
        with self._lock:
            return len(self._live)

    def stop(self) -> None:
        """Refuse new runs and kill the running ones (their callers get a 503 outcome)."""
        with self._lock:
            self._stopping = True
            live = list(self._live.values())
        for process in live:
            self._kill(process)
