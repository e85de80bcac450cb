"""Diagnostics: what a rule found, where, with the numbers."""

from __future__ import annotations

import enum
import hashlib
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal

from geomcheck.fixes import SuggestedFix, suggested_fix
from geomcheck.model import SourceLocation


class Severity(enum.StrEnum):
    """How bad a finding is; ``rank`` orders them (error highest)."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"error": 3, "warning": 2, "info": 1}[self.value]


Better = Literal["lower", "higher", "none"]

# The units a metric may declare: SI units (lengths in report data are metres unless the key
# ends in ``_mm``), ``1`` for a dimensionless ratio or share, ``count``, ``SI`` for a value in
# the unit of the attribute it comes from (m, rad or kg); for a value that is not a number,
# its kind: ``text`` (a string, or strings), ``bool`` or ``object`` (a structure of mixed fields).
UNITS = frozenset(
    {"m", "mm", "m^2", "m^3", "rad", "deg", "kg", "kg m^2", "kg/m^3", "1", "count", "SI", "text", "bool", "object"}
)


@dataclass(frozen=True)
class Metric:
    """One key of the ``data`` a rule's findings carry, declared with the rule.

    ``unit`` is one of :data:`UNITS` (for a list or mapping of numbers, the unit of its
    numbers); ``better`` says which way a number improves (``lower``, ``higher``, or ``none``
    for a value that describes rather than measures: a mass, a volume, a threshold), which is
    how ``geomcheck diff`` tells a regression; ``optional`` marks a key only some findings of
    the rule carry (``description`` says when).
    """

    name: str
    unit: str
    better: Better = "none"
    description: str = ""
    optional: bool = False

    @property
    def numeric(self) -> bool:
        """Whether the value is a number (or numbers) with a unit, not text or a structure."""
        return self.unit not in ("text", "bool", "object")


@dataclass(frozen=True)
class Diagnostic:
    """One finding of one rule about one subject.

    ``link``/``joint``/``links`` name the subject (``links`` for a pair, sorted);
    ``about`` names the part of the subject the finding concerns (``collision[0]``,
    ``axis``, ``inertia``) so that two findings of one rule on one link stay apart.
    ``data`` holds the metrics behind the message, JSON-ready, in SI units; each key is a
    :class:`Metric` its rule declares (``Rule.metrics``: unit, which way is better).
    ``excerpt`` is filled by the pipeline: ``(line, text)`` pairs around the location.
    """

    code: str
    name: str
    severity: Severity
    message: str
    help: str
    link: str | None = None
    joint: str | None = None
    links: tuple[str, str] | None = None
    about: str = ""
    location: SourceLocation | None = None
    data: Mapping[str, Any] = field(default_factory=dict)
    excerpt: tuple[tuple[int, str], ...] = ()
    # whether ``geomcheck fix`` can edit the finding's source (a format without fixes keeps
    # its advice, ``help``, but offers none), and the format its fix is written in (``urdf``
    # for URDF and xacro, ``mjcf``, ``sdf``); not compared: two findings differ by their
    # fixes, not by why one has none
    editable: bool = field(default=True, compare=False)
    syntax: str = field(default="urdf", compare=False)

    @property
    def subject(self) -> str:
        """Human name of the subject: ``link X``, ``joint Y``, ``links A / B`` or ``robot``."""
        if self.links is not None:
            return f"links {self.links[0]} / {self.links[1]}"
        if self.joint is not None:
            return f"joint {self.joint}"
        if self.link is not None:
            return f"link {self.link}"
        return "robot"

    @property
    def fix(self) -> SuggestedFix | None:
        """How ``geomcheck fix`` would fix this finding (derived from its rule and ``data``, in its
        description's ``syntax``), if it can."""
        return suggested_fix(self) if self.editable else None

    @property
    def fingerprint(self) -> str:
        """Identity stable under reformatting and line shifts: rule, subject and ``about``."""
        pair = "|".join(self.links) if self.links else ""
        key = "\x1f".join((self.code, self.link or "", self.joint or "", pair, self.about))
        return hashlib.sha256(key.encode()).hexdigest()[:16]

    def grouped_under(self, head: Diagnostic, note: str) -> Diagnostic:
        """This finding as a member of a group reported once, on ``head``: info, ``note`` added,
        and its own severity kept in ``data`` (``severity_alone``, with ``grouped_with`` the head's
        fingerprint): a baseline that accepts the head reports a member it does not hold at that
        severity, so grouping never hides a new defect from a CI gate."""
        data = {**self.data, "grouped_with": head.fingerprint, "severity_alone": self.severity.value}
        return replace(self, message=self.message + note, severity=Severity.INFO, data=data)

    def on_its_own(self, note: str) -> Diagnostic:
        """A group's member (:meth:`grouped_under`) at its own severity, ``note`` added: reported
        apart when what accepts the group (a baseline, a base revision) does not hold it."""
        alone = self.data.get("severity_alone")
        if not isinstance(alone, str):
            return self
        return replace(self, severity=Severity(alone), message=self.message + note)

    def sort_key(self) -> tuple[int, str, str, str]:
        """Errors first, then by code, subject and ``about``: a stable report order."""
        return (-self.severity.rank, self.code, self.subject, self.about)


@dataclass(frozen=True)
class SkippedCheck:
    """A check that could not run for a subject, and why (``check`` is ``fit``, ``units``,
    ``inertia-geometry``, ``sweep``...; ``subject`` a link or joint name, ``""`` for the robot)."""

    check: str
    subject: str
    reason: str


__all__ = [
    "UNITS",
    "Better",
    "Diagnostic",
    "Metric",
    "Severity",
    "SkippedCheck",
    "diagnostic_from_dict",
    "diagnostic_to_dict",
    "location_to_dict",
]


# --- JSON form (the report's, and the stage caches') ---------------------------------


def location_to_dict(loc: SourceLocation | None) -> dict[str, Any] | None:
    if loc is None:
        return None
    return {"file": loc.file, "line": loc.line, "column": loc.column, "expanded_line": loc.expanded_line}


def diagnostic_to_dict(d: Diagnostic) -> dict[str, Any]:
    return {
        "code": d.code,
        "name": d.name,
        "severity": d.severity.value,
        "message": d.message,
        "help": d.help,
        "link": d.link,
        "joint": d.joint,
        "links": list(d.links) if d.links else None,
        "about": d.about,
        "location": location_to_dict(d.location),
        "fingerprint": d.fingerprint,
        "data": dict(d.data),
        "excerpt": [[n, text] for n, text in d.excerpt],
        "fix": None if (fix := d.fix) is None else fix.to_dict(),
    }


def diagnostic_from_dict(data: Mapping[str, Any]) -> Diagnostic:
    loc = data.get("location")
    links = data.get("links")
    return Diagnostic(
        code=data["code"],
        name=data["name"],
        severity=Severity(data["severity"]),
        message=data["message"],
        help=data["help"],
        link=data.get("link"),
        joint=data.get("joint"),
        links=(links[0], links[1]) if links else None,
        about=data.get("about", ""),
        location=SourceLocation(loc["file"], loc.get("line"), loc.get("column"), loc.get("expanded_line"))
        if loc
        else None,
        data=data.get("data", {}),
        excerpt=tuple((int(n), str(t)) for n, t in data.get("excerpt", [])),
        editable=data.get("fix", True) is not None,  # a stored "fix": null stays without a fix
        syntax=str(fix.get("syntax", "urdf")) if isinstance(fix := data.get("fix"), Mapping) else "urdf",
    )
