"""How far a check has come: its stage and the fraction done, for whoever listens.

A check run goes through stages (loading, then each check family the selection keeps); the
long ones (the continuous-joint sweeps, the collision matrix's samples) count their steps
through :class:`Progress`. A listener (:func:`listening`) hears every change as a
:class:`StageProgress`: the command line draws one bar on a terminal's stderr, the service's
check process writes it where the service reads it for ``GET /v1/checks/{id}``. Elsewhere
(a CI log, a pipe) the command line writes one line per stage once a run takes more than a
few seconds (:class:`StageLines`; none with ``--quiet``). Without a listener nothing is
computed nor drawn: JSON output and files never see a bar.
"""

from __future__ import annotations

import contextlib
import contextvars
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from types import TracebackType


@dataclass(frozen=True)
class StageProgress:
    """Stage ``name`` (``index`` of ``count`` stages, from 0) and the ``fraction`` of it done
    [0, 1], in the run's ``phase`` (``""``: the check itself; ``"fixes"``: verifying its fixes
    after the report, a stage list of its own)."""

    name: str
    index: int
    count: int
    fraction: float = 0.0
    phase: str = ""

    @property
    def overall(self) -> float:
        """The fraction of the whole run done [0, 1] (every stage counted alike)."""
        return min(1.0, (self.index + min(max(self.fraction, 0.0), 1.0)) / max(self.count, 1))

    def to_dict(self) -> dict[str, object]:
        phase = {"phase": self.phase} if self.phase else {}
        return {
            "stage": self.name,
            "stage_index": self.index,
            "stages": self.count,
            "stage_fraction": round(self.fraction, 3),
            "fraction": round(self.overall, 3),
            **phase,
        }


Listener = Callable[[StageProgress], None]
_LISTENER: contextvars.ContextVar[Listener | None] = contextvars.ContextVar("geomcheck_progress", default=None)
_STAGE: contextvars.ContextVar[StageProgress | None] = contextvars.ContextVar("geomcheck_stage", default=None)
_PHASE: contextvars.ContextVar[str] = contextvars.ContextVar("geomcheck_phase", default="")


@contextlib.contextmanager
def listening(listener: Listener | None) -> Iterator[None]:
    """Send every stage change and advance inside the block to ``listener``."""
    token = _LISTENER.set(listener)
    stage = _STAGE.set(None)
    try:
        yield
    finally:
        _STAGE.reset(stage)
        _LISTENER.reset(token)


def listened() -> bool:
    return _LISTENER.get() is not None


def clear_display() -> None:
    """Clear a listener's drawing (a terminal bar) before other text goes to the terminal; it
    is drawn again at the next advance."""
    clear = getattr(_LISTENER.get(), "clear", None)
    if callable(clear):
        clear()


def stage(name: str, index: int, count: int) -> None:
    """The run enters stage ``name`` (``index`` of ``count``)."""
    listener = _LISTENER.get()
    if listener is None:
        return
    current = StageProgress(name, index, count, phase=_PHASE.get())
    _STAGE.set(current)
    listener(current)


@contextlib.contextmanager
def phase(name: str) -> Iterator[None]:
    """The stages entered inside the block belong to phase ``name`` (a stage list of its own,
    after the check's: ``"fixes"``, verifying the fixes its report offers)."""
    token = _PHASE.set(name)
    try:
        yield
    finally:
        _PHASE.reset(token)


@contextlib.contextmanager
def nested(start: float, end: float) -> Iterator[None]:
    """The stages run inside the block (a whole check) count as the part ``start`` to ``end``
    of the current stage, so the stage list never goes backwards: each round verifying fixes
    checks the description again, within the one stage "verifying fixes". Without a current
    stage nothing inside is heard."""
    listener, outer = _LISTENER.get(), _STAGE.get()
    if listener is None or outer is None:
        with listening(None):
            yield
        return

    def inner(progress: StageProgress) -> None:
        listener(replace(outer, fraction=start + (end - start) * progress.overall))

    stage_fraction(start)
    with listening(inner):
        yield
    stage_fraction(end)


def stage_fraction(fraction: float) -> None:
    """The current stage is ``fraction`` done."""
    listener, current = _LISTENER.get(), _STAGE.get()
    if listener is not None and current is not None:
        current = replace(current, fraction=fraction)
        _STAGE.set(current)
        listener(current)


class Progress:
    """``total`` steps of the current stage (a sweep's joints, the matrix's samples); each
    :meth:`advance` tells the listener how far the stage has come. A context manager::

        with Progress(len(joints)) as bar:
            for joint in joints:
                ...
                bar.advance()
    """

    def __init__(self, total: int, description: str = "", *, enabled: bool = True, unit: str = "step") -> None:
        self.total, self.done = max(total, 0), 0
        self.description, self.unit = description, unit
        self._enabled = enabled and self.total > 0 and listened()

    @property
    def enabled(self) -> bool:
        return self._enabled

    def advance(self, steps: int = 1, note: str | None = None) -> None:
        """Count ``steps`` more steps done (``note``, a joint or pair name, is for the reader)."""
        if not self._enabled:
            return
        self.done += steps
        stage_fraction(self.done / self.total)

    def close(self) -> None:
        self._enabled = False

    def __enter__(self) -> Progress:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()


