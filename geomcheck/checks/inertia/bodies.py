"""The rigid bodies consumers simulate: links merged across fixed joints.

Pinocchio's URDF parser appends a link on a fixed joint to its parent's body, sdformat's URDF
conversion (Gazebo) lumps it into its parent (``ReduceFixedJoints``, creating the parent's
``<inertial>`` when it has none) and MuJoCo's URDF import fuses static bodies. A moving link
is therefore simulated with the mass of every link fixed below it, and a fixed link's mass
properties only through the body it is merged into. GC501/GC502 ask whether such a body has
mass; GC503-GC508 are lowered when the merged body passes the check its member fails.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from geomcheck.geometry.hull_cache import stored_distance_outside
from geomcheck.geometry.inertia import (
    Hull,
    MassProperties,
    combined,
    exceedance,
    geometry_bounds,
    mass_properties,
)
from geomcheck.model import Link, Robot
from geomcheck.thresholds import InertiaThresholds


def usable_mass(link: Link | None) -> float:
    """The link's written mass when finite and positive, else 0 [kg]."""
    m = link.inertial.mass if link is not None and link.inertial is not None else 0.0
    return m if math.isfinite(m) and m > 0.0 else 0.0


@dataclass(frozen=True)
class Body:
    """Link ``top`` and the links fixed below it: ``members`` maps each (``top`` first) to its
    transform top-from-member, shape (4, 4); ``mass`` is the sum of their usable masses [kg]."""

    top: str
    members: dict[str, np.ndarray] = field(hash=False)
    mass: float

    @property
    def merged(self) -> bool:
        """Whether consumers merge more than one link into this body."""
        return len(self.members) > 1

    def others(self, link: str) -> list[str]:
        """The body's other links, sorted: the same whatever the order of the ``<link>`` elements."""
        return sorted(m for m in self.members if m != link)

    def others_text(self, link: str, shown: int = 3) -> str:
        """The body's other links for a message: the first ``shown`` sorted, then how many more."""
        others = self.others(link)
        head = ", ".join(others[:shown])
        return head if len(others) <= shown else f"{head} and {len(others) - shown} more"


def rigid_bodies(robot: Robot) -> dict[str, Body]:
    """Each declared link's body, by link name (the first of duplicated names)."""
    tops: dict[str, tuple[str, np.ndarray]] = {}

    def top_of(name: str) -> tuple[str, np.ndarray]:
        if name in tops:
            return tops[name]
        chain, seen, current = [], {name}, name
        while True:
            parent = robot.parent_joint.get(current)
            if parent is None or parent.type != "fixed" or parent.parent in seen or parent.parent not in robot.link_map:
                break
            chain.append(parent)
            current = parent.parent
            seen.add(current)
        transform = np.eye(4)
        for joint in reversed(chain):
            transform = transform @ joint.origin.matrix()
        tops[name] = (current, transform)
        return tops[name]

    names = list(dict.fromkeys(link.name for link in robot.links))
    groups: dict[str, dict[str, np.ndarray]] = {}
    for name in names:
        top, transform = top_of(name)
        groups.setdefault(top, {top: np.eye(4)})[name] = transform
    bodies = {
        top: Body(top, members, sum(usable_mass(robot.link_map.get(m)) for m in members))
        for top, members in groups.items()
    }
    return {name: bodies[top_of(name)[0]] for name in names}


class MergedBody:
    """Mass properties and geometry of a :class:`Body` as consumers merge it, computed on demand.

    ``points`` are the members' geometry points in the top link's frame, shape (n, 3) [m]
    (those of the members whose geometry can be read), or ``None`` when there are none."""

    def __init__(
        self,
        body: Body,
        robot: Robot,
        points_of: Callable[[str], np.ndarray | str],
        hull_of: Callable[[np.ndarray], Hull],
    ) -> None:
        self.body = body
        self._robot = robot
        self._points_of = points_of
        self._hull_of = hull_of

    @cached_property
    def props(self) -> MassProperties | None:
        parts = []
        for name, transform in self.body.members.items():
            link = self._robot.link_map.get(name)
            if link is None or link.inertial is None or usable_mass(link) == 0.0:
                continue
            own = mass_properties(link.inertial)
            if not (np.isfinite(own.tensor).all() and np.isfinite(own.com).all()):
                return None
            rotation = transform[:3, :3]
            parts.append((own.mass, rotation @ own.com + transform[:3, 3], rotation @ own.tensor @ rotation.T))
        return combined(parts) if parts else None

    @cached_property
    def points(self) -> np.ndarray | None:
        chunks = []
        for name, transform in self.body.members.items():
            link = self._robot.link_map.get(name)
            if link is None or not link.has_geometry:
                continue  # a frame without shapes adds nothing to the body's extent
            found = self._points_of(name)
            if isinstance(found, str):
                # an unreadable mesh leaves the body smaller than it is: every test of the merged
                # body (reach, hull, volume) only gets stricter, so a pass still holds
                continue
            chunks.append(found @ transform[:3, :3].T + transform[:3, 3])
        return np.concatenate(chunks) if chunks else None

    @cached_property
    def hull(self) -> Hull | None:
        return None if self.points is None else self._hull_of(self.points)

    def tensor_valid(self, th: InertiaThresholds) -> bool:
        """The merged tensor is positive definite and meets the triangle inequality (GC503, GC504)."""
        p = self.props
        return p is not None and p.positive_definite and p.triangle_excess <= th.relative_tolerance * p.scale

    def within_geometry(self, th: InertiaThresholds) -> bool:
        """The merged tensor is valid and possible for the merged geometry (GC505)."""
        p, points = self.props, self.points
        if p is None or points is None or not self.tensor_valid(th):
            return False
        bounds = geometry_bounds(p, points)
        limit = 1.0 + th.relative_tolerance
        worst = max(
            exceedance(bounds.moments, bounds.moment_bound).max(), exceedance(bounds.spread, bounds.spread_bound).max()
        )
        return bool(worst <= limit)

    def com_inside(self, th: InertiaThresholds) -> bool:
        """The merged centre of mass lies within the merged geometry's hull (GC506)."""
        p, hull = self.props, self.hull
        return p is not None and hull is not None and stored_distance_outside(hull, p.com) <= th.com_margin_m

    def density_plausible(self, th: InertiaThresholds) -> bool:
        """The merged mass fits in the merged hull at most at osmium's density (GC508)."""
        hull = self.hull
        return hull is not None and hull.volume > 0.0 and self.body.mass / hull.volume <= th.max_density_kg_m3
