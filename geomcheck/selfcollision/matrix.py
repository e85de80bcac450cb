"""The collision matrix: every pair of links with collision geometry, classified as MoveIt's
Setup Assistant does (Adjacent, Default, Always, Never, or enabled), with the evidence.

This module holds the result types; :mod:`geomcheck.selfcollision.compute` builds them.
"""

from __future__ import annotations

import enum
import functools
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

DISTANCE_DECIMALS = 6  # report distances and depths to the micrometre [m]
JOINT_DECIMALS = 6  # report joint values to the micro-radian / micrometre


class PairClass(enum.StrEnum):
    """Why a pair is (or is not) disabled, in MoveIt's order of precedence."""

    ADJACENT = "adjacent"  # parent-child with geometry, or joined only through links without geometry
    DEFAULT = "default"  # in collision at the default pose
    ALWAYS = "always"  # in collision in at least ``always_fraction`` of the samples
    NEVER = "never"  # never in collision: certified, or in no sample and no witness found
    ENABLED = "enabled"  # sometimes in collision: must stay checked

    @property
    def srdf_reason(self) -> str | None:
        """The SRDF ``reason`` of a disabled class; ``None`` for enabled pairs."""
        return None if self is PairClass.ENABLED else self.value.capitalize()


class WitnessSource(enum.StrEnum):
    DEFAULT = "default"  # the default pose
    SAMPLE = "sample"  # a random sample
    SEARCH = "search"  # the local search from the closest samples


@dataclass(frozen=True)
class Witness:
    """A configuration in which the pair collides: values of the joints on the path between
    the two links ([rad] or [m]; the others do not change the pair's relative pose), the
    penetration depth there [m] (0 when the backend only reports contact) and how it was found."""

    configuration: Mapping[str, float]
    depth: float
    source: WitnessSource

    def to_dict(self) -> dict[str, Any]:
        return {
            "configuration": {k: round(float(v), JOINT_DECIMALS) for k, v in self.configuration.items()},
            "depth": round(float(self.depth), DISTANCE_DECIMALS),
            "source": self.source.value,
        }

    def describe(self, limit: int = 6) -> str:
        """``j1=0.12, j2=-1.3`` (the first ``limit`` joints)."""
        items = [f"{k}={v:.3f}" for k, v in list(self.configuration.items())[:limit]]
        if len(self.configuration) > limit:
            items.append(f"... ({len(self.configuration) - limit} more)")
        return ", ".join(items) if items else "any configuration"


@dataclass(frozen=True)
class PairResult:
    """One pair of links (sorted by name) and the evidence behind its class.

    ``tested`` samples were checked for it (0 for adjacent, default and certified pairs),
    ``collisions`` of them collided. ``min_distance`` is the closest distance seen [m]
    (exact distances at the samples of closest approach; negative = penetration when the
    backend gives it). ``clearance_bound`` is the proven lower bound of the distance over the
    whole joint space for certified pairs [m].
    """

    links: tuple[str, str]
    cls: PairClass
    tested: int = 0
    collisions: int = 0
    min_distance: float | None = None
    certified: bool = False
    clearance_bound: float | None = None
    witness: Witness | None = None

    @property
    def fraction(self) -> float | None:
        """Share of the tested samples in collision, ``None`` when none was tested."""
        return self.collisions / self.tested if self.tested else None

    @property
    def disabled(self) -> bool:
        return self.cls is not PairClass.ENABLED

    def to_dict(self) -> dict[str, Any]:
        frac = self.fraction
        return {
            "links": list(self.links),
            "class": self.cls.value,
            "fraction": None if frac is None else round(frac, 6),
            "tested": self.tested,
            "min_distance": _round(self.min_distance),
            "certified": self.certified,
            "clearance_bound": _round(self.clearance_bound),
            "witness": self.witness.to_dict() if self.witness else None,
        }


def _round(value: float | None) -> float | None:
    return None if value is None else round(float(value), DISTANCE_DECIMALS)


@dataclass(frozen=True)
class MatrixStats:
    """How the work was spent (not part of the report, which must not depend on timing)."""

    seconds: float = 0.0
    narrow_phase_calls: int = 0  # collision and distance queries, witness search aside
    certified_before_sampling: int = 0
    witness_searches: int = 0


@dataclass(frozen=True)
class CollisionMatrix:
    """The classified pairs, sorted by link names, and how they were computed. Under the
    ``pinocchio`` semantics, pairs of links that only fixed joints join are not pairs
    (:mod:`geomcheck.collision.topology`)."""

    samples: int
    seed: int
    backend: str
    always_fraction: float
    links: tuple[str, ...]  # links with collision geometry, document order
    pairs: tuple[PairResult, ...]
    default_configuration: Mapping[str, float]
    stats: MatrixStats = MatrixStats()
    semantics: str = "moveit"

    @functools.cached_property
    def _index(self) -> Mapping[tuple[str, str], PairResult]:
        return {p.links: p for p in self.pairs}

    def pair(self, a: str, b: str) -> PairResult | None:
        """The result of the pair ``{a, b}``, ``None`` when either link has no collision geometry
        (or, under the ``pinocchio`` semantics, when the two are one rigid body)."""
        return self._index.get((a, b) if a <= b else (b, a))

    def counts(self) -> dict[str, int]:
        """Number of pairs per class, every class present, plus ``certified``."""
        out = {c.value: 0 for c in PairClass}
        for p in self.pairs:
            out[p.cls.value] += 1
        out["certified"] = sum(p.certified for p in self.pairs)
        return out

    def to_section(self) -> dict[str, Any]:
        """The report's ``matrix`` section (docs/report-schema.md)."""
        return {
            "samples": self.samples,
            "seed": self.seed,
            "backend": self.backend,
            "semantics": self.semantics,
            "always_fraction": self.always_fraction,
            "links": list(self.links),
            "counts": self.counts(),
            "pairs": [p.to_dict() for p in self.pairs],
        }
