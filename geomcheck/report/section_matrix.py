"""The ``matrix`` report section as typed data: the collision matrix, one class per link pair.

Written by the matrix family (geomcheck/checks/matrix.py, ``CollisionMatrix.to_section`` in
geomcheck/selfcollision/matrix.py) as a JSON-ready dict, documented in docs/report-schema.md;
readers parse it here and use named fields. The section does not hold everything the
``CollisionMatrix`` does (the collision counts behind a fraction, the timing), so it gets its
own model rather than that one. ``from_dict`` tolerates the keys an older or hand-written
report leaves out; ``to_dict`` writes the keys, in the order, the family writes them, so a
parsed section serialises back to the same JSON. Numbers keep their JSON type.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class MatrixWitness:
    """A configuration in which the pair collides: joint values [rad or m], the depth there
    [m] and how it was found (``default``, ``sample``, ``search``; ``None`` when not said)."""

    configuration: Mapping[str, float] = field(default_factory=dict)
    depth: float | None = None
    source: str | None = None

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> MatrixWitness:
        return cls(configuration=data.get("configuration") or {}, depth=data.get("depth"), source=data.get("source"))

    def to_dict(self) -> dict[str, Any]:
        return {"configuration": dict(self.configuration), "depth": self.depth, "source": self.source}


@dataclass(frozen=True)
class MatrixPair:
    """One link pair (sorted) and its class (``adjacent``, ``default``, ``always``, ``never``,
    ``enabled``: the JSON key ``class``), the share ``fraction`` of the ``tested`` samples in
    collision, the closest distance seen [m], whether bounds ``certified`` it never collides
    with a ``clearance_bound`` [m], and a colliding ``witness``."""

    links: tuple[str, ...] = ()
    cls: str = "enabled"
    fraction: float | None = None
    tested: int | None = None
    min_distance: float | None = None
    certified: bool = False
    clearance_bound: float | None = None
    witness: MatrixWitness | None = None

    @property
    def name(self) -> str:
        """``a / b``."""
        return " / ".join(self.links)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> MatrixPair:
        witness = data.get("witness")
        return cls(
            links=tuple(str(x) for x in data.get("links") or ()),
            cls=str(data.get("class", "enabled")),
            fraction=data.get("fraction"),
            tested=data.get("tested"),
            min_distance=data.get("min_distance"),
            certified=bool(data.get("certified")),
            clearance_bound=data.get("clearance_bound"),
            witness=MatrixWitness.from_dict(witness) if witness else None,
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "links": list(self.links),
            "class": self.cls,
            "fraction": self.fraction,
            "tested": self.tested,
            "min_distance": self.min_distance,
            "certified": self.certified,
            "clearance_bound": self.clearance_bound,
            "witness": None if self.witness is None else self.witness.to_dict(),
        }


@dataclass(frozen=True)
class MatrixSection:
    """The matrix: ``samples`` random configurations drawn with ``seed``, the collision
    ``backend``, the pair ``semantics`` (``moveit`` or ``pinocchio``), the share of samples
    that makes a pair ``always`` in collision, the ``links`` with collision geometry
    (document order), the pairs per class (``counts``) and the ``pairs``."""

    samples: int | None = None
    seed: int | None = None
    backend: str | None = None
    semantics: str | None = None
    always_fraction: float | None = None
    links: tuple[str, ...] = ()
    counts: Mapping[str, int] = field(default_factory=dict)
    pairs: tuple[MatrixPair, ...] = ()

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> MatrixSection:
        return cls(
            samples=data.get("samples"),
            seed=data.get("seed"),
            backend=data.get("backend"),
            semantics=data.get("semantics"),
            always_fraction=data.get("always_fraction"),
            links=tuple(str(x) for x in data.get("links") or ()),
            counts=data.get("counts") or {},
            pairs=tuple(MatrixPair.from_dict(p) for p in data.get("pairs") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "samples": self.samples,
            "seed": self.seed,
            "backend": self.backend,
            "semantics": self.semantics,
            "always_fraction": self.always_fraction,
            "links": list(self.links),
            "counts": dict(self.counts),
            "pairs": [p.to_dict() for p in self.pairs],
        }


def matrix_section(sections: Mapping[str, Any]) -> MatrixSection | None:
    """The report's ``matrix`` section, parsed; ``None`` when the family did not run."""
    section = sections.get("matrix")
    return MatrixSection.from_dict(section) if isinstance(section, dict) and section else None
