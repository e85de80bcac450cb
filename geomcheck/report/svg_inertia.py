"""A small bar per principal axis: the moment [kg m^2] against the largest moment the link's
geometry allows about that axis (mass x reach^2). A bar past the bound line needs mass
outside the link's geometry: impossible for a rigid body."""

from __future__ import annotations

import math

from markupsafe import Markup

from geomcheck.report.svg import num, svg, tag, text

BOUND_PX = 80.0  # the bound's position [px]
MAX_PX = 120.0  # longest bar drawn [px]
HEIGHT_PX = 12.0


def moment_ratio(moment: float, bound: float) -> float:
    """``moment / bound``; infinite for a positive moment with a zero bound."""
    if bound > 0:
        return moment / bound
    return 0.0 if moment <= 0 else math.inf


def moment_bar(moment: float, bound: float, label: str) -> Markup:
    """The bar of one principal axis; ``label`` names it for the tooltip."""
    ratio = moment_ratio(float(moment), float(bound))
    over = ratio > 1.0
    width = min(max(ratio, 0.0), MAX_PX / BOUND_PX) * BOUND_PX
    children = [
        tag("rect", {"class": "track", "x": "0", "y": "2", "width": num(BOUND_PX), "height": "8"}),
        tag("rect", {"class": "bar over" if over else "bar", "x": "0", "y": "2", "width": num(width), "height": "8"}),
        tag("path", {"class": "bound", "d": f"M{num(BOUND_PX)} 0v{num(HEIGHT_PX)}"}),
    ]
    if over:
        factor = "∞" if math.isinf(ratio) else (f"{ratio:.0f}" if ratio >= 10 else f"{ratio:.1f}")
        children.append(tag("text", {"x": num(width + 4), "y": "10"}, text(f"×{factor}")))
    return svg(MAX_PX + 40, HEIGHT_PX, children, label, "bars")
