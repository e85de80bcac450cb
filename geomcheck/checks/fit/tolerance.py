"""How far a link's mesh may stick out of its collision geometry: the tolerance at the part's size."""

from __future__ import annotations

import numpy as np

from geomcheck.geometry.elements import VisualCloud
from geomcheck.geometry.fit import ElementFit
from geomcheck.thresholds import FitThresholds


def part_tolerance(visual: VisualCloud, th: FitThresholds) -> float:
    """How far [m] this link's mesh may stick out of its collision geometry: the fixed
    ``protrusion_tolerance_m``, or ``protrusion_tolerance_fraction`` of the mesh's smallest
    extent (bounding box in the link frame) when smaller, never below ``protrusion_floor_m``:
    10 mm is nothing on a base but the whole thickness of a finger. On a large part,
    ``protrusion_size_fraction`` of its largest extent when that is more (at most
    ``protrusion_size_cap_m``): a primitive standing for a 0.5 m body is not expected to follow
    its detail closer than that."""
    spans = np.ptp(visual.bounds(), axis=0)
    relative = max(th.protrusion_tolerance_fraction * float(spans.min()), th.protrusion_floor_m)
    large = min(th.protrusion_size_fraction * float(spans.max()), th.protrusion_size_cap_m)
    return max(min(th.protrusion_tolerance_m, relative), large)


def element_tolerance(f: ElementFit, th: FitThresholds) -> float:
    """The tolerance [m] for one element: the link's, or ``protrusion_tolerance_fraction`` of
    the smallest extent of the part of the mesh the element answers for (along its own axes)
    when smaller, never below ``protrusion_floor_m``: a finger pad's box in a union of four is
    judged at the pad's size, not the finger's."""
    spans = [v[2] for v in (f.extent or {}).values() if v[2] > 0.0]
    if not spans:
        return th.protrusion_tolerance_m
    relative = max(th.protrusion_tolerance_fraction * min(spans), th.protrusion_floor_m)
    return min(th.protrusion_tolerance_m, relative)
