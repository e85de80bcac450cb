"""Fixes as data.

A :class:`SuggestedFix` says what a finding's fix changes in the element the finding points
at, independently of how that element is written (plain URDF, a xacro macro, values from
properties). Planning (:mod:`geomcheck.patch.plan`) turns it into :class:`Edit` s: byte spans
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
    the namespace declared): :mod:`geomcheck.patch.modernise`."""

    file: str

    def describe(self) -> str:
        return f"modernise the xacro syntax of {self.file}"


@dataclass(frozen=True)
class RemoveAttribute:
    """Remove ``attribute`` from the element reached by ``path`` when it is written there (an
    MJCF geom's ``fromto`` once ``pos``, ``quat`` and ``size`` place it)."""

    path: tuple[str, ...]
    attribute: str

    def describe(self) -> str:
        where = "/".join(self.path) or "element"
        return f"{where} without {self.attribute}"


@dataclass(frozen=True)
class SetText:
    """Set the text of the element reached by ``path`` to ``text`` (SDFormat writes values as
    element text: ``<size>0.1 0.2 0.3</size>``); missing elements of ``path`` are created."""

    path: tuple[str, ...]
    text: str
    keep_leading: int = 0  # the written text's first values kept before ``text`` (a pose's x y z)

    def describe(self) -> str:
        tag = self.path[-1]
        return f"{'/'.join(self.path[:-1]) + '/' if len(self.path) > 1 else ''}<{tag}>{self.text}</{tag}>"


@dataclass(frozen=True)
class SetPose:
    """Set the SDFormat ``<pose>`` child of the element to ``xyz`` and ``rpy`` [m, rad] in the
    frame of the link holding it (the planner states ``relative_to`` when the pose named
    another frame, and drops ``degrees`` and ``rotation_format``)."""

    xyz: str | None  # None: the position as written
    rpy: str

    def describe(self) -> str:
        if self.xyz is None:
            return f"<pose> angles {self.rpy} in the link frame, its position kept"
        return f"<pose>{self.xyz} {self.rpy}</pose> in the link frame"


@dataclass(frozen=True)
class SetInertia:
    """Set an MJCF ``<inertial>``'s tensor to ``tensor`` (``ixx ixy ixz iyy iyz izz``
    [kg m^2]), given in the axes of the inertial frame MuJoCo compiled (its principal axes):
    the planner writes it in what the element already uses (``fullinertia`` in the body's axes,
    or ``diaginertia`` with the ``quat`` of its principal axes)."""

    tensor: tuple[float, float, float, float, float, float]

    def describe(self) -> str:
        values = " ".join(
            f"{k}={v:.6g}" for k, v in zip(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), self.tensor, strict=True)
        )
        return f"inertial tensor {values} (in MuJoCo's compiled inertial axes) as fullinertia or diaginertia+quat"


Change = (
    SetAttribute
    | RenameAttribute
    | RenameElement
    | ReplaceElement
    | ModerniseXacro
    | RemoveAttribute
    | SetText
    | SetPose
    | SetInertia
)


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
    syntax: str = "urdf"  # the format the changes are written in: urdf (and xacro), mjcf, sdf

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "applicability": self.applicability.value,
            "title": self.title,
            "element": self.element,
            "changes": [change.describe() for change in self.changes],
        }
        if self.syntax != "urdf":  # additive: URDF fixes are written as before
            out["syntax"] = self.syntax
        return out


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


class Refused(Exception):
    """A fix that cannot be applied automatically: ``reason`` and the places involved."""

    def __init__(self, reason: str, *locations: str) -> None:
        super().__init__(reason)
        self.reason = reason
        self.locations = locations


def place(file: str, line: int) -> str:
    return f"{file}:{line}"
