"""The ``links`` report section as typed data: per link, how its collision elements fit its
visual geometry.

Written by the fit family (geomcheck/checks/fit.py: ``check_link``, with each element's
metrics from geomcheck/geometry/fit.py ``ElementFit.to_dict``) as JSON-ready dicts, documented
in docs/report-schema.md; readers parse it here and use named fields. ``from_dict`` tolerates
the keys an older or hand-written report leaves out; ``to_dict`` writes the keys, in the
order, the family writes them, so a parsed entry serialises back to the same JSON. Numbers
keep their JSON type (no conversion), which is what keeps that exact. Parts no reader
interprets (an element's ``origin`` and ``geometry``, the visual meshes, the union, the
borrowed elements, the precision) stay JSON objects.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

JSONObject = Mapping[str, Any]


@dataclass(frozen=True)
class AxisAlternative:
    """A cylinder that does not cover its part, turned onto the best other link axis."""

    axis: tuple[float, ...] = ()
    axis_name: str = "other"
    rpy: tuple[float, ...] = ()
    coverage: float | None = None
    protrusion_max_mm: float | None = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> AxisAlternative:
        return cls(
            axis=tuple(data.get("axis") or ()),
            axis_name=str(data.get("axis_name", "other")),
            rpy=tuple(data.get("rpy") or ()),
            coverage=data.get("coverage"),
            protrusion_max_mm=data.get("protrusion_max_mm"),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "axis": list(self.axis),
            "axis_name": self.axis_name,
            "rpy": list(self.rpy),
            "coverage": self.coverage,
            "protrusion_max_mm": self.protrusion_max_mm,
        }


@dataclass(frozen=True)
class SuggestedPrimitive:
    """The primitive that would fit the element's part of the mesh, with its URDF text."""

    type: str = ""
    origin: JSONObject | None = None  # {"xyz": [...], "rpy": [...]}
    geometry: JSONObject | None = None
    urdf: str = ""
    coverage: float | None = None
    slack: float | None = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> SuggestedPrimitive:
        return cls(
            type=str(data.get("type", "")),
            origin=data.get("origin"),
            geometry=data.get("geometry"),
            urdf=str(data.get("urdf", "")),
            coverage=data.get("coverage"),
            slack=data.get("slack"),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": self.type,
            "origin": self.origin,
            "geometry": self.geometry,
            "urdf": self.urdf,
            "coverage": self.coverage,
            "slack": self.slack,
        }


@dataclass(frozen=True)
class MeshComparison:
    """A collision mesh against the visual one, the other way round (collision meshes only)."""

    reverse_coverage: float | None = None
    overshoot_max_mm: float | None = None
    overshoot_p95_mm: float | None = None
    surface_distance_max_mm: float | None = None
    surface_distance_p95_mm: float | None = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> MeshComparison:
        return cls(
            reverse_coverage=data.get("reverse_coverage"),
            overshoot_max_mm=data.get("overshoot_max_mm"),
            overshoot_p95_mm=data.get("overshoot_p95_mm"),
            surface_distance_max_mm=data.get("surface_distance_max_mm"),
            surface_distance_p95_mm=data.get("surface_distance_p95_mm"),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "reverse_coverage": self.reverse_coverage,
            "overshoot_max_mm": self.overshoot_max_mm,
            "overshoot_p95_mm": self.overshoot_p95_mm,
            "surface_distance_max_mm": self.surface_distance_max_mm,
            "surface_distance_p95_mm": self.surface_distance_p95_mm,
        }