class Throttled:
    """A listener passing to ``listener`` every new stage and the end of each, and otherwise at
    most one advance every ``min_interval_s`` [s]: a sample loop may advance thousands of
    times a second, and each call of a listener may cost a write to a pipe or a database."""

    def __init__(self, listener: Listener, min_interval_s: float) -> None:
        self.listener = listener
        self.min_interval_s = min_interval_s
        self._last = -float("inf")
        self._stage: tuple[str, int] | None = None

    def __call__(self, progress: StageProgress) -> None:
        now = time.monotonic()
        stage = (progress.name, progress.index)
        if stage == self._stage and progress.fraction < 1.0 and now - self._last < self.min_interval_s:
            return
        self._stage, self._last = stage, now
        self.listener(progress)


class TerminalBar:
    """A listener drawing one bar on a terminal (stderr): ``[3/8] fit ▕████▏ 42%``; cleared
    when the run ends, so it leaves nothing in the scrollback."""

    def __init__(self, stream: object, min_interval_s: float = 0.1) -> None:
        self.stream = stream
        self.min_interval_s = min_interval_s
        self._last = 0.0
        self._shown = False

    def __call__(self, progress: StageProgress) -> None:
        now = time.monotonic()
        if progress.fraction not in (0.0, 1.0) and now - self._last < self.min_interval_s:
            return
        self._last = now
        width = 20
        filled = round(progress.overall * width)
        bar = "#" * filled + "-" * (width - filled)
        step = f"[{progress.index + 1}/{progress.count}]"
        # the line is erased first: a shorter text would leave the end of the longer one before it
        text = f"\r\x1b[2Kgeomcheck {step} {progress.name:<14} [{bar}] {progress.overall:4.0%}"
        self.stream.write(text)  # type: ignore[attr-defined]
        self.stream.flush()  # type: ignore[attr-defined]
        self._shown = True

    def clear(self) -> None:
        if self._shown:
            self.stream.write("\r\x1b[2K")  # type: ignore[attr-defined]
            self.stream.flush()  # type: ignore[attr-defined]
            self._shown = False


LINES_AFTER_S = 5.0  # a run writes its stage lines once it has taken this long: a quick check writes none [s]
LINES_AFTER_ENV = "GEOMCHECK_PROGRESS_AFTER_S"  # sets it (seconds), for a CI job that wants the lines sooner or later


class StageLines:
    """A listener writing one line per stage to a log (a CI job's stderr, a pipe), no bar:
    ``geomcheck: [5/8] selfcollision (12.3 s)``, the time since the run started. Nothing is
    written before the run has taken ``after_s``: a quick check leaves the log as it was. A
    stage that began earlier and is still running then (a 40 s sweep) gets its line at that
    moment, from a timer, since the stage itself may not advance for a long while."""

    def __init__(self, stream: object, after_s: float = LINES_AFTER_S) -> None:
        self.stream = stream
        self.after_s = after_s
        self._started = time.monotonic()
        self._lock = threading.Lock()
        self._current: StageProgress | None = None
        self._written: tuple[str, int, int] | None = None  # the stage last written
        self._timer: threading.Timer | None = None
        self._closed = False

    def __call__(self, progress: StageProgress) -> None:
        with self._lock:
            self._current = progress
            if self._timer is None and not self._closed:  # started with the run's first stage, not before
                wait = max(0.0, self.after_s - (time.monotonic() - self._started))
                self._timer = threading.Timer(wait, self._write_current)
                self._timer.daemon = True
                self._timer.start()
        self._write_current()

    def _write_current(self) -> None:
        with self._lock:
            current, elapsed = self._current, time.monotonic() - self._started
            if current is None or elapsed < self.after_s:
                return
            key = (current.name, current.index, current.count)
            if key == self._written:  # a stage advancing; a new run of the same stages is written again
                return
            self._written = key
            line = f"geomcheck: [{current.index + 1}/{current.count}] {current.name} ({elapsed:.1f} s)\n"
            self.stream.write(line)  # type: ignore[attr-defined]
            self.stream.flush()  # type: ignore[attr-defined]

    def clear(self) -> None:
        """Nothing to clear: what is written stays in the log."""

    def close(self) -> None:
        """Stop the timer: nothing more is written."""
        with self._lock:
            self._closed = True
            self._current = None
            if self._timer is not None:
                self._timer.cancel()


__all__ = [
    "LINES_AFTER_ENV",
    "LINES_AFTER_S",
    "Progress",
    "StageLines",
    "StageProgress",
    "TerminalBar",
    "Throttled",
    "clear_display",
    "listened",
    "listening",
    "nested",
    "phase",
    "stage",
    "stage_fraction",
]
