"""The collision matrix (``matrix`` section) as a links-by-links grid, one cell per pair.

Only the lower triangle is drawn (a pair appears once). Cells are coloured by class; the
pair's figures are in the cell's ``<title>`` (shown on hover).
"""

from __future__ import annotations

from collections.abc import Mapping

from markupsafe import Markup

from geomcheck.report.html_common import mm
from geomcheck.report.section_matrix import MatrixPair, MatrixSection
from geomcheck.report.svg import num, svg, tag, text, title

# display class -> legend text, in legend order
CLASSES: Mapping[str, str] = {
    "adjacent": "adjacent (parent and child)",
    "default": "in collision at the default pose",
    "always": "always in collision",
    "never": "never in collision in the samples",
    "certified": "never in collision, certified by bounds",
    "enabled": "can collide: checked at run time",
    "witness": "looked never, but a colliding configuration was found",
}
LABEL_CHAR_PX = 6.2  # estimated width of a label character at the matrix font size [px]
MAX_LABEL_CHARS = 40  # longer link names are shortened in the middle


def display_class(pair: MatrixPair) -> str:
    """The colour class of a pair: its class, refined by ``certified`` and by a witness that
    the search found (``source`` ``"search"``) for a pair no sample had seen in collision."""
    if pair.witness and pair.witness.source in (None, "search"):
        return "witness"
    if pair.cls == "never" and pair.certified:
        return "certified"
    return pair.cls if pair.cls in CLASSES else "enabled"


def pair_summary(pair: MatrixPair, samples: int | None) -> str:
    """One line with the pair's figures, for the tooltip."""
    parts = [f"{pair.name}: {CLASSES[display_class(pair)]}"]
    tested = samples if pair.tested is None else pair.tested
    if pair.fraction is not None and tested:
        parts.append(f"in collision in {float(pair.fraction) * 100:.1f}% of {tested} samples")
    distance = pair.min_distance
    if distance is not None:
        closest = f"closest {mm(distance)}" if float(distance) >= 0 else f"penetrating {mm(-float(distance))}"
        parts.append(closest)
    if pair.certified and pair.clearance_bound is not None:
        parts.append(f"bounds prove a clearance of at least {mm(pair.clearance_bound)}")
    witness = pair.witness
    if witness:
        config = witness.configuration
        joints = ", ".join(f"{k}={float(v):.3f}" for k, v in sorted(config.items())) or "the default pose"
        parts.append(f"witness: depth {mm(witness.depth if witness.depth is not None else 0.0)} at {joints}")
    return "; ".join(parts)


def class_counts(section: MatrixSection) -> dict[str, int]:
    """Number of pairs per display class, every class present, in legend order."""
    counts = dict.fromkeys(CLASSES, 0)
    for pair in section.pairs:
        counts[display_class(pair)] += 1
    return counts


def _label(name: str) -> str:
    """``name``, shortened in the middle to :data:`MAX_LABEL_CHARS` (the tooltip keeps it whole)."""
    if len(name) <= MAX_LABEL_CHARS:
        return name
    keep = MAX_LABEL_CHARS - 1
    return name[: keep - keep // 2] + "…" + name[len(name) - keep // 2 :]


def matrix_grid(section: MatrixSection, link_href: Mapping[str, str]) -> Markup:
    """The grid of ``section``; row labels link to the links' pictures (``link_href``).

    Cells carry ``data-row``/``data-col`` and labels ``data-i`` so a script can highlight
    the row and column of the cell under the pointer.
    """
    links = section.links
    n = len(links)
    if n < 2:
        return Markup("")
    index = {name: i for i, name in enumerate(links)}
    samples = section.samples
    cell = max(7.0, min(16.0, 720.0 / n))
    margin = max(len(_label(x)) for x in links) * LABEL_CHAR_PX + 10
    top, left = margin, margin
    labels = []
    for i, name in enumerate(links[1:], start=1):
        y = top + (i - 1) * cell + cell / 2 + 3.5
        attrs = {"class": "row", "data-i": str(i), "x": num(left - 6), "y": num(y), "text-anchor": "end"}
        label = tag("text", attrs, [title(name), text(_label(name))])
        href = link_href.get(name)
        labels.append(tag("a", {"href": href}, label) if href else label)
    for j, name in enumerate(links[:-1]):
        x, y = left + j * cell + cell / 2 + 3.5, top - 6
        attrs = {
            "class": "col",
            "data-i": str(j),
            "x": num(x),
            "y": num(y),
            "transform": f"rotate(-90 {num(x)} {num(y)})",
        }
        labels.append(tag("text", attrs, [title(name), text(_label(name))]))
    placed = []
    for pair in section.pairs:
        a, b = (*pair.links, "", "")[:2]  # a pair without its links is not placed
        if a in index and b in index and a != b:
            placed.append((max(index[a], index[b]), min(index[a], index[b]), pair))
    cells = [
        tag(
            "rect",
            {
                "class": f"m-{display_class(pair)}",
                "data-row": str(row),
                "data-col": str(col),
                "x": num(left + col * cell),
                "y": num(top + (row - 1) * cell),
                "width": num(cell),
                "height": num(cell),
            },
            [title(pair_summary(pair, samples))],
        )
        for row, col, pair in sorted(placed, key=lambda p: (p[0], p[1]))
    ]
    children = [tag("g", {"class": "labels"}, labels), tag("g", {"class": "cells"}, cells)]
    size = left + (n - 1) * cell + 2
    return svg(size, top + (n - 1) * cell + 2, children, f"collision matrix of {n} links", "matrix")
