"""One mistake, one finding: findings a xacro macro wrote alike for several subjects.

A macro expanded for four casters writes the same collision box four times; when the box is
wrong, the four findings share their rule, severity, source line, part (``about``) and every
number, and the maintainer fixes one line. They are reported as the first of them, naming
the other subjects (``also``). Findings whose numbers differ (a mirrored mesh, another
parameter) stay apart: they are not the same mistake.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from geomcheck.diagnostics import Diagnostic

SIGNIFICANT_DIGITS = 4  # numbers equal to this many digits are the same value for grouping
LISTED_SUBJECTS = 5  # subjects named in the message; the data lists them all


def _rounded(value: Any) -> Any:
    """The numbers of ``value`` to :data:`SIGNIFICANT_DIGITS`; names and text dropped (they
    differ per expansion: ``bl_caster`` against ``br_caster``)."""
    if isinstance(value, bool) or value is None:
        return value
    if isinstance(value, int | float):
        return float(f"{value:.{SIGNIFICANT_DIGITS}g}") if math.isfinite(value) else str(value)
    if isinstance(value, Mapping):
        return {k: _rounded(v) for k, v in sorted(value.items()) if not isinstance(v, str)}
    if isinstance(value, list | tuple):
        return [_rounded(v) for v in value if not isinstance(v, str)]
    return None


def repeat_key(d: Diagnostic) -> tuple[str, ...] | None:
    """What findings of one mistake share; ``None`` for a finding that is never grouped (no
    source line, a pair of links, or already grouped)."""
    loc = d.location
    if loc is None or loc.line is None or d.links is not None or "also" in d.data:
        return None
    if d.link is None and d.joint is None:
        return None
    numbers = json.dumps(_rounded(dict(d.data)), sort_keys=True)
    place = (loc.file, str(loc.line), str(loc.column))
    return (d.code, d.severity.value, *place, d.about, "joint" if d.joint else "link", numbers)


def _expanded_line(d: Diagnostic) -> int | None:
    return d.location.expanded_line if d.location is not None else None


def group_repeats(diagnostics: Sequence[Diagnostic]) -> list[Diagnostic]:
    """``diagnostics`` (in report order) with each group of alike findings reported once, as
    its first, naming the others in its message and in ``data["also"]``."""
    first: dict[tuple[str, ...], int] = {}
    others: dict[int, list[str]] = {}
    kept: list[Diagnostic] = []
    for d in diagnostics:
        key = repeat_key(d)
        # one source line written several times lands on several lines of the expanded
        # document; elements side by side on one line (a minified file) are not a macro's
        if key is not None and key in first and _expanded_line(d) not in (None, _expanded_line(kept[first[key]])):
            others[first[key]].append(d.link or d.joint or "")
            continue
        if key is not None and key not in first:
            first[key] = len(kept)
            others[len(kept)] = []
        kept.append(d)
    for index, names in others.items():
        if names:
            d = kept[index]
            listed = ", ".join(names[:LISTED_SUBJECTS]) + (
                f" and {len(names) - LISTED_SUBJECTS} more" if len(names) > LISTED_SUBJECTS else ""
            )
            kept[index] = replace(d, message=f"{d.message} (also in {listed})", data={**d.data, "also": names})
    return kept


__all__ = ["group_repeats", "repeat_key"]
