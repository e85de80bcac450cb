"""Progress bars for long checks (sweeps, the collision matrix), on stderr.

Shown only when asked (:attr:`geomcheck.options.CheckOptions.progress`, which the CLI sets
only for text output to a terminal), so JSON output, files, pipes and the HTTP service
never see a bar. The bar is cleared when done: it leaves nothing in the terminal's scrollback.
"""

from __future__ import annotations

import sys
from types import TracebackType

from tqdm import tqdm


class Progress:
    """A progress bar over ``total`` steps of work; does nothing when ``enabled`` is false.

    Use as a context manager and call :meth:`advance` after each step::

        with Progress(len(joints), "sweep", enabled=options.progress) as bar:
            for joint in joints:
                ...
                bar.advance()
    """

    def __init__(self, total: int, description: str, *, enabled: bool, unit: str = "step") -> None:
        self._bar: tqdm | None = None
        if enabled and total > 0:
            self._bar = tqdm(total=total, desc=description, unit=unit, file=sys.stderr, leave=False, dynamic_ncols=True)

    @property
    def enabled(self) -> bool:
        return self._bar is not None

    def advance(self, steps: int = 1, note: str | None = None) -> None:
        """Count ``steps`` more steps done; ``note`` (a joint or pair name) is shown beside the bar."""
        if self._bar is None:
            return
        if note is not None:
            self._bar.set_postfix_str(note, refresh=False)
        self._bar.update(steps)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> Progress:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()
