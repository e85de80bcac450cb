"""Shared pieces of the HTML view model: element ids and how numbers read on the page."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable

from geomcheck.diagnostics import Diagnostic, Severity


class Anchors:
    """Unique, deterministic element ids derived from names (``link-base_link``).

    ``pictured`` names the links that have an entry in the page's links section: only
    they get a link href.
    """

    def __init__(self, pictured: Iterable[str] = ()) -> None:
        self._used: dict[str, int] = {}
        self._known: dict[tuple[str, str], str] = {}
        self.pictured = tuple(dict.fromkeys(pictured))
        self._pictured = frozenset(self.pictured)

    def __call__(self, prefix: str, name: str) -> str:
        key = (prefix, name)
        if key not in self._known:
            base = f"{prefix}-" + (re.sub(r"[^A-Za-z0-9_.-]+", "-", name).strip("-") or "x")
            count = self._used.get(base, 0)
            self._used[base] = count + 1
            self._known[key] = base if count == 0 else f"{base}-{count + 1}"
        return self._known[key]

    def link_href(self, name: str) -> str | None:
        return "#" + self("link", name) if name in self._pictured else None

    def link_ref(self, name: str) -> dict[str, str | None]:
        return {"name": name, "href": self.link_href(name)}


def mm(metres: float | None, digits: int = 1) -> str:
    """``12.3 mm`` or an en dash when unknown."""
    if metres is None or not math.isfinite(float(metres)):
        return "–"
    return f"{float(metres) * 1000:.{digits}f} mm"


def mm_value(value: float | None) -> str:
    """A value already in mm."""
    if value is None or not math.isfinite(float(value)):
        return "–"
    return f"{float(value):.1f} mm"


def percent(fraction: float | None) -> str:
    if fraction is None or not math.isfinite(float(fraction)):
        return "–"
    value = float(fraction) * 100
    return f"{value:.0f}%" if value >= 10 or value == 0 else f"{value:.1f}%"


def sig(value: float | None, digits: int = 3) -> str:
    """A number to ``digits`` significant digits, or an en dash."""
    if value is None:
        return "–"
    v = float(value)
    if not math.isfinite(v):
        return str(v)
    return f"{v:.{digits}g}"


def degrees(angle: float) -> str:
    return f"{math.degrees(float(angle)) % 360:.0f}°"


def plural(count: int, word: str) -> str:
    """``1 finding``, ``2 findings``."""
    return f"{count} {word}" if count == 1 else f"{count} {word}s"


def worst(severities: Iterable[str]) -> str | None:
    ranked = sorted(set(severities), key=lambda s: -Severity(s).rank)
    return ranked[0] if ranked else None


def subjects_of(d: Diagnostic) -> tuple[str, ...]:
    return tuple(x for x in (d.link, *(d.links or ())) if x)


def count_label(severity: Severity, count: int) -> str:
    """``1 error``, ``2 warnings``, ``3 info``: the word under a count."""
    word = severity.value
    return word if severity is Severity.INFO or count == 1 else word + "s"
