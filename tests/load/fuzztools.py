"""What the fuzz tests share: their hypothesis settings and the bounds every example is held to."""

from __future__ import annotations

import contextlib
import os
import resource
import time
import warnings
from collections.abc import Iterator

from hypothesis import HealthCheck, Phase, settings

MAX_SECONDS = 10.0  # one example, imports excluded (the time a check may take on any input) [s]
MAX_GROWTH_KIB = 1024 * 1024  # growth of the process's peak memory in one example [KiB]


def fuzz_settings(default_examples: int, suppressed: HealthCheck) -> settings:
    """A bounded, deterministic run in CI (``default_examples`` per test; the environment's
    ``GEOMCHECK_FUZZ_EXAMPLES`` for a long campaign), with one health check ``suppressed``."""
    return settings(
        max_examples=int(os.environ.get("GEOMCHECK_FUZZ_EXAMPLES", str(default_examples))),
        deadline=None,  # each example is timed by :func:`bounded`, with the bound of the guarantee
        derandomize=True,  # the same inputs on every CI run
        suppress_health_check=[suppressed],
        database=None,
        phases=[Phase.explicit, Phase.generate],  # no shrinking: a failure is reported as generated
    )


def load_factor() -> float:
    """How many times longer than on an idle machine work takes now: the last minute's load
    average per core, at least 1. A time limit catches inputs that take hours, not a busy CI
    machine (other test workers, browsers, Celery workers) stretching a check of seconds."""
    cores = os.cpu_count() or 1
    return max(1.0, os.getloadavg()[0] / cores)


@contextlib.contextmanager
def bounded() -> Iterator[None]:
    """Fails the example when it takes more than :data:`MAX_SECONDS`, grows the process's peak
    memory by more than :data:`MAX_GROWTH_KIB`, or lets a warning escape the library."""
    started = time.monotonic()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield
    elapsed = time.monotonic() - started
    grown = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - peak
    allowed = MAX_SECONDS * load_factor()
    assert elapsed < allowed, f"{elapsed:.1f} s (allowed {allowed:.1f} s at this machine's load)"
    assert grown < MAX_GROWTH_KIB, f"the process grew by {grown // 1024} MiB"
