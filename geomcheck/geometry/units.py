"""Which unit mistake, if any, explains a mesh's size against reference sizes.

Sizes are largest extents [m]. A ratio ``size / reference`` near a unit factor ``f`` (or
``1 / f``) suggests the mesh was exported in another unit; the fix is ``scale *= 1 / f``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

# factor: (mesh size / true size, how the mistake reads)
UNIT_FACTORS: tuple[tuple[float, str], ...] = (
    (1000.0, "millimetres read as metres"),
    (100.0, "centimetres read as metres"),
    (1.0 / 0.0254, "inches read as metres"),
    (25.4, "millimetres read as inches"),
)
ROBOT_ONLY_FACTORS = (1000.0,)  # without a same-link reference only this factor is distinctive
PLAUSIBLE_SIZE_M = 0.3  # a typical link when nothing else is known [m]
ROBOT_AGREEMENT = 4.0  # the robot's typical link must be off by at least factor / this [ratio]
SPAN_OUTGROWN = 2.0  # a mesh too large by a unit factor spans this times its primitives and joints [ratio]
# a mesh too small by a unit factor, scaled up, would lie over this times the robot's extent away [ratio]
OFF_THE_ROBOT = 2.0


@dataclass(frozen=True)
class UnitVerdict:
    """``factor``: how many times too large the mesh is (< 1: too small); ``explanation`` of
    the mistake; ``reference`` (``"link"`` or ``"robot"``) it was judged against; the ratios."""

    factor: float
    explanation: str
    reference: str
    link_ratio: float | None
    robot_ratio: float | None

    @property
    def scale_factor(self) -> float:
        """What the current ``scale`` must be multiplied by."""
        return 1.0 / self.factor


def _candidates(factors: Sequence[float]) -> list[tuple[float, str]]:
    out = []
    for factor, text in UNIT_FACTORS:
        if factor in factors or not factors:
            out.append((factor, text))
            inverse = text.split(" read as ")
            out.append((1.0 / factor, f"{inverse[1]} scaled as {inverse[0]}"))
    return out


def match_factor(ratio: float, tolerance: float, factors: Sequence[float] = ()) -> tuple[float, str] | None:
    """The unit factor (or inverse) within ``tolerance`` (``|ln(ratio / f)| <= ln(1 + tolerance)``)
    of ``ratio``, the closest one; ``None`` when none is."""
    if not ratio > 0.0 or not math.isfinite(ratio):
        return None
    best: tuple[float, float, str] | None = None
    for factor, text in _candidates(factors):
        miss = abs(math.log(ratio / factor))
        if miss <= math.log1p(tolerance) and (best is None or miss < best[0]):
            best = (miss, factor, text)
    return None if best is None else (best[1], best[2])


def _agrees(robot_ratio: float | None, factor: float) -> bool:
    """The robot reference points the same way and comes within ``ROBOT_AGREEMENT`` of
    ``factor``: links of one robot differ in size by tens, so the link's own geometry alone
    does not convict a mesh."""
    if robot_ratio is None:
        return True
    along = math.log(robot_ratio) * math.copysign(1.0, math.log(factor))
    return along >= abs(math.log(factor)) - math.log(ROBOT_AGREEMENT)


def _beyond_span(size: float, link_span: float | None, factor: float) -> bool:
    """A mesh ``factor`` (> 1) times too large outgrows its whole link: ``size`` is at least
    ``SPAN_OUTGROWN`` times the link's span (its primitives and joint origins together, typed
    in metres). The median element a link reference is made of can be a screw beside a housing;
    the span is not: a 0.18 m gripper housing among 7 mm screw heads, a rail and mirrors that
    span 0.18 m is no mesh 25.4x too large. Always true for a factor below 1 or without a span."""
    if factor <= 1.0 or not link_span:
        return True
    return size >= SPAN_OUTGROWN * link_span


def _stays_on_robot(offset: float, factor: float, robot_extent: float | None) -> bool:
    """A mesh ``factor`` (< 1) times too small, scaled up about its file's origin, stays on the
    robot: the centre of its bounding box, ``offset`` [m] from that origin, lands within
    ``OFF_THE_ROBOT`` times ``robot_extent`` [m]. A file in the wrong unit is wrong in its
    placement by the same factor; a small part drawn far from its file's origin (a sesamoid
    bone 2.6 mm across, 169 mm from the origin of a skeleton's shared frame) would be thrown
    4.3 m away by the scale: it is small, not in another unit. Always true for a factor above
    1 or without an extent."""
    if factor >= 1.0 or not robot_extent:
        return True
    return offset / factor <= OFF_THE_ROBOT * robot_extent


def infer_unit_factor(
    size: float,
    link_reference: float | None,
    robot_reference: float | None,
    tolerance: float,
    link_reference_trusted: bool = True,
    link_span: float | None = None,
    offset: float = 0.0,
    robot_extent: float | None = None,
) -> UnitVerdict | None:
    """A unit mistake explaining ``size`` [m], or ``None``.

    With a ``link_reference`` (the link's other geometry) any factor is considered and the
    ``robot_reference`` (typical size of the other links) must agree; a link reference made
    of other meshes only (``link_reference_trusted`` false) needs the robot reference. A mesh
    too large must also outgrow ``link_span`` [m], the extent of the link's primitives and
    joint origins together (:func:`_beyond_span`); a mesh too small, scaled up about its file's
    origin (its bounding box's centre ``offset`` [m] from it), must stay within the robot's
    ``robot_extent`` [m] (:func:`_stays_on_robot`). Without a link reference only the factor
    1000 is distinctive enough against the robot alone.
    """
    if not size > 0.0:
        return None
    robot_ratio = size / robot_reference if robot_reference else None
    if link_reference:
        link_ratio = size / link_reference
        found = match_factor(link_ratio, tolerance)
        if (
            found
            and _agrees(robot_ratio, found[0])
            and (link_reference_trusted or robot_ratio is not None)
            and _beyond_span(size, link_span, found[0])
            and _stays_on_robot(offset, found[0], robot_extent)
        ):
            return UnitVerdict(found[0], found[1], "link", link_ratio, robot_ratio)
        return None
    if robot_ratio is None:
        return None
    found = match_factor(robot_ratio, tolerance, ROBOT_ONLY_FACTORS)
    if (
        found is None
        or not _beyond_span(size, link_span, found[0])
        or not _stays_on_robot(offset, found[0], robot_extent)
    ):
        return None
    return UnitVerdict(found[0], found[1], "robot", None, robot_ratio)


def plausible_factor(size: float, robot_reference: float | None) -> tuple[float, str] | None:
    """For an absurd ``size`` [m]: the unit factor that brings it closest (in log) to the
    robot's typical link size (or to a typical link when unknown)."""
    if not size > 0.0 or not math.isfinite(size):
        return None
    target = robot_reference or PLAUSIBLE_SIZE_M
    return min(_candidates(()), key=lambda c: abs(math.log(size / c[0] / target)))


def median(values: Sequence[float]) -> float | None:
    """Median of the positive finite ``values``, ``None`` when there are none."""
    good = sorted(v for v in values if v > 0.0 and math.isfinite(v))
    if not good:
        return None
    mid = len(good) // 2
    return good[mid] if len(good) % 2 else 0.5 * (good[mid - 1] + good[mid])
