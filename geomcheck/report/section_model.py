"""The ``model`` report section as typed data: the links and joints the description's file
declares, as its format's own tool counts them, with their frames, shapes, inertials, axes
and limits.

Written by the structure family (geomcheck/checks/model_section.py) as JSON-ready dicts,
documented in docs/report-schema.md; readers parse it here and use named fields. ``from_dict``
tolerates keys a hand-written report leaves out, and ``to_dict`` writes every key in the
family's order (``axis2`` only when present), so a parsed section serialises back to the same
JSON. Numbers keep their JSON type.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

Vector = tuple[float, ...]


@dataclass(frozen=True)
class Frame:
    """A pose: translation [m] and fixed-axis roll, pitch, yaw [rad], as URDF's ``<origin>``."""

    xyz: Vector = (0.0, 0.0, 0.0)
    rpy: Vector = (0.0, 0.0, 0.0)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any] | None) -> Frame:
        data = data or {}
        return cls(tuple(data.get("xyz") or (0.0, 0.0, 0.0)), tuple(data.get("rpy") or (0.0, 0.0, 0.0)))

    def to_dict(self) -> dict[str, list[float]]:
        return {"xyz": list(self.xyz), "rpy": list(self.rpy)}


@dataclass(frozen=True)
class ModelShape:
    """A visual or collision: its ``type`` as the file writes it (``capsule``, ``cone``...) and
    its dimensions as the file writes them (``geometry``: ``size``; ``radius`` and ``length``;
    ``radius``; ``filename`` and ``scale``)."""

    index: int
    name: str | None
    type: str
    origin: Frame
    geometry: Mapping[str, Any]

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ModelShape:
        return cls(
            int(data.get("index", 0)),
            data.get("name"),
            str(data.get("type", "")),
            Frame.from_dict(data.get("origin")),
            dict(data.get("geometry") or {}),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "index": self.index,
            "name": self.name,
            "type": self.type,
            "origin": self.origin.to_dict(),
            "geometry": dict(self.geometry),
        }


@dataclass(frozen=True)
class ModelInertial:
    """``mass`` [kg], the centre-of-mass frame ``origin`` and the tensor in it [kg m^2]."""

    mass: float
    origin: Frame
    inertia: Mapping[str, float]

    @classmethod
    def from_dict(cls, data: Mapping[str, Any] | None) -> ModelInertial | None:
        if data is None:
            return None
        return cls(data.get("mass", 0.0), Frame.from_dict(data.get("origin")), dict(data.get("inertia") or {}))

    def to_dict(self) -> dict[str, Any]:
        return {"mass": self.mass, "origin": self.origin.to_dict(), "inertia": dict(self.inertia)}


@dataclass(frozen=True)
class ModelLink:
    name: str
    inertial: ModelInertial | None
    visuals: tuple[ModelShape, ...]
    collisions: tuple[ModelShape, ...]

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ModelLink:
        return cls(
            str(data.get("name", "")),
            ModelInertial.from_dict(data.get("inertial")),
            tuple(ModelShape.from_dict(s) for s in data.get("visuals") or ()),
            tuple(ModelShape.from_dict(s) for s in data.get("collisions") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "inertial": None if self.inertial is None else self.inertial.to_dict(),
            "visuals": [s.to_dict() for s in self.visuals],
            "collisions": [s.to_dict() for s in self.collisions],
        }


@dataclass(frozen=True)
class ModelJoint:
    """A joint of the file: ``type`` as written, ``parent`` and ``child`` links of the file,
    ``origin`` the joint frame in the parent link's frame (every joint at zero), ``axis`` in the
    joint frame (``None`` for a joint without one), ``limit`` (``lower``, ``upper`` [rad or m],
    ``None`` on an open side; ``effort``, ``velocity``), ``mimic`` (``joint``, ``multiplier``,
    ``offset``) and, for an SDFormat universal or revolute2 joint, ``axis2``."""

    name: str
    type: str
    parent: str
    child: str
    origin: Frame
    axis: Vector | None
    limit: Mapping[str, float | None] | None
    mimic: Mapping[str, Any] | None
    axis2: Vector | None = None

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ModelJoint:
        axis, axis2 = data.get("axis"), data.get("axis2")
        limit, mimic = data.get("limit"), data.get("mimic")
        return cls(
            str(data.get("name", "")),
            str(data.get("type", "")),
            str(data.get("parent", "")),
            str(data.get("child", "")),
            Frame.from_dict(data.get("origin")),
            None if axis is None else tuple(axis),
            None if limit is None else dict(limit),
            None if mimic is None else dict(mimic),
            None if axis2 is None else tuple(axis2),
        )

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "name": self.name,
            "type": self.type,
            "parent": self.parent,
            "child": self.child,
            "origin": self.origin.to_dict(),
            "axis": None if self.axis is None else list(self.axis),
            "limit": None if self.limit is None else dict(self.limit),
            "mimic": None if self.mimic is None else dict(self.mimic),
        }
        if self.axis2 is not None:
            out["axis2"] = list(self.axis2)
        return out


@dataclass(frozen=True)
class ModelSection:
    links: tuple[ModelLink, ...] = ()
    joints: tuple[ModelJoint, ...] = ()

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ModelSection:
        return cls(
            tuple(ModelLink.from_dict(e) for e in data.get("links") or ()),
            tuple(ModelJoint.from_dict(e) for e in data.get("joints") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        return {"links": [e.to_dict() for e in self.links], "joints": [e.to_dict() for e in self.joints]}

    def link(self, name: str) -> ModelLink | None:
        return next((e for e in self.links if e.name == name), None)

    def joint(self, name: str) -> ModelJoint | None:
        return next((e for e in self.joints if e.name == name), None)


def model_section(sections: Mapping[str, Any]) -> ModelSection | None:
    """The report's ``model`` section, parsed; ``None`` when the structure family did not run."""
    found = sections.get("model")
    return None if found is None else ModelSection.from_dict(found)