@dataclass(frozen=True)
class ElementFit:
    """How one collision element fits its part of the visual mesh (docs/report-schema.md):
    ``gaps_mm`` per side (positive: the element overshoots), ``coverage`` and protrusions of
    the part, ``slack``, the volumes, ``offset_mm`` that centres the element and whether it
    ``fits_when_moved``, a better cylinder axis, the suggested primitive, the comparison of
    a collision mesh with the visual one, whether the element closes a capsule and the
    neighbour it covers across a joint."""

    gaps_mm: Mapping[str, float | None] | None = None
    coverage: float | None = None
    protrusion_max_mm: float | None = None
    protrusion_p95_mm: float | None = None
    slack: float | None = None
    primitive_volume: float | None = None
    hull_volume: float | None = None
    mesh_inside: float | None = None
    in_hull: float | None = None
    part_points: int | None = None
    offset_mm: tuple[float, ...] | None = None
    fits_when_moved: bool | None = None
    axis_alternative: AxisAlternative | None = None
    suggested: SuggestedPrimitive | None = None
    comparison: MeshComparison | None = None
    capsule_cap: bool | None = None
    covers_neighbour: str | None = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> ElementFit:
        offset, alt, suggested = data.get("offset_mm"), data.get("axis_alternative"), data.get("suggested")
        return cls(
            gaps_mm=data.get("gaps_mm"),
            coverage=data.get("coverage"),
            protrusion_max_mm=data.get("protrusion_max_mm"),
            protrusion_p95_mm=data.get("protrusion_p95_mm"),
            slack=data.get("slack"),
            primitive_volume=data.get("primitive_volume"),
            hull_volume=data.get("hull_volume"),
            mesh_inside=data.get("mesh_inside"),
            in_hull=data.get("in_hull"),
            part_points=data.get("part_points"),
            offset_mm=None if offset is None else tuple(offset),
            fits_when_moved=data.get("fits_when_moved"),
            axis_alternative=AxisAlternative.from_dict(alt) if alt else None,
            suggested=SuggestedPrimitive.from_dict(suggested) if suggested else None,
            comparison=MeshComparison.from_dict(data) if "reverse_coverage" in data else None,
            capsule_cap=data.get("capsule_cap"),
            covers_neighbour=data.get("covers_neighbour"),
        )

    def to_dict(self) -> dict[str, Any]:
        alt, suggested = self.axis_alternative, self.suggested
        out: dict[str, Any] = {
            "gaps_mm": self.gaps_mm,
            "coverage": self.coverage,
            "protrusion_max_mm": self.protrusion_max_mm,
            "protrusion_p95_mm": self.protrusion_p95_mm,
            "slack": self.slack,
            "primitive_volume": self.primitive_volume,
            "hull_volume": self.hull_volume,
            "mesh_inside": self.mesh_inside,
            "in_hull": self.in_hull,
            "part_points": self.part_points,
            "offset_mm": None if self.offset_mm is None else list(self.offset_mm),
            "fits_when_moved": self.fits_when_moved,
            "axis_alternative": None if alt is None else alt.to_dict(),
            "suggested": None if suggested is None else suggested.to_dict(),
        }
        if self.comparison is not None:
            out |= self.comparison.to_dict()
        return out | {"capsule_cap": self.capsule_cap, "covers_neighbour": self.covers_neighbour}


@dataclass(frozen=True)
class CollisionElement:
    """One ``<collision>`` of the link: its ``index`` among them, geometry ``type`` (``box``,
    ``cylinder``, ``sphere``, ``mesh``), ``origin`` and ``geometry`` as JSON objects, and its
    ``fit`` (``None`` when the link was not fitted)."""

    index: int | None = None
    type: str = "?"
    origin: JSONObject | None = None
    geometry: JSONObject | None = None
    fit: ElementFit | None = None

    @property
    def label(self) -> str:
        """``collision[0]``: how findings name the element (their ``about``)."""
        return f"collision[{'?' if self.index is None else self.index}]"

    @classmethod
    def from_dict(cls, data: JSONObject) -> CollisionElement:
        fit = data.get("fit")
        return cls(
            index=data.get("index"),
            type=str(data.get("type", "?")),
            origin=data.get("origin"),
            geometry=data.get("geometry"),
            fit=ElementFit.from_dict(fit) if fit else None,
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "index": self.index,
            "type": self.type,
            "origin": self.origin,
            "geometry": self.geometry,
            "fit": None if self.fit is None else self.fit.to_dict(),
        }


@dataclass(frozen=True)
class LinkFit:
    """One ``links`` entry: the link's visual meshes, its collision elements, the union of
    them (with borrowed ones), the elements it borrows across joints, the primitive suggested
    for a link without collision geometry, the checks ``skipped`` (why, in words), and the
    ``precision`` of its metrics (present when the link was fitted)."""

    link: str
    visual_meshes: tuple[JSONObject, ...] = ()
    collisions: tuple[CollisionElement, ...] = ()
    union: JSONObject | None = None
    borrowed: tuple[JSONObject, ...] = ()
    suggested: Any = None
    skipped: tuple[str, ...] = ()
    precision: JSONObject | None = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> LinkFit:
        return cls(
            link=str(data.get("link", "")),
            visual_meshes=tuple(data.get("visual_meshes") or ()),
            collisions=tuple(CollisionElement.from_dict(c) for c in data.get("collisions") or ()),
            union=data.get("union"),
            borrowed=tuple(data.get("borrowed") or ()),
            suggested=data.get("suggested"),
            skipped=tuple(str(s) for s in data.get("skipped") or ()),
            precision=data.get("precision"),
        )

    def to_dict(self) -> dict[str, Any]:
        out = {
            "link": self.link,
            "visual_meshes": list(self.visual_meshes),
            "collisions": [c.to_dict() for c in self.collisions],
            "union": self.union,
            "borrowed": list(self.borrowed),
            "suggested": self.suggested,
            "skipped": list(self.skipped),
        }
        if self.precision is not None:
            out["precision"] = self.precision
        return out


def links_section(sections: Mapping[str, Any]) -> tuple[LinkFit, ...]:
    """The report's ``links`` section, parsed; empty when the family did not run."""
    return tuple(LinkFit.from_dict(e) for e in sections.get("links") or ())
