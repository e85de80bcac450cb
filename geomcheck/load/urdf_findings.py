"""Findings of one URDF parse: who they are about, where they stand, and one finding per
repeated mistake (a typo inside a xacro macro is one mistake however often it is expanded)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from lxml import etree

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load.locations import LocationResolver
from geomcheck.model import SourceLocation
from geomcheck.rules import Rule
from geomcheck.rules.structure import INVALID_NUMBER, MISSING_ATTRIBUTE, MISSING_ELEMENT, NUMBER_OUT_OF_RANGE

REFERENCE = "urdfdom"  # the parser a finding's ``accepted_by`` names when it loads the file as written
# findings of a link's elements that urdfdom answers by leaving the element out, not by
# refusing the robot (parseLink's failure is logged; the link is kept without the element)
LINK_PARSE_RULES = (INVALID_NUMBER, MISSING_ATTRIBUTE, MISSING_ELEMENT)


@dataclass(frozen=True)
class Subject:
    """Who a finding is about: a link, a joint, or the robot (both ``None``)."""

    link: str | None = None
    joint: str | None = None


MAX_QUOTED_CHARACTERS = 80  # an attribute value quoted in a message [characters]


def shorten(text: str) -> str:
    """``text`` cut to :data:`MAX_QUOTED_CHARACTERS` (a message never carries a whole hostile value)."""
    return text if len(text) <= MAX_QUOTED_CHARACTERS else f"{text[:MAX_QUOTED_CHARACTERS]}..."


def tag_of(element: etree._Element) -> str | None:
    """Local name of a core-candidate element; ``None`` for comments and namespaced extensions."""
    tag = element.tag
    if not isinstance(tag, str) or tag.startswith("{"):
        return None
    return tag


def _member_order(d: Diagnostic) -> tuple[str, str, str, int]:
    """Order of the members of a group of findings: by subject name, then place."""
    loc = d.location
    return (d.link or d.joint or "", d.about, loc.file if loc else "", (loc.line or 0) if loc else 0)


class UrdfFindings:
    """The findings of one parse of one document, in :attr:`diagnostics`, and the child and
    name lookups every element reader uses."""

    def __init__(self, root: etree._Element, resolver: LocationResolver) -> None:
        self.root = root
        self.resolver = resolver
        self.elements = [e for e in root.iter() if isinstance(e.tag, str)]
        self.index = {e: i for i, e in enumerate(self.elements)}
        self.diagnostics: list[Diagnostic] = []
        self.seen: dict[tuple[object, ...], int] = {}
        self.repeats: dict[int, list[Diagnostic]] = {}

    def location(self, element: etree._Element, name: str | None = None) -> SourceLocation:
        tag = tag_of(element) or "robot"
        return self.resolver.locate(self.index.get(element, -1), element.sourceline, tag, name)

    def report(
        self,
        rule: Rule,
        message: str,
        node: etree._Element,
        subject: Subject,
        about: str,
        severity: Severity | None = None,
        group: tuple[str, ...] | None = None,
        **data: Any,
    ) -> None:
        if rule in LINK_PARSE_RULES and subject.link is not None and severity is None:
            # urdfdom gives up on the element (a visual, a collision, an inertial) and keeps the
            # link and the robot: the element is missing in every consumer, the file loads
            message += "; urdfdom logs an error and loads the link without this element"
            data = {**data, "accepted_by": REFERENCE}
        elif rule is NUMBER_OUT_OF_RANGE:  # urdfdom never judges a magnitude
            if severity is None:
                message += "; urdfdom loads it as written, geomcheck does not use it"
            data = {**data, "accepted_by": REFERENCE}
        self.add(
            rule.diagnose(
                message,
                link=subject.link,
                joint=subject.joint,
                about=about,
                location=self.location(node),
                data=data,
                severity=severity,
            ),
            group,
        )

    def add(self, diagnostic: Diagnostic, group: tuple[str, ...] | None = None) -> None:
        """Keep ``diagnostic`` unless the same finding at the same source line (or, given a
        ``group``, the same kind of finding anywhere in the robot) was kept already.

        A typo inside a xacro macro is one mistake however often the macro is expanded: the
        first expansion is reported and names the other subjects. Extension markup that no
        consumer reads is one fact about the robot: one finding per kind, naming the others.
        """
        loc = diagnostic.location
        key: tuple[object, ...]
        if group is not None:
            key = (diagnostic.code, "robot-wide", *group)
        elif loc is None or loc.line is None:
            self.diagnostics.append(diagnostic)
            return
        else:
            key = (diagnostic.code, loc.file, loc.line, diagnostic.about, diagnostic.message)
        if key in self.seen:
            if diagnostic.link or diagnostic.joint:
                self.repeats.setdefault(self.seen[key], []).append(diagnostic)
            return
        self.seen[key] = len(self.diagnostics)
        self.diagnostics.append(diagnostic)

    def findings(self) -> list[Diagnostic]:
        """The diagnostics, each group of repeats as one finding: its member with the first
        subject name (not the first in document order, which reordering the file would
        change) naming the other subjects, sorted."""
        out = list(self.diagnostics)
        for index, others in self.repeats.items():
            members = [out[index], *others]
            d = min(members, key=_member_order)
            names = sorted({m.link or m.joint or "" for m in members if m is not d})
            listed = ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")
            out[index] = replace(d, message=f"{d.message} (also in {listed})", data={**d.data, "also": names})
        return out

    def children(self, element: etree._Element, tag: str) -> list[etree._Element]:
        return [c for c in element if tag_of(c) == tag]

    def child(self, element: etree._Element, tag: str) -> etree._Element | None:
        found = self.children(element, tag)
        return found[0] if found else None

    def name_of(self, element: etree._Element, subject: Subject, about: str) -> str:
        name = (element.get("name") or "").strip()
        if not name:
            kind = tag_of(element)
            self.report(MISSING_ATTRIBUTE, f"<{kind}> has no name", element, subject, f"{about}.name", element=kind)
        return name


__all__ = [
    "LINK_PARSE_RULES",
    "MAX_QUOTED_CHARACTERS",
    "REFERENCE",
    "Subject",
    "UrdfFindings",
    "shorten",
    "tag_of",
]
