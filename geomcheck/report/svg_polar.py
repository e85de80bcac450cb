"""Polar chart of one swept pair: clearance [m] against the joint angle [rad].

The angle runs counter-clockwise from the right (0°), as a positive joint rotation about
the joint axis looks from the axis tip; the clearance grows outwards from zero at the
centre. Angle ranges in contact are shaded red with a red arc on the rim.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from markupsafe import Markup

from geomcheck.report.section_sweeps import SweepPair
from geomcheck.report.svg import nice_step, num, svg, tag, text, title

SIZE = 232.0  # chart width and height [px]
RADIUS = 84.0  # radius of the largest clearance ring [px]
CENTRE = (SIZE / 2, SIZE / 2)


def _point(angle: float, radius: float) -> tuple[float, float]:
    return CENTRE[0] + radius * math.cos(angle), CENTRE[1] - radius * math.sin(angle)


def _arc(a0: float, a1: float, radius: float) -> str:
    """Path from angle ``a0`` to ``a1`` (a1 > a0) [rad] on a circle, counter-clockwise."""
    x0, y0 = _point(a0, radius)
    x1, y1 = _point(a1, radius)
    large = 1 if a1 - a0 > math.pi else 0
    return f"M{num(x0)} {num(y0)}A{num(radius)} {num(radius)} 0 {large} 0 {num(x1)} {num(y1)}"


def _ranges(ranges: Sequence[Sequence[float]]) -> list[tuple[float, float]]:
    """Colliding ranges [rad] as increasing pairs (a range that wraps past 2π gets a1 > 2π)."""
    out = []
    for a0, a1 in ((float(r[0]), float(r[1])) for r in ranges if len(r) == 2):
        if a1 < a0:
            a1 += 2 * math.pi
        out.append((a0, max(a1, a0 + math.radians(0.5))))  # a contact at one angle stays visible
    return out


def is_full_turn(a0: float, a1: float) -> bool:
    """Whether the increasing range ``a0``..``a1`` [rad] covers the whole turn."""
    return a1 - a0 >= 2 * math.pi - 1e-3


def _contact(a0: float, a1: float, css: str) -> list[str]:
    """Shading and rim arc of one contact range."""
    cx, cy = num(CENTRE[0]), num(CENTRE[1])
    if is_full_turn(a0, a1):
        return [
            tag("circle", {"class": css, "cx": cx, "cy": cy, "r": num(RADIUS)}),
            tag("circle", {"class": css + "-arc", "cx": cx, "cy": cy, "r": num(RADIUS + 4)}),
        ]
    return [
        tag("path", {"class": css, "d": _arc(a0, a1, RADIUS) + f"L{cx} {cy}Z"}),
        tag("path", {"class": css + "-arc", "d": _arc(a0, a1, RADIUS + 4)}),
    ]


def _ring_step(largest: float) -> tuple[float, float]:
    """(ring spacing, outer ring) [m] for clearances up to ``largest``."""
    largest = max(largest, 0.001)
    step = nice_step(largest, 3)
    return step, math.ceil(largest / step - 1e-9) * step


def _mm(metres: float) -> str:
    return f"{num(metres * 1000, 1)} mm"


def sweep_chart(pair: SweepPair, joint: str) -> Markup:
    """The chart of one ``sweeps`` pair entry of ``joint``. Contact between adjacent links
    (``"adjacent": true``, parent and child, never checked at run time) is shaded grey."""
    angles = [float(a) for a in pair.angles]
    clearance = [float(c) for c in pair.clearance]
    n = min(len(angles), len(clearance))
    step, outer = _ring_step(max(clearance[:n], default=0.0))
    children: list[str] = []
    grid = [tag("circle", {"cx": num(CENTRE[0]), "cy": num(CENTRE[1]), "r": num(RADIUS)})]
    ring = step
    while ring < outer - 1e-12:
        grid.append(tag("circle", {"cx": num(CENTRE[0]), "cy": num(CENTRE[1]), "r": num(RADIUS * ring / outer)}))
        ring += step
    for k in range(8):
        x, y = _point(k * math.pi / 4, RADIUS)
        grid.append(tag("path", {"d": f"M{num(CENTRE[0])} {num(CENTRE[1])}L{num(x)} {num(y)}"}))
    children.append(tag("g", {"class": "grid"}, grid))
    labels = []
    for degrees, anchor, dx, dy in (
        (0, "start", 6, 4),
        (90, "middle", 0, -6),
        (180, "end", -6, 4),
        (270, "middle", 0, 14),
    ):
        x, y = _point(math.radians(degrees), RADIUS)
        labels.append(tag("text", {"x": num(x + dx), "y": num(y + dy), "text-anchor": anchor}, f"{degrees}°"))
    ring = step
    while ring <= outer + 1e-12:
        x, y = _point(math.radians(62), RADIUS * ring / outer)
        labels.append(tag("text", {"class": "ring", "x": num(x + 2), "y": num(y - 2)}, text(_mm(ring))))
        ring += step
    children.append(tag("g", {"class": "labels"}, labels))
    css = "expected" if pair.adjacent else "contact"
    for a0, a1 in _ranges(pair.colliding_ranges):
        children += _contact(a0, a1, css)
    if n >= 2:
        pts = [_point(angles[i], RADIUS * max(clearance[i], 0.0) / outer) for i in range(n)]
        wrap_gap = angles[0] + 2 * math.pi - angles[n - 1]
        closed = 0 <= wrap_gap <= 1.5 * (angles[n - 1] - angles[0]) / (n - 1)
        d = "M" + "L".join(f"{num(x)} {num(y)}" for x, y in pts) + ("Z" if closed else "")
        children.append(tag("path", {"class": "curve" + (" closed" if closed else ""), "d": d}))
    minimum, at = pair.min_clearance, pair.min_angle
    if minimum is not None and at is not None:
        x, y = _point(float(at), RADIUS * max(float(minimum), 0.0) / outer)
        css = "min" if float(minimum) > 0 else ("min touch" if pair.adjacent else "min hit")
        label = f"closest {_mm(float(minimum))} at {num(math.degrees(float(at)) % 360, 0)}°"
        children.append(tag("circle", {"class": css, "cx": num(x), "cy": num(y), "r": "3.5"}, [title(label)]))
    return svg(SIZE, SIZE, children, f"clearance of {pair.name} against the angle of {joint}", "polar")
