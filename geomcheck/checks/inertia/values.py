"""How the family writes its numbers: reported values rounded to what they mean, the same JSON on
every CPU and BLAS build; and the links it reports on.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator

import numpy as np

from geomcheck.geometry.elements import at_nanometre
from geomcheck.model import Inertial, Joint, Link, Robot

REPORTED_DIGITS = 6  # significant digits of reported moments and axes: what they mean, not a BLAS kernel's last digits
DISTINCT_MOMENTS = 1e-6  # moments closer than this share of the largest have no axis of their own [ratio]
AXIS_DECIMALS = 6  # decimals of a principal axis's components (a unit vector): a microradian, not solver noise


def rounded(value: float | None) -> float | None:
    """``value`` to :data:`REPORTED_DIGITS` significant digits (the same JSON on every CPU and
    BLAS build), ``None`` for non-finite."""
    if value is None or not math.isfinite(value):
        return None
    return float(f"{value:.{REPORTED_DIGITS}g}") + 0.0  # + 0.0: no negative zero


def distinct_axes(moments: np.ndarray, axes: np.ndarray) -> list[list[float | None] | None]:
    """The principal axes of moments that differ from the other two (``None`` for an axis
    whose moment equals another's: any direction in their plane is principal, and which one a
    solver returns depends on the CPU). ``axes`` columns, signs already canonical."""
    scale = max(float(np.max(np.abs(moments))), 1e-300)
    out: list[list[float | None] | None] = []
    for k in range(3):
        others = [abs(float(moments[k] - moments[j])) for j in range(3) if j != k]
        axis = np.round(axes[:, k], AXIS_DECIMALS)  # 1e-16 where the axis is 0 is a solver's, not the body's
        out.append(rounded_list(axis) if min(others) > DISTINCT_MOMENTS * scale else None)
    return out


def rounded_list(values: Iterable[float]) -> list[float | None]:
    return [rounded(float(v)) for v in values]


def metres_list(values: Iterable[float]) -> list[float | None]:
    """Coordinates [m] to a nanometre, then to :data:`REPORTED_DIGITS` significant digits: a
    bounding box face at 0 stays 0, not -2.9e-15 on one CPU and -2.1e-15 on another."""
    return [rounded(at_nanometre(float(v))) for v in values]


def vector_text(v: Iterable[float]) -> str:
    return "(" + ", ".join(f"{float(x):.4g}" for x in v) + ")"


def percent(share: float) -> str:
    """``share`` as a percentage with two significant digits: ``0.33%``, ``0.00039%``."""
    return f"{share * 100:.2g}%"


def tensor_values(inertial: Inertial) -> tuple[float, ...]:
    return (inertial.ixx, inertial.ixy, inertial.ixz, inertial.iyy, inertial.iyz, inertial.izz)


def unique_links(robot: Robot) -> Iterator[Link]:
    """Links in document order, the first of duplicated names only (duplicates are a GC1xx finding)."""
    seen: set[str] = set()
    for link in robot.links:
        if link.name not in seen:
            seen.add(link.name)
            yield link


def moving_joint(robot: Robot, link: Link) -> Joint | None:
    """The non-fixed joint that moves ``link``, if any."""
    joint = robot.parent_joint.get(link.name)
    return joint if joint is not None and joint.is_moving else None
