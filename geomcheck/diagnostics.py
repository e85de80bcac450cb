"""Diagnostics: what a rule found, where, with the numbers."""

from __future__ import annotations

import enum
import hashlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from geomcheck.model import SourceLocation

if TYPE_CHECKING:
    from geomcheck.fix.model import SuggestedFix


class Severity(enum.StrEnum):
    """How bad a finding is; ``rank`` orders them (error highest)."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"error": 3, "warning": 2, "info": 1}[self.value]


@dataclass(frozen=True)
class Diagnostic:
    """One finding of one rule about one subject.

    ``link``/``joint``/``links`` name the subject (``links`` for a pair, sorted);
    ``about`` names the part of the subject the finding concerns (``collision[0]``,
    ``axis``, ``inertia``) so that two findings of one rule on one link stay apart.
    ``data`` holds the metrics behind the message, JSON-ready, in SI units.
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
        """How ``geomcheck fix`` would fix this finding (derived from its rule and ``data``), if it can."""
        from geomcheck.fix.derive import suggested_fix

        return suggested_fix(self)

    @property
    def fingerprint(self) -> str:
        """Identity stable under reformatting and line shifts: rule, subject and ``about``."""
        pair = "|".join(self.links) if self.links else ""
        key = "\x1f".join((self.code, self.link or "", self.joint or "", pair, self.about))
        return hashlib.sha256(key.encode()).hexdigest()[:16]

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


__all__ = ["Diagnostic", "Severity", "SkippedCheck"]
