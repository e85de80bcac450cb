"""GC302's measure: how much farther a collision element reaches than the part of the mesh it stands for.

Over-coverage is judged as under-coverage is (GC301), on the element's part of the link's visual
geometry (the points nearer to it than to the link's other elements):

- **a side standing off**: the element's face (or radius) lies beyond the part's extreme on that
  side by more than the part's tolerance, more than ``oversize_gap_fraction`` of the part's
  extent across it and more than ``oversize_floor_m`` (5 mm: padding a few millimetres proud of a
  thin part, Minitaur's motor cylinders 4 mm past a 13 mm decorative disc, is within the margin
  the sweeps call a near miss, not a false contact), while a primitive of the same kind fitted to
  the part is at least ``oversize_volume_ratio`` times smaller (a 140 mm box on a 109 mm forearm, a 25 mm sphere on an
  11 mm camera, a wheel's cylinder twice its tyre's width). A face of one element of a union that
  lies inside another element of the link is an inner face: the union's surface is elsewhere,
  so it is not judged;
- **the wrong kind of shape** (a link's only element): another kind fitted to the link's mesh
  encloses it in ``oversize_kind_ratio`` times less volume than the element and than the best
  element of its own kind fitted to the mesh (a sphere of a wheel's radius on a wheel, 2.3 times
  the volume of the cylinder that fits it). The part's shape is judged by the fitted element, not
  the element: round shapes enclose a blocky part in 1.5 to 2.7 times a box's volume whatever
  their size, so a capsule on a rod-like bone, 2.5 times its box while a fitted capsule would be
  1.5 times, is of the right kind and only larger than its fit, which the side standing off says.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geomcheck.geometry.elements import CollisionElement
from geomcheck.geometry.fit import ElementFit
from geomcheck.geometry.primitives import half_extents
from geomcheck.geometry.suggest import Suggestion
from geomcheck.model import Capsule
from geomcheck.thresholds import FitThresholds

INNER_FACE_DEPTH_M = 1e-4  # a face point this deep inside another element lies within the union [m]
RADIAL_PROBES = 8  # points around a cylinder's or sphere's equator probing whether its radius is an inner face


@dataclass(frozen=True)
class Oversize:
    """Why an element is larger than its part: the worst free ``side`` (a key of
    :attr:`ElementFit.gaps`) with its ``gap`` [m], the part's ``span`` across it [m] and the gap
    ``allowed`` [m]; ``volume_ratio``, the element's volume over a same-kind primitive fitted to
    the part; and, for the wrong kind, the ``better`` fitted primitive and ``kind_ratio``."""

    side: str | None
    gap: float
    span: float
    allowed: float
    volume_ratio: float | None
    better: Suggestion | None = None
    kind_ratio: float | None = None
    own_kind_ratio: float | None = None


def _face_probes(element: CollisionElement, side: str) -> np.ndarray:
    """Link-frame points on the middle of the element's face ``side`` (or around its equator for
    ``radial``), shape (k, 3)."""
    primitive = element.primitive
    assert primitive is not None
    h = half_extents(primitive)
    if side == "radial":
        angles = np.linspace(0.0, 2.0 * np.pi, RADIAL_PROBES, endpoint=False)
        r = primitive.radius  # type: ignore[union-attr]
        local = np.column_stack((r * np.cos(angles), r * np.sin(angles), np.zeros(RADIAL_PROBES)))
    else:
        axis = "xyz".index(side[0])
        local = np.zeros((1, 3))
        local[0, axis] = h[axis] if side[1] == "+" else -h[axis]
    return local @ np.asarray(element.rotation, dtype=float).T + np.asarray(element.translation, dtype=float)


def free_gaps(f: ElementFit, others: list[CollisionElement]) -> dict[str, float]:
    """The element's gaps on the sides that are the union's outer surface: a side whose middle
    lies inside another of the link's elements is an inner face of the union."""
    if f.gaps is None or f.element.primitive is None:
        return {}
    out = {}
    for side, gap in f.gaps.items():
        if isinstance(f.element.primitive, Capsule) and side != "radial":
            continue  # a capsule is measured by the cylinder enclosing it: its rounded ends are not flat faces
        probes = _face_probes(f.element, side)
        inner = any(bool((other.signed_distance(probes) < -INNER_FACE_DEPTH_M).all()) for other in others)
        if not inner:
            out[side] = gap
    return out


def _span(f: ElementFit, side: str) -> float:
    """The part's extent [m] across ``side``: along the face's axis, or its diameter for ``radial``."""
    assert f.extent is not None
    key = "radial" if side == "radial" else side[0]
    return float(f.extent[key][2])


def standing_off(f: ElementFit, others: list[CollisionElement], tolerance: float, th: FitThresholds) -> Oversize | None:
    """The element's worst free side when it stands off its part (see the module), else ``None``."""
    if f.extent is None or f.suggested is None or f.suggested.volume <= 0.0:
        return None
    ratio = f.element.volume / f.suggested.volume
    if ratio < th.oversize_volume_ratio:
        return None
    worst: Oversize | None = None
    for side, gap in free_gaps(f, others).items():
        span = _span(f, side)
        allowed = max(tolerance, th.oversize_gap_fraction * span, th.oversize_floor_m)
        if gap > allowed and (worst is None or gap - allowed > worst.gap - worst.allowed):
            worst = Oversize(side, gap, span, allowed, ratio)
    return worst


def wrong_kind(f: ElementFit, th: FitThresholds) -> Oversize | None:
    """For a link's only element: the primitive of another kind fitted to the whole visual
    (:attr:`ElementFit.better_kind`) when it encloses it in ``oversize_kind_ratio`` times less
    volume than the element and than an element of its kind fitted to it (:attr:`ElementFit.own_kind_volume`)."""
    best = f.better_kind
    if f.element.primitive is None or f.element.volume <= 0.0 or best is None:
        return None
    if f.element.volume < th.oversize_kind_ratio * best.volume:
        return None
    own = f.own_kind_volume
    if own is not None and own < th.oversize_kind_ratio * best.volume:
        return None  # the part is shaped for the element's kind: the element is only larger than its fit
    same = f.element.volume / f.suggested.volume if f.suggested is not None and f.suggested.volume > 0 else None
    own_ratio = None if own is None else own / best.volume
    return Oversize(None, 0.0, 0.0, 0.0, same, best, f.element.volume / best.volume, own_ratio)


__all__ = ["Oversize", "free_gaps", "standing_off", "wrong_kind"]
