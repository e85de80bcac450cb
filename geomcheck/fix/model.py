"""Fixes as data.

A :class:`SuggestedFix` says what a finding's fix changes in the element the finding points
at, independently of how that element is written (plain URDF, a xacro macro, values from
properties). Planning (:mod:`geomcheck.fix.plan`) turns it into :class:`Edit` s: byte spans
of source files and their replacement text.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any


class Applicability(enum.StrEnum):
    """``safe`` fixes keep the description's meaning (a typo, a path's letter case);
    ``unsafe`` ones change the robot (a collision primitive, an inertia tensor) and are
    applied only with ``--unsafe-fixes``."""

    SAFE = "safe"
    UNSAFE = "unsafe"


@dataclass(frozen=True)
class SetAttribute:
    """Set ``attribute`` to ``value`` on the element reached by ``path`` (child tags, first
    match each) from the finding's element; a missing last element of ``path`` is created."""

    path: tuple[str, ...]
    attribute: str
    value: str

    def describe(self) -> str:
        where = "/".join(self.path) or "element"
        return f'{where} {self.attribute}="{self.value}"'


@dataclass(frozen=True)
class RenameAttribute:
    """Rename attribute ``old`` to ``new`` on the element reached by ``path``."""

    path: tuple[str, ...]
    old: str
    new: str

    def describe(self) -> str:
        return f"attribute {self.old} -> {self.new}"


@dataclass(frozen=True)
class RenameElement:
    """Rename the element reached by ``path`` (its start and end tags) to ``new``."""

    path: tuple[str, ...]
    new: str

    def describe(self) -> str:
        return f"element -> <{self.new}>"


@dataclass(frozen=True)
class ReplaceElement:
    """Replace the element reached by ``path`` by ``xml`` (one element, written out)."""

    path: tuple[str, ...]
    xml: str

    def describe(self) -> str:
        return f"{'/'.join(self.path)} -> {self.xml}"


@dataclass(frozen=True)
class ModerniseXacro:
    """Write the legacy xacro syntax of the finding's file in today's (``xacro:`` prefixes,
    the namespace declared): :mod:`geomcheck.fix.modernise`."""

    file: str

    def describe(self) -> str:
        return f"modernise the xacro syntax of {self.file}"


Change = SetAttribute | RenameAttribute | RenameElement | ReplaceElement | ModerniseXacro


@dataclass(frozen=True)
class SuggestedFix:
    """The fix of one finding: ``changes`` to the ``element`` (its tag) at the finding's location.

    ``context_free`` fixes (a typo, a path) are the same wherever the element is expanded;
    the others (a fitted primitive, an inertia) depend on the link, so an element written once
    in a macro is only changed when every link expanded from it gets the same change.
    """

    applicability: Applicability
    title: str
    element: str
    changes: tuple[Change, ...]
    context_free: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {
            "applicability": self.applicability.value,
            "title": self.title,
            "element": self.element,
            "changes": [change.describe() for change in self.changes],
        }


@dataclass(frozen=True)
class Edit:
    """Replace characters ``start:end`` of source ``file`` (display path) by ``replacement``."""

    file: str
    start: int
    end: int
    replacement: str

    @property
    def span(self) -> tuple[str, int, int]:
        return (self.file, self.start, self.end)


@dataclass(frozen=True)
class PlannedFix:
    """A finding's fix made concrete: its ``edits``, or why it cannot be applied automatically.

    ``reason`` is empty for an applicable fix; ``locations`` names the places involved
    (``file:line``) when the fix is refused, so the user can apply it by hand.
    """

    code: str
    subject: str
    fingerprint: str
    fix: SuggestedFix
    edits: tuple[Edit, ...] = ()
    reason: str = ""
    locations: tuple[str, ...] = ()

    @property
    def applicable(self) -> bool:
        return not self.reason

    def refused(self, reason: str, *locations: str) -> PlannedFix:
        return PlannedFix(self.code, self.subject, self.fingerprint, self.fix, (), reason, tuple(locations))

    def to_dict(self) -> dict[str, Any]:
        return {
            "code": self.code,
            "subject": self.subject,
            "fingerprint": self.fingerprint,
            "applicability": self.fix.applicability.value,
            "title": self.fix.title,
            "applicable": self.applicable,
            "reason": self.reason or None,
            "locations": list(self.locations),
        }
