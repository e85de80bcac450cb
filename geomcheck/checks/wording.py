"""How the rule families write numbers and directions in their messages: lengths in millimetres or
metres, vectors, the link's axes by name."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from geomcheck.geometry.suggest import fmt

AXIS_NAMES = "xyz"


def length(value: float) -> str:
    """A length [m] for a message: millimetres below 0.1 m, metres above."""
    v = round(float(value), 6)
    if abs(v) < 0.1:
        return f"{v * 1000:.0f} mm" if abs(v) >= 0.01 else f"{v * 1000:.1f} mm"
    return f"{v:.3g} m"


def millimetres(metres: float) -> str:
    """A depth or clearance [m] in millimetres to a tenth, whatever its size (``12.7 mm``)."""
    return f"{metres * 1000:.1f} mm"


def listed(names: Sequence[str], shown: int) -> str:
    """``names`` for a message, the first ``shown`` of them and how many more (``a, b and 3 more``)."""
    more = f" and {len(names) - shown} more" if len(names) > shown else ""
    return ", ".join(names[:shown]) + more


def vector(v: np.ndarray) -> str:
    return "(" + ", ".join(fmt(float(c), 3) for c in v) + ") m"


def direction(v: np.ndarray) -> str:
    """``the link's x axis`` when ``v`` (3,) is one, else its components."""
    u = np.asarray(v, dtype=float) / np.linalg.norm(v)
    i = int(np.argmax(np.abs(u)))
    if abs(u[i]) > 0.999:
        return f"the link's {AXIS_NAMES[i]} axis"
    return "(" + ", ".join(f"{c:.2f}" for c in u) + ")"
