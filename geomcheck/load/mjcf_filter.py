"""The body pairs a compiled MJCF model never collides, as disabled collision pairs (read where
an SRDF's would be): bodies welded into one (``same-body``), a welded body and its parent's
(MuJoCo's ``filterparent``, unless the option disables it or one is welded to the world:
``Adjacent``), pairs whose geoms' ``contype``/``conaffinity`` bits never match (``contype``) and
``<exclude>`` pairs (``exclude``); a ``<pair>`` between two bodies keeps them a pair. A model whose
options turn contacts off (``<flag contact="disable"/>``, or ``constraint="disable"``, which
turns off every constraint) collides no pair at all (``contacts-disabled``).
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from lxml import etree

from geomcheck.load.mjcf_xml import XmlModel
from geomcheck.load.srdf import DisabledPair, Srdf
from geomcheck.model import SourceLocation


class BodyPlaces(Protocol):
    """Names and source locations of a compiled model's bodies (the MJCF loader's mapper)."""

    root_display: str
    xml: XmlModel
    mujoco: Any

    def body_name(self, b: int) -> str: ...

    def body_location(self, b: int) -> SourceLocation: ...

    def location(self, element: etree._Element | None, file: str) -> SourceLocation: ...


class CollisionFilter:
    """MuJoCo's collision filter of one compiled ``model``, its bodies named by ``places``."""

    def __init__(self, model: Any, places: BodyPlaces) -> None:
        self.model = model
        self.places = places
        mujoco = places.mujoco
        disabled = int(model.opt.disableflags)
        self.filter_parent = not disabled & int(mujoco.mjtDisableBit.mjDSBL_FILTERPARENT)
        off = int(mujoco.mjtDisableBit.mjDSBL_CONTACT) | int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
        self.no_contacts = bool(disabled & off)
        self.weld = [int(w) for w in model.body_weldid]
        self.weld_parent = [self.weld[int(model.body_parentid[w])] for w in self.weld]

    def srdf(self) -> Srdf | None:
        """The pairs as an SRDF's disabled pairs, sorted by body; ``None`` when there are none."""
        pairs = self.excluded()
        paired = self.paired()
        by_body = self.colliding_geoms()
        bodies = sorted(by_body)
        for i, first in enumerate(bodies):
            for second in bodies[i + 1 :]:
                if (first, second) in pairs or ((first, second) in paired and not self.no_contacts):
                    continue
                reason = self.reason(first, second, by_body)
                if reason:
                    where = self.places.body_location(second)
                    pairs[(first, second)] = DisabledPair(
                        self.places.body_name(first), self.places.body_name(second), reason, where
                    )
        if not pairs:
            return None
        disabled = tuple(pairs[key] for key in sorted(pairs))
        return Srdf(robot_name="", source=self.places.root_display, disabled=disabled, location=disabled[0].location)

    def excluded(self) -> dict[tuple[int, int], DisabledPair]:
        """The ``<exclude>`` pairs, each at its element when the elements match MuJoCo's."""
        model, places = self.model, self.places
        pairs: dict[tuple[int, int], DisabledPair] = {}
        elements = places.xml.excludes
        for k in range(int(model.nexclude)):
            signature = int(model.exclude_signature[k])
            first, second = sorted((signature >> 16, signature & 0xFFFF))
            found = elements[k] if len(elements) == model.nexclude else None
            where = places.location(*found) if found else SourceLocation(places.root_display)
            pairs[(first, second)] = DisabledPair(places.body_name(first), places.body_name(second), "exclude", where)
        return pairs

    def paired(self) -> set[tuple[int, ...]]:
        """The body pairs an explicit ``<pair>`` of geoms makes collide whatever the filter says."""
        model = self.model
        return {
            tuple(sorted((int(model.geom_bodyid[a]), int(model.geom_bodyid[b]))))
            for a, b in zip(model.pair_geom1, model.pair_geom2, strict=True)
        }

    def colliding_geoms(self) -> dict[int, list[int]]:
        """Per body, its geoms that take part in contacts."""
        model = self.model
        by_body: dict[int, list[int]] = {}
        for g in range(model.ngeom):
            if model.geom_contype[g] or model.geom_conaffinity[g]:
                by_body.setdefault(int(model.geom_bodyid[g]), []).append(g)
        return by_body

    def reason(self, first: int, second: int, by_body: dict[int, list[int]]) -> str:
        """Why MuJoCo never collides bodies ``first`` and ``second`` (``""``: it may)."""
        if self.no_contacts:
            return "contacts-disabled"
        w1, w2 = self.weld[first], self.weld[second]
        if w1 == w2:
            return "same-body"
        if self.filter_parent and w1 and w2 and (w1 == self.weld_parent[w2] or w2 == self.weld_parent[w1]):
            return "Adjacent"
        if not self.bits_match(by_body[first], by_body[second]):
            return "contype"
        return ""

    def bits_match(self, first: list[int], second: list[int]) -> bool:
        """Whether a geom of ``first`` and one of ``second`` can touch by their contact bits."""
        model = self.model
        type1, aff1 = model.geom_contype[first][:, None], model.geom_conaffinity[first][:, None]
        type2, aff2 = model.geom_contype[second][None, :], model.geom_conaffinity[second][None, :]
        return bool(np.any((type1 & aff2) | (type2 & aff1)))


def collision_filter(model: Any, places: BodyPlaces) -> Srdf | None:
    """The body pairs the compiled ``model`` never collides, as disabled pairs (``None``: none)."""
    return CollisionFilter(model, places).srdf()


__all__ = ["BodyPlaces", "CollisionFilter", "collision_filter"]
