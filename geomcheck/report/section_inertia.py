"""The ``inertia`` report section as typed data: per link with an ``<inertial>``, its mass
properties against what its geometry allows.

Written by the inertia family (geomcheck/checks/inertia/link.py: ``empty_entry`` and the checks
that fill it) as JSON-ready dicts, documented in docs/report-schema.md; readers parse it here
and use named fields. The family writes every key, ``None`` where a value is unknown (the
tensor was not finite, the mass not positive, the geometry not readable); ``from_dict``
tolerates the keys a hand-written report leaves out, and ``to_dict`` writes every key in the
family's order, so a parsed entry serialises back to the same JSON. Numbers keep their JSON
type (no conversion), which is what keeps that exact.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

# Per principal axis (three values) or per link axis; ``None`` for a value that is unknown.
Triple = tuple[float | None, ...]


@dataclass(frozen=True)
class InertiaEntry:
    """One ``inertia`` entry. Masses [kg], lengths [m], moments [kg m^2], all in the link frame.

    ``principal_moments`` with their unit ``principal_axes`` (an axis is ``None`` when its
    moment equals another's); ``geometry_bound`` the largest moment the geometry allows about
    each principal axis (mass x ``reach``^2) and ``radius_of_gyration`` the moment's own
    reach; ``spread``, ``extent``, ``moments_xyz`` and ``geometry_bound_xyz`` the same about
    the link axes; the verdicts ``positive_definite``, ``triangle_ok`` (triangle inequality),
    ``within_geometry`` (every moment under its bound) and ``com_inside_bounds`` (the centre
    of mass ``com`` within ``com_distance_outside`` of the geometry's ``bounds``, lower and
    upper corners); ``hull_volume`` [m^3] and ``density`` [kg/m^3] of the convex hull;
    ``copied_from`` the link whose tensor this one repeats.
    """

    link: str
    mass: float | None = None
    com: Triple | None = None
    principal_moments: Triple | None = None
    principal_axes: tuple[Triple | None, ...] | None = None
    geometry_bound: Triple | None = None
    radius_of_gyration: Triple | None = None
    reach: Triple | None = None
    positive_definite: bool | None = None
    triangle_ok: bool | None = None
    within_geometry: bool | None = None
    com_inside_bounds: bool | None = None
    spread: Triple | None = None
    extent: Triple | None = None
    moments_xyz: Triple | None = None
    geometry_bound_xyz: Triple | None = None
    com_distance_outside: float | None = None
    bounds: tuple[Triple, ...] | None = None
    hull_volume: float | None = None
    density: float | None = None
    copied_from: str | None = None

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> InertiaEntry:
        values = {f.name: _tuples(data.get(f.name)) for f in fields(cls) if f.name != "link"}
        return cls(link=str(data.get("link", "")), **values)

    def to_dict(self) -> dict[str, Any]:
        return {f.name: _lists(getattr(self, f.name)) for f in fields(self)}


def _tuples(value: Any) -> Any:
    """A JSON value with its lists (at any depth) as tuples: hashable, immutable."""
    return tuple(_tuples(v) for v in value) if isinstance(value, list) else value


def _lists(value: Any) -> Any:
    return [_lists(v) for v in value] if isinstance(value, Sequence) and not isinstance(value, str) else value


def inertia_section(sections: Mapping[str, Any]) -> tuple[InertiaEntry, ...]:
    """The report's ``inertia`` section, parsed; empty when the family did not run."""
    return tuple(InertiaEntry.from_dict(e) for e in sections.get("inertia") or ())
