"""Small helpers to write inline SVG as escaped markup, deterministically.

Numbers are written with at most one decimal (screen pixels), so the same data always
gives the same bytes; text and attribute values are escaped.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence

from markupsafe import Markup, escape

Attrs = Mapping[str, object]


def num(value: float, digits: int = 1) -> str:
    """``value`` with at most ``digits`` decimals, no trailing zeros, never ``-0``."""
    text = f"{value:.{digits}f}".rstrip("0").rstrip(".") if digits else f"{value:.0f}"
    return "0" if text in ("-0", "") else text


def attrs(values: Attrs) -> str:
    """`` key="value"`` pairs in the given order; ``None`` values are left out; floats as :func:`num`."""
    parts = []
    for key, value in values.items():
        if value is None:
            continue
        text = num(value) if isinstance(value, float) else str(value)
        parts.append(f' {key}="{escape(text)}"')
    return "".join(parts)


def tag(name: str, values: Attrs | None = None, children: Iterable[str] | str = "") -> Markup:
    """An element; ``children`` are markup (escape text with :func:`text`)."""
    body = children if isinstance(children, str) else "".join(children)
    if not body:
        return Markup(f"<{name}{attrs(values or {})}/>")
    return Markup(f"<{name}{attrs(values or {})}>{body}</{name}>")


def text(value: object) -> Markup:
    """Escaped text content."""
    return escape(str(value))


def title(value: object) -> Markup:
    """A ``<title>`` child: the tooltip of its parent element."""
    return tag("title", None, text(value))


def path_data(rings: Sequence[Sequence[tuple[float, float]]], closed: bool = True) -> str:
    """SVG path ``d`` for point rings (already in screen coordinates)."""
    out = []
    for ring in rings:
        if len(ring) < 2:
            continue
        head, *rest = ring
        out.append("M" + num(head[0]) + " " + num(head[1]))
        out.append("".join("L" + num(x) + " " + num(y) for x, y in rest))
        if closed:
            out.append("Z")
    return "".join(out)


def nice_step(span: float, target: float) -> float:
    """A 1-2-5 step close to ``span / target`` divisions (``span`` > 0)."""
    raw = span / max(target, 1.0)
    power = 10.0 ** math.floor(math.log10(raw))
    for factor in (1.0, 2.0, 5.0, 10.0):
        if raw <= factor * power:
            return factor * power
    return 10.0 * power


def nice_floor(value: float) -> float:
    """The largest 1-2-5 number not above ``value`` (``value`` > 0)."""
    power = 10.0 ** math.floor(math.log10(value))
    for factor in (5.0, 2.0, 1.0):
        if factor * power <= value * (1 + 1e-9):
            return factor * power
    return power


def length_label(metres: float) -> str:
    """A length for people: ``2 m``, ``50 cm``, ``5 mm``, ``0.5 mm``."""
    if metres >= 1.0:
        return f"{num(metres, 2)} m"
    if metres >= 0.01:
        return f"{num(metres * 100, 1)} cm"
    return f"{num(metres * 1000, 2)} mm"


def svg(width: float, height: float, children: Iterable[str], label: str, css_class: str) -> Markup:
    """A standalone inline ``<svg>`` of natural size ``width`` x ``height`` [px] that scales down with the page."""
    return tag(
        "svg",
        {
            "xmlns": "http://www.w3.org/2000/svg",
            "class": css_class,
            "viewBox": f"0 0 {num(width)} {num(height)}",
            "width": num(width),
            "height": num(height),
            "role": "img",
            "aria-label": label,
        },
        [title(label), *children],
    )
