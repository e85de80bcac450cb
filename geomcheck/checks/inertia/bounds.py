"""GC505: moments of inertia beyond what the link's geometry allows, and the tensor its fix writes."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from geomcheck.checks.inertia.values import rounded, rounded_list, vector_text
from geomcheck.diagnostics import Diagnostic
from geomcheck.geometry.hull_cache import stored_solid_hull
from geomcheck.geometry.inertia import (
    AXIS_NAMES,
    GeometryBounds,
    MassProperties,
    exceedance,
)
from geomcheck.model import Link, SourceLocation
from geomcheck.rules.inertia import (
    EXCEEDS_GEOMETRY,
)
from geomcheck.thresholds import InertiaThresholds

ALIGNED_TOLERANCE = 1e-9  # a principal axis this close to a link axis is named after it


def direction_label(bounds: GeometryBounds, k: int) -> str:
    """``link y axis``, ``principal axis 2 (the link y axis)`` or ``principal axis 3 (-0.24, 0.97, -0.03)``."""
    label = bounds.labels[k]
    if not label.startswith("principal"):
        return label
    direction = bounds.directions[:, k]
    aligned = np.flatnonzero(np.abs(np.abs(direction) - 1.0) < ALIGNED_TOLERANCE)
    if len(aligned) == 1:
        return f"{label} (the link {AXIS_NAMES[aligned[0]]} axis)"
    return f"{label} {vector_text(direction)}"


def geometry_diagnostic(
    link: Link, props: MassProperties, bounds: GeometryBounds, th: InertiaThresholds, loc: SourceLocation | None
) -> Diagnostic | None:
    """GC505: the worst moment (or, failing none, the worst spread) beyond what the geometry allows."""
    limit = 1.0 + th.relative_tolerance
    axis_ratio = exceedance(bounds.moments, bounds.moment_bound)
    plane_ratio = exceedance(bounds.spread, bounds.spread_bound)
    if max(axis_ratio.max(), plane_ratio.max()) <= limit:
        return None
    m = props.mass
    data: dict[str, Any] = {
        "mass": rounded(m),
        "directions": list(bounds.labels),
        "moments": rounded_list(bounds.moments),
        "moment_bound": rounded_list(bounds.moment_bound),
        "radius_of_gyration": rounded_list(np.sqrt(np.clip(bounds.moments, 0.0, None) / m)),
        "reach": rounded_list(bounds.axis_reach),
        "spread": rounded_list(np.sqrt(np.clip(bounds.spread, 0.0, None) / m)),
        "extent": rounded_list(bounds.plane_reach),
    }
    if axis_ratio.max() > limit:
        kind, ratios = "moment", axis_ratio
        k = int(np.argmax(axis_ratio))
        gyration = math.sqrt(bounds.moments[k] / m)
        message = EXCEEDS_GEOMETRY.message(
            "moment",
            link=link.name,
            gyration=gyration,
            direction=direction_label(bounds, k),
            moment=bounds.moments[k],
            mass=m,
            reach=bounds.axis_reach[k],
            bound=bounds.moment_bound[k],
        )
    else:
        kind, ratios = "spread", plane_ratio
        k = int(np.argmax(plane_ratio))
        spread = math.sqrt(bounds.spread[k] / m)
        message = EXCEEDS_GEOMETRY.message(
            "spread",
            link=link.name,
            spread=spread,
            direction=direction_label(bounds, k),
            second_moment=bounds.spread[k],
            mass=m,
            extent=bounds.plane_reach[k],
            bound=bounds.spread_bound[k],
        )
    data["worst"] = {"direction": bounds.labels[k], "bound": kind, "ratio": rounded(float(ratios[k]))}
    return EXCEEDS_GEOMETRY.diagnose(message, link=link.name, about="inertia", location=loc, data=data)


def implied_inertia(link: Link, props: MassProperties, points: np.ndarray) -> dict[str, float | None] | None:
    """The tensor [kg m^2] of the solid convex hull of ``points`` (n, 3) [m, link frame] with
    the stated mass, about the stated centre of mass, in the ``<inertial>``'s own axes (its
    origin's rpy): what GC505's fix writes. ``None`` when the points span no volume."""
    if link.inertial is None:
        return None
    solid = stored_solid_hull(points)
    if solid is None:
        return None
    offset = props.com - solid.center_mass
    about_com = solid.moment_inertia * (props.mass / solid.mass) + props.mass * (
        float(offset @ offset) * np.eye(3) - np.outer(offset, offset)
    )
    rotation = link.inertial.origin.rotation()
    tensor = rotation.T @ about_com @ rotation
    # six significant digits of the largest moment: the hull's round-off off the diagonal becomes 0
    quantum = 10.0 ** (math.floor(math.log10(float(np.abs(tensor).max()))) - 5)
    tensor = np.round(tensor / quantum) * quantum + 0.0
    return {
        key: rounded(float(tensor[i, j]))
        for key, (i, j) in zip(
            ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)), strict=True
        )
    }


def part_centroid(points: np.ndarray) -> np.ndarray | None:
    """The centroid (3,) [m, link frame] of the solid convex hull of ``points`` (n, 3): where a
    uniform part's centre of mass lies; ``None`` when they span no volume."""
    solid = stored_solid_hull(points)
    return None if solid is None else np.asarray(solid.center_mass, dtype=float)
