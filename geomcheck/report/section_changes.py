"""The ``diff`` and ``baseline`` report sections as typed data: what changed against a base
revision (``geomcheck diff``), and which findings a baseline file knew.

Written by geomcheck/diff.py (``diff_report``) and geomcheck/baseline.py as JSON-ready dicts,
documented in docs/report-schema.md; readers parse them here and use named fields. A fixed or
regressed finding stays in its JSON form (docs/report-schema.md, "A diagnostic"), read by key
(a hand-written section may give only some of its keys). ``from_dict`` tolerates the keys a
hand-written report leaves out; ``to_dict`` writes the keys, in the order, the writer writes
them, so a parsed section serialises back to the same JSON.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

JSONObject = Mapping[str, Any]


@dataclass(frozen=True)
class MetricChange:
    """One metric of a regressed finding, before and after (any JSON value)."""

    name: str
    before: Any = None
    after: Any = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> MetricChange:
        return cls(name=str(data.get("name", "")), before=data.get("before"), after=data.get("after"))

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "before": self.before, "after": self.after}


@dataclass(frozen=True)
class Regression:
    """A finding of both sides that got worse: the head's ``diagnostic`` (JSON form), the
    base's severity and the metrics that worsened."""

    diagnostic: JSONObject
    severity_before: str | None = None
    metrics: tuple[MetricChange, ...] = ()

    @classmethod
    def from_dict(cls, data: JSONObject) -> Regression:
        return cls(
            diagnostic=data.get("diagnostic") or {},
            severity_before=data.get("severity_before"),
            metrics=tuple(MetricChange.from_dict(m) for m in data.get("metrics") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "diagnostic": self.diagnostic,
            "severity_before": self.severity_before,
            "metrics": [m.to_dict() for m in self.metrics],
        }


@dataclass(frozen=True)
class DiffSection:
    """``base`` (the revision's label; the description may not exist there: ``base_exists``,
    with a ``base_note`` on why a base side has no findings), the number of ``new`` findings
    (they are the report's diagnostics), the ``fixed`` ones (JSON form), the ``regressions``,
    how many stayed ``unchanged`` and whether regressions are ``gated`` (they then fail)."""

    base: str | None = None
    base_exists: bool = True
    base_note: str | None = None
    new: int = 0
    fixed: tuple[JSONObject, ...] = ()
    regressions: tuple[Regression, ...] = ()
    unchanged: int | None = None
    gated: bool | None = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> DiffSection:
        return cls(
            base=data.get("base"),
            base_exists=bool(data.get("base_exists", True)),
            base_note=data.get("base_note"),
            new=int(data.get("new", 0)),
            fixed=tuple(data.get("fixed") or ()),
            regressions=tuple(Regression.from_dict(r) for r in data.get("regressions") or ()),
            unchanged=data.get("unchanged"),
            gated=data.get("gated"),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "base": self.base,
            "base_exists": self.base_exists,
            "base_note": self.base_note,
            "new": self.new,
            "fixed": list(self.fixed),
            "regressions": [r.to_dict() for r in self.regressions],
            "unchanged": self.unchanged,
            "gated": self.gated,
        }


@dataclass(frozen=True)
class StaleEntry:
    """A baseline entry no finding matched any more."""

    fingerprint: str = ""
    code: str = ""
    subject: str = ""
    message: str = ""

    @classmethod
    def from_dict(cls, data: JSONObject) -> StaleEntry:
        return cls(
            fingerprint=str(data.get("fingerprint", "")),
            code=str(data.get("code", "")),
            subject=str(data.get("subject", "")),
            message=str(data.get("message", "")),
        )

    def to_dict(self) -> dict[str, Any]:
        return {"fingerprint": self.fingerprint, "code": self.code, "subject": self.subject, "message": self.message}


@dataclass(frozen=True)
class BaselineSection:
    """The baseline ``file``, its number of ``entries``, how many findings it ``matched``
    (left out of the diagnostics) and its ``stale`` entries."""

    file: str | None = None
    entries: int | None = None
    matched: int = 0
    stale: tuple[StaleEntry, ...] = ()

    @classmethod
    def from_dict(cls, data: JSONObject) -> BaselineSection:
        return cls(
            file=data.get("file"),
            entries=data.get("entries"),
            matched=int(data.get("matched", 0)),
            stale=tuple(StaleEntry.from_dict(e) for e in data.get("stale") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "file": self.file,
            "entries": self.entries,
            "matched": self.matched,
            "stale": [e.to_dict() for e in self.stale],
        }


def diff_section(sections: Mapping[str, Any]) -> DiffSection | None:
    """The report's ``diff`` section, parsed; ``None`` outside ``geomcheck diff``."""
    section = sections.get("diff")
    return DiffSection.from_dict(section) if isinstance(section, dict) else None


def baseline_section(sections: Mapping[str, Any]) -> BaselineSection | None:
    """The report's ``baseline`` section, parsed; ``None`` without a baseline."""
    section = sections.get("baseline")
    return BaselineSection.from_dict(section) if isinstance(section, dict) else None
