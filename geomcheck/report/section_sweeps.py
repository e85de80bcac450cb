"""The ``sweeps`` report section as typed data: per swept joint, the clearance of each link
pair over the joint's turn.

Written by the self-collision family (geomcheck/checks/selfcollision.py: ``sweep_section``,
``pair_section``) as JSON-ready dicts, documented in docs/report-schema.md; readers parse it
here and use named fields. ``from_dict`` tolerates the keys an older or hand-written report
leaves out; ``to_dict`` writes the keys, in the order, the family writes them, so a parsed
entry serialises back to the same JSON. Numbers keep their JSON type (no conversion), which
is what keeps that exact.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class SweepPair:
    """One link pair of a sweep. Lengths [m], angles [rad] of the swept joint.

    ``min_clearance`` at ``min_angle`` is the closest approach (negative: penetration),
    ``colliding_ranges`` the (start, end) angle ranges in contact, ``max_depth`` the deepest
    penetration; ``angles``/``clearance`` the charted curve; ``adjacent`` a parent/child pair
    (never checked at run time); ``proven`` whether ``clearance_bound`` certifies the gaps
    between grid points, after ``queries`` distance queries.
    """

    links: tuple[str, ...]
    min_clearance: float | None = None
    min_angle: float | None = None
    colliding_ranges: tuple[tuple[float, float], ...] = ()
    max_depth: float | None = None
    angles: tuple[float, ...] = ()
    clearance: tuple[float, ...] = ()
    moving_link: str | None = None
    adjacent: bool = False
    clearance_bound: float | None = None
    proven: bool | None = None
    queries: int | None = None

    @property
    def name(self) -> str:
        """``a / b``."""
        return " / ".join(self.links)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> SweepPair:
        return cls(
            links=tuple(str(x) for x in data.get("links") or ()),
            min_clearance=data.get("min_clearance"),
            min_angle=data.get("min_angle"),
            colliding_ranges=tuple((r[0], r[1]) for r in data.get("colliding_ranges") or () if len(r) == 2),
            max_depth=data.get("max_depth"),
            angles=tuple(data.get("angles") or ()),
            clearance=tuple(data.get("clearance") or ()),
            moving_link=data.get("moving_link"),
            adjacent=bool(data.get("adjacent")),
            clearance_bound=data.get("clearance_bound"),
            proven=data.get("proven"),
            queries=data.get("queries"),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "links": list(self.links),
            "min_clearance": self.min_clearance,
            "min_angle": self.min_angle,
            "colliding_ranges": [list(r) for r in self.colliding_ranges],
            "max_depth": self.max_depth,
            "angles": list(self.angles),
            "clearance": list(self.clearance),
            "moving_link": self.moving_link,
            "adjacent": self.adjacent,
            "clearance_bound": self.clearance_bound,
            "proven": self.proven,
            "queries": self.queries,
        }


@dataclass(frozen=True)
class JointSweep:
    """One ``sweeps`` entry: ``joint`` turned over ``grid_points`` angles (with the
    ``moving_joints`` that turn with it over ``swept_dimensions``), the ``moving_links``, its
    ``pairs``, whether every pair's clearance is ``proven`` between grid points, the
    ``scope`` of links checked (``None``: all) and the ``far_pairs`` the broad phase proved
    out of reach."""

    joint: str
    pairs: tuple[SweepPair, ...] = ()
    moving_joints: tuple[str, ...] = ()
    moving_links: tuple[str, ...] = ()
    grid_points: int | None = None
    proven: bool | None = None
    swept_dimensions: tuple[str, ...] = ()
    scope: tuple[str, ...] | None = None
    far_pairs: int | None = None

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> JointSweep:
        scope = data.get("scope")
        return cls(
            joint=str(data.get("joint", "")),
            pairs=tuple(SweepPair.from_dict(p) for p in data.get("pairs") or ()),
            moving_joints=tuple(str(x) for x in data.get("moving_joints") or ()),
            moving_links=tuple(str(x) for x in data.get("moving_links") or ()),
            grid_points=data.get("grid_points"),
            proven=data.get("proven"),
            swept_dimensions=tuple(data.get("swept_dimensions") or ()),
            scope=None if scope is None else tuple(str(x) for x in scope),
            far_pairs=data.get("far_pairs"),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "joint": self.joint,
            "moving_joints": list(self.moving_joints),
            "moving_links": list(self.moving_links),
            "grid_points": self.grid_points,
            "proven": self.proven,
            "pairs": [p.to_dict() for p in self.pairs],
            "swept_dimensions": list(self.swept_dimensions),
            "scope": None if self.scope is None else list(self.scope),
            "far_pairs": self.far_pairs,
        }


def sweeps_section(sections: Mapping[str, Any]) -> tuple[JointSweep, ...]:
    """The report's ``sweeps`` section, parsed; empty when the family did not run."""
    entries = sections.get("sweeps")
    return tuple(JointSweep.from_dict(e) for e in entries) if isinstance(entries, list) else ()
