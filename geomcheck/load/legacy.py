"""Legacy xacro syntax: bare ``<property>``, ``<include>``, ``<macro>``... and a missing ``xmlns:xacro``.

Descriptions written before xacro required the ``xacro:`` prefix (the 2009 PR2 is the real
case) are rewritten in memory to the modern form before expansion; the user's files are
never touched. :func:`legacy_tag` decides, per element, whether a bare tag is a xacro
instruction (mirroring the rules ROS 1 xacro applied when it still accepted them);
:class:`LegacyUse` collects what one file used, for its GC103 finding.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Set
from dataclasses import dataclass, field

from lxml import etree

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.model import SourceLocation
from geomcheck.rules.structure import LEGACY_XACRO, XACRO_NS

ACCEPTED_XACRO_URIS = frozenset({XACRO_NS, "http://ros.org/wiki/xacro", "http://wiki.ros.org/xacro"})

# Bare tag -> attribute that a xacro instruction of that name must carry.
LEGACY_TAGS: dict[str, str] = {
    "property": "name",
    "include": "filename",
    "macro": "name",
    "insert_block": "name",
    "arg": "name",
    "if": "value",
    "unless": "value",
    "call": "macro",
}

MACRO_CALL = "macro call"
# xacro parses with xml.dom.minidom (expat, namespace-aware): a xacro: prefix without its
# declaration is an "unbound prefix" error there; geomcheck declares it in memory and goes on
UNBOUND_PREFIX_NOTE = "xacro: prefix used without an xmlns:xacro declaration"

_ROOT_START_TAG = re.compile(rb"<(?![?!])([A-Za-z_][\w.\-]*(?::[\w.\-]+)?)")


def legacy_tag(element: etree._Element) -> str | None:
    """The bare xacro instruction ``element`` is (``"include"``...), or ``None``.

    A bare ``<include>`` with element children is not xacro (Gazebo's ``<include><uri>``),
    as ROS 1 xacro decided; every other tag needs its defining attribute.
    """
    if not isinstance(element.tag, str) or element.prefix is not None or element.tag.startswith("{"):
        return None
    name = element.tag
    required = LEGACY_TAGS.get(name)
    if required is None or element.get(required) is None:
        return None
    if name == "include" and len(element) > 0:
        return None
    return name


@dataclass
class LegacyUse:
    """What legacy syntax one file uses: tag counts, the first line, namespace problems."""

    display: str
    identity: str  # see Bundle.identity: stable across working folders and checkouts
    tags: Counter[str] = field(default_factory=Counter)
    first_line: int | None = None
    namespace_note: str | None = None
    # the macros holding legacy tags, and how many tags lie outside any macro
    macros: set[str] = field(default_factory=set)
    outside_macros: int = 0

    def add(self, tag: str, line: int | None, macro: str | None = None) -> None:
        """Count ``tag`` (at ``line``), written inside the definition of ``macro`` if named."""
        self.tags[tag] += 1
        if macro is None:
            self.outside_macros += 1
        else:
            self.macros.add(macro)
        if line is not None and (self.first_line is None or line < self.first_line):
            self.first_line = line

    def unused(self, called: Set[str]) -> list[str]:
        """The macros holding every legacy tag of the file when none of them is ``called``
        (the tags then never reach this robot's expansion); ``[]`` otherwise."""
        if not self.tags or self.outside_macros or self.macros & called:
            return []
        return sorted(self.macros)

    @property
    def found(self) -> bool:
        return bool(self.tags) or self.namespace_note is not None

    def describe(self) -> str:
        """``<property> x27, <include> x2; no xmlns:xacro declaration``."""
        parts = []
        for tag, count in sorted(self.tags.items(), key=lambda item: (item[0] == MACRO_CALL, -item[1], item[0])):
            label = "bare macro calls" if tag == MACRO_CALL else f"<{tag}>"
            parts.append(f"{label} x{count}")
        text = ", ".join(parts)
        if self.namespace_note:
            text = f"{text}; {self.namespace_note}" if text else self.namespace_note
        return text

    def severity(self, called: Set[str] = frozenset()) -> Severity:
        """By what xacro does with the file. It recognises its instructions by the ``xacro:``
        prefix of the tag name, never by the namespace URI, so a wrong URI on a file that
        expands is dead markup (info). Bare tags were accepted by ROS 1 xacro with a
        deprecation warning and are copied unexpanded by ROS 2 xacro (warning). A prefix
        without its declaration makes xacro's XML parser refuse the file (error). Bare tags
        only inside macros this robot never calls do not reach its expansion (info)."""
        if self.namespace_note == UNBOUND_PREFIX_NOTE:
            return Severity.ERROR
        return Severity.WARNING if self.tags and not self.unused(called) else Severity.INFO

    def diagnostic(self, called: Set[str] = frozenset()) -> Diagnostic:
        """The GC103 finding for this file, at its first legacy tag; ``called`` names the
        macros the expansion called."""
        fixes = []
        if self.tags:
            tags = sorted(t for t in self.tags if t != MACRO_CALL)
            if tags:
                fixes.append("prefix " + ", ".join(f"<{t}>" for t in tags) + " with xacro:")
            if MACRO_CALL in self.tags:
                fixes.append("call macros as <xacro:NAME>")
        fixes.append(f'declare xmlns:xacro="{XACRO_NS}" on the root element')
        if self.tags or self.namespace_note == UNBOUND_PREFIX_NOTE:
            because = " (geomcheck rewrote them in memory; current xacro does not)"
        else:
            because = " (xacro matches its tags by the xacro: prefix, not the URI: the file expands as it is)"
        unused = self.unused(called)
        only = f" (only in macros this robot does not call: {', '.join(unused)})" if unused else ""
        return LEGACY_XACRO.diagnose(
            f"legacy xacro syntax in {self.display}: {self.describe()}{only}",
            help="; ".join(fixes) + because,
            about=self.identity,
            location=SourceLocation(self.display, self.first_line),
            data={"file": self.display, "tags": dict(sorted(self.tags.items())), "namespace": self.namespace_note},
            severity=self.severity(called),
        )


def enclosing_macro(element: etree._Element) -> str | None:
    """The name of the xacro macro whose definition holds ``element`` (innermost), or ``None``."""
    for parent in element.iterancestors():
        if not isinstance(parent.tag, str):
            continue
        local = etree.QName(parent).localname
        if local == "macro" and (parent.prefix == "xacro" or legacy_tag(parent) == "macro"):
            return parent.get("name")
    return None


def namespace_problem(root: etree._Element) -> str | None:
    """A note when the ``xacro`` prefix is bound to a URI other than xacro's, else ``None``."""
    uri = root.nsmap.get("xacro")
    if uri is not None and uri not in ACCEPTED_XACRO_URIS:
        return f"xmlns:xacro is bound to {uri!r} instead of {XACRO_NS!r}"
    return None


def declare_xacro_namespace(data: bytes) -> bytes | None:
    """``data`` with ``xmlns:xacro`` declared on its root start tag (same lines), or ``None``."""
    match = _ROOT_START_TAG.search(_skip_prolog(data))
    if match is None:
        return None
    offset = len(data) - len(_skip_prolog(data)) + match.end()
    return data[:offset] + f' xmlns:xacro="{XACRO_NS}"'.encode() + data[offset:]


def _skip_prolog(data: bytes) -> bytes:
    """``data`` from the first element start tag on (after declaration, comments, DOCTYPE)."""
    position = 0
    while True:
        start = data.find(b"<", position)
        if start < 0:
            return b""
        if data.startswith(b"<!--", start):
            end = data.find(b"-->", start)
            position = len(data) if end < 0 else end + 3
        elif data.startswith(b"<?", start) or data.startswith(b"<!", start):
            end = data.find(b">", start)
            position = len(data) if end < 0 else end + 1
        else:
            return data[start:]


def uses_xacro(root: etree._Element, filename: str) -> bool:
    """Whether a document is xacro: ``.xacro`` name, a ``xacro`` namespace, or any xacro/legacy tag."""
    if filename.endswith(".xacro") or "xacro" in root.nsmap:
        return True
    return any(e.prefix == "xacro" or legacy_tag(e) is not None for e in root.iter(tag=etree.Element))
