"""The three orthographic views of a link (a ``views`` section entry) as one inline SVG.

All three panels share one scale, so the views compare directly; a scale bar gives it.
The visual geometry is a filled silhouette, the collision geometry a solid outline over
it, the suggested primitive a dashed outline.
"""

from __future__ import annotations

from collections.abc import Sequence

from markupsafe import Markup

from geomcheck.report.section_views import LinkViews, View
from geomcheck.report.svg import length_label, nice_floor, num, path_data, svg, tag, text

VIEW_TITLES = {"front": "front, from +x", "side": "side, from −y", "top": "top, from +z"}
FIGURE_PX = 170.0  # the largest extent of any view of a link is drawn this long [px]
MIN_PANEL_PX = 96.0  # narrowest panel content [px]
PAD = 16.0  # space around a panel's drawing [px]
LABEL_PX = 20.0  # panel title band [px]
FOOT_PX = 30.0  # scale bar band [px]
GAP = 10.0  # between panels [px]


def _extent(bounds: Sequence[float] | None) -> tuple[float, float]:
    if not bounds:
        return 0.0, 0.0
    return float(bounds[2]) - float(bounds[0]), float(bounds[3]) - float(bounds[1])


def _axis_glyph(x: float, y: float, axes: Sequence[str]) -> Markup:
    """Two small arrows at (x, y) [px] naming the view's right and up axes."""
    arm = 14.0
    return tag(
        "g",
        {"class": "axes"},
        [
            tag("path", {"d": f"M{num(x)} {num(y)}h{num(arm)}M{num(x)} {num(y)}v{num(-arm)}"}),
            tag("path", {"class": "tip", "d": f"M{num(x + arm + 3)} {num(y)}l-4 -2.5v5Z"}),
            tag("path", {"class": "tip", "d": f"M{num(x)} {num(y - arm - 3)}l-2.5 4h5Z"}),
            tag("text", {"x": num(x + arm + 5), "y": num(y + 3.5)}, text(axes[0])),
            tag("text", {"x": num(x - 3), "y": num(y - arm - 6)}, text(axes[1])),
        ],
    )


def _panel(view: str, data: View, scale: float, left: float, top: float, width: float, height: float):
    """One view's drawing in the box (left, top, width, height) [px]; returns its markup."""
    children = [
        tag("rect", {"class": "panel", "x": num(left), "y": num(top), "width": num(width), "height": num(height)}),
        tag("text", {"class": "label", "x": num(left + 6), "y": num(top + 14)}, text(VIEW_TITLES[view])),
    ]
    bounds = data.bounds
    if bounds is None:
        children.append(
            tag("text", {"class": "none", "x": num(left + width / 2), "y": num(top + height / 2)}, "no geometry")
        )
        return children
    umin, vmin, umax, vmax = bounds
    cx = left + width / 2 - (umax - umin) * scale / 2
    cy = top + LABEL_PX + (height - LABEL_PX) / 2 + (vmax - vmin) * scale / 2

    def to_screen(rings: Sequence[Sequence[Sequence[float]]]) -> list[list[tuple[float, float]]]:
        return [[(cx + (p[0] - umin) * scale, cy - (p[1] - vmin) * scale) for p in ring] for ring in rings]

    for rings, css in ((data.mesh, "mesh"), (data.collision, "collision"), (data.suggested, "suggested")):
        if rings:
            children.append(tag("path", {"class": css, "d": path_data(to_screen(rings))}))
    ox, oy = cx - umin * scale, cy + vmin * scale
    if left + 4 <= ox <= left + width - 4 and top + LABEL_PX <= oy <= top + height - 4:
        children.append(
            tag("path", {"class": "origin", "d": f"M{num(ox - 5)} {num(oy)}h10M{num(ox)} {num(oy - 5)}v10"})
        )
    children.append(_axis_glyph(left + 8, top + height - 8, data.axes))
    return children


def link_figure(entry: LinkViews) -> Markup:
    """The front, side and top views of one ``views`` entry, to one scale, with a scale bar."""
    views = [(name, view or View()) for name, view in entry.views()]
    extents = [_extent(view.bounds) for _, view in views]
    largest = max((max(e) for e in extents), default=0.0) or (entry.scale_m or 0.0) or 1.0
    scale = FIGURE_PX / largest
    widths = [max(w * scale, MIN_PANEL_PX) + 2 * PAD for w, _ in extents]
    height = max(max(h for _, h in extents) * scale, 40.0) + 2 * PAD + LABEL_PX
    children: list[str] = []
    left = 0.5
    for (name, view), width in zip(views, widths, strict=True):
        children += _panel(name, view, scale, left, 0.5, width, height)
        left += width + GAP
    total_width = left - GAP + 0.5
    bar = nice_floor(0.4 * largest)
    bar_px = bar * scale
    y = height + FOOT_PX / 2 + 2
    children.append(
        tag(
            "g",
            {"class": "scalebar"},
            [
                tag("path", {"d": f"M1 {num(y - 4)}v8M1 {num(y)}h{num(bar_px)}M{num(1 + bar_px)} {num(y - 4)}v8"}),
                tag("text", {"x": num(bar_px + 8), "y": num(y + 4)}, text(length_label(bar))),
            ],
        )
    )
    return svg(total_width, height + FOOT_PX, children, f"front, side and top views of {entry.link}", "views")
