"""Numbers of URDF attributes: parsed as urdfdom parses them, judged against the magnitudes
geomcheck can compute with (GC107 unparseable, GC108 missing, GC126 out of range)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from lxml import etree

from geomcheck.load.urdf_findings import Subject, shorten, tag_of
from geomcheck.load.urdf_markup import UrdfMarkup
from geomcheck.model import Vec3
from geomcheck.rules import Rule
from geomcheck.rules.structure import INVALID_NUMBER, MISSING_ATTRIBUTE, NUMBER_OUT_OF_RANGE
from geomcheck.thresholds import LoadLimits

LIMITS = LoadLimits()  # the magnitudes geomcheck computes with
_LENGTH = (LIMITS.max_length_m, "m")
# (element, attribute) -> largest magnitude and its unit; numbers beyond it are GC126
MAGNITUDE_LIMITS: dict[tuple[str, str], tuple[float, str]] = {
    ("origin", "xyz"): _LENGTH,
    ("origin", "rpy"): (LIMITS.max_length_m, "rad"),
    ("box", "size"): _LENGTH,
    ("cylinder", "radius"): _LENGTH,
    ("cylinder", "length"): _LENGTH,
    ("sphere", "radius"): _LENGTH,
    ("capsule", "radius"): _LENGTH,
    ("capsule", "length"): _LENGTH,
    ("mesh", "scale"): (LIMITS.max_mesh_scale, ""),
    ("axis", "xyz"): _LENGTH,
    ("mass", "value"): (LIMITS.max_mass_kg, "kg"),
    **{("inertia", k): (LIMITS.max_inertia_kg_m2, "kg m^2") for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")},
}
_SIZE = (LIMITS.min_size_m, "m")
# (element, attribute) -> smallest nonzero magnitude and its unit; sizes below it are GC126
SIZE_FLOORS: dict[tuple[str, str], tuple[float, str]] = {
    ("box", "size"): _SIZE,
    ("cylinder", "radius"): _SIZE,
    ("cylinder", "length"): _SIZE,
    ("sphere", "radius"): _SIZE,
    ("capsule", "radius"): _SIZE,
    ("capsule", "length"): _SIZE,
    ("mesh", "scale"): (LIMITS.min_mesh_scale, ""),
}


@dataclass(frozen=True)
class Complaint:
    """What is wrong with the numbers of an attribute: the rule, its message and its data."""

    rule: Rule
    message: str
    data: dict[str, Any]


@dataclass(frozen=True)
class NumberText:
    """The text of one numeric attribute of a ``<kind>`` and the numbers read from it."""

    kind: str | None
    attribute: str
    text: str
    count: int  # how many numbers the attribute holds
    values: tuple[float, ...]  # the finite numbers before the first that is not one
    bad: str | None  # the first part that is not a finite number

    @classmethod
    def read(cls, kind: str | None, attribute: str, text: str, count: int) -> NumberText:
        values: list[float] = []
        for part in text.split():
            try:
                value = float(part)
            except ValueError:
                return cls(kind, attribute, text, count, tuple(values), part)
            if not math.isfinite(value):
                return cls(kind, attribute, text, count, tuple(values), part)
            values.append(value)
        return cls(kind, attribute, text, count, tuple(values), None)

    @property
    def well_formed(self) -> bool:
        return self.bad is None and len(self.values) == self.count

    def range_complaint(self, value: float, limit: float, unit: str, beyond: str) -> Complaint:
        unit = f" {unit}" if unit else ""
        return Complaint(
            NUMBER_OUT_OF_RANGE,
            f'<{self.kind} {self.attribute}="{shorten(self.text)}">: {value:g}{unit} {beyond} {limit:g}{unit}',
            {"element": self.kind, "attribute": self.attribute, "value": value, "limit": limit},
        )


def malformed(read: NumberText) -> Complaint | None:
    """GC107 for text that is not ``count`` finite numbers."""
    if read.well_formed:
        return None
    parts = len(read.text.split())
    reason = f"{read.bad!r} is not a finite number" if read.bad is not None else f"expected {read.count}, got {parts}"
    noun = "a number" if read.count == 1 else f"{read.count} numbers"
    return Complaint(
        INVALID_NUMBER,
        f'<{read.kind} {read.attribute}="{shorten(read.text)}"> is not {noun}: {reason}',
        {"element": read.kind, "attribute": read.attribute, "value": shorten(read.text), "expected": read.count},
    )


def too_large(read: NumberText) -> Complaint | None:
    """GC126 for a number beyond the largest magnitude of its attribute."""
    bound = MAGNITUDE_LIMITS.get((read.kind or "", read.attribute))
    if bound is None:
        return None
    largest = max(read.values, key=abs)
    if abs(largest) <= bound[0]:
        return None
    return read.range_complaint(largest, bound[0], bound[1], "is beyond the limit of")


def too_small(read: NumberText) -> Complaint | None:
    """GC126 for a nonzero size below the smallest one geomcheck computes with."""
    floor = SIZE_FLOORS.get((read.kind or "", read.attribute))
    tiny = [v for v in read.values if 0.0 < abs(v) < floor[0]] if floor is not None else []
    if floor is None or not tiny:
        return None
    return read.range_complaint(tiny[0], floor[0], floor[1], "is below the smallest size of")


def complaint(read: NumberText, magnitude: bool) -> Complaint | None:
    """The first thing wrong with ``read``: its form, then its magnitude (when the caller leaves
    it to this module), then its size."""
    if not read.well_formed:
        return malformed(read)
    return (too_large(read) if magnitude else None) or too_small(read)


class UrdfNumbers(UrdfMarkup):
    """Readers of numeric attributes, each finding reported and the default kept in its place."""

    def numbers(
        self,
        element: etree._Element,
        attribute: str,
        count: int,
        subject: Subject,
        about: str,
        default: Sequence[float] | None,
        required: bool = False,
        magnitude: bool = True,
    ) -> tuple[float, ...] | None:
        """``count`` finite numbers from ``attribute``; the default (and GC107/GC108) otherwise.
        ``magnitude=False`` leaves the size of the numbers to the caller (GC126)."""
        text = element.get(attribute)
        kind = tag_of(element)
        fallback = tuple(default) if default is not None else None
        if text is None or not text.strip():
            if required:
                self.report(
                    MISSING_ATTRIBUTE,
                    f"<{kind}> has no {attribute} attribute",
                    element,
                    subject,
                    f"{about}.{attribute}",
                    element=kind,
                    attribute=attribute,
                )
            return fallback
        read = NumberText.read(kind, attribute, text, count)
        found = complaint(read, magnitude)
        if found is None:
            return read.values
        self.report(found.rule, found.message, element, subject, f"{about}.{attribute}", **found.data)
        return fallback

    def number(
        self,
        element: etree._Element,
        attribute: str,
        subject: Subject,
        about: str,
        default: float | None,
        required: bool = False,
        magnitude: bool = True,
    ) -> float | None:
        values = self.numbers(
            element, attribute, 1, subject, about, None if default is None else (default,), required, magnitude
        )
        return values[0] if values else None

    def vec3(self, element: etree._Element, attribute: str, subject: Subject, about: str, default: Vec3) -> Vec3:
        values = self.numbers(element, attribute, 3, subject, about, default)
        assert values is not None
        return (values[0], values[1], values[2])


__all__ = ["MAGNITUDE_LIMITS", "SIZE_FLOORS", "NumberText", "UrdfNumbers"]
