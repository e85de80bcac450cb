"""Elements of an XML source file with the character spans of their tags and attributes.

Fixes edit the file's text, not a re-serialised tree, so that everything they do not touch
(comments, indentation, attribute order and quoting, number formatting) stays as written.
The files were parsed by the hardened parser when the description was loaded; this scanner
only needs to find spans in well-formed XML.
"""

from __future__ import annotations

import bisect
import re
from collections import defaultdict
from dataclasses import dataclass, field

NAME = r"[A-Za-z_][\w:.-]*"
_TOKEN = re.compile(
    rf"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|<!DOCTYPE[^>]*>|</\s*(?P<end>{NAME})\s*>"
    rf"|<(?P<start>{NAME})(?P<attrs>(?:\s+{NAME}\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(?P<close>/?)>",
    re.DOTALL,
)
_ATTRIBUTE = re.compile(rf"(?P<name>{NAME})\s*=\s*(?P<quote>[\"'])(?P<value>.*?)(?P=quote)", re.DOTALL)


@dataclass(frozen=True)
class Attribute:
    """``name="value"``: ``start``/``end`` span the whole attribute, ``value_start``/``value_end`` its value."""

    name: str
    value: str
    start: int
    end: int
    value_start: int
    value_end: int


@dataclass
class Element:
    """An element's tag ``name`` (``name_start``/``name_end`` in the start tag), start tag span
    ``start``..``open_end``, the end tag's name span (``None`` when self-closing), its
    attributes in written order, children, and the lines its start tag covers."""

    name: str
    start: int
    open_end: int
    name_start: int
    attributes: list[Attribute]
    first_line: int
    last_line: int
    parent: Element | None = None
    children: list[Element] = field(default_factory=list)
    end_name: tuple[int, int] | None = None
    end: int = 0

    def attribute(self, name: str) -> Attribute | None:
        return next((a for a in self.attributes if a.name == name), None)

    def child(self, tag: str) -> Element | None:
        return next((c for c in self.children if c.name == tag), None)

    @property
    def local_name(self) -> str:
        return self.name.split(":", 1)[-1]

    def ancestors(self) -> list[Element]:
        out, node = [], self.parent
        while node is not None:
            out.append(node)
            node = node.parent
        return out


class SourceText:
    """The elements of one file's ``text``, in document order."""

    def __init__(self, text: str) -> None:
        self.text = text
        self._newlines = [m.start() for m in re.finditer("\n", text)]
        self.elements: list[Element] = []
        self._by_line: defaultdict[int, list[Element]] | None = None
        stack: list[Element] = []
        for match in _TOKEN.finditer(text):
            if match.group("start"):
                element = self._element(match)
                element.parent = stack[-1] if stack else None
                if stack:
                    stack[-1].children.append(element)
                self.elements.append(element)
                if match.group("close"):
                    element.end = match.end()
                else:
                    stack.append(element)
            elif match.group("end") and stack:
                element = stack.pop()
                element.end_name = (match.start("end"), match.end("end"))
                element.end = match.end()

    def line_of(self, offset: int) -> int:
        """1-based line of character ``offset``."""
        return bisect.bisect_left(self._newlines, offset) + 1

    def _element(self, match: re.Match[str]) -> Element:
        attributes = [
            Attribute(
                a.group("name"),
                a.group("value"),
                match.start("attrs") + a.start(),
                match.start("attrs") + a.end(),
                match.start("attrs") + a.start("value"),
                match.start("attrs") + a.end("value"),
            )
            for a in _ATTRIBUTE.finditer(match.group("attrs"))
        ]
        return Element(
            name=match.group("start"),
            start=match.start(),
            open_end=match.end(),
            name_start=match.start("start"),
            attributes=attributes,
            first_line=self.line_of(match.start()),
            last_line=self.line_of(match.end() - 1),
        )

    def at_line(self, line: int, tag: str) -> Element | None:
        """The first ``tag`` element whose start tag covers ``line`` (lxml counts the line
        its start tag ends on, a hand-written line is usually the one it begins on)."""
        if self._by_line is None:
            self._by_line = defaultdict(list)
            for e in self.elements:
                for n in range(e.first_line, e.last_line + 1):
                    self._by_line[n].append(e)
        return next((e for e in self._by_line.get(line, ()) if e.name == tag), None)

    def indentation(self, offset: int) -> str:
        """The whitespace that begins the line holding ``offset``."""
        begin = self.text.rfind("\n", 0, offset) + 1
        end = begin
        while end < len(self.text) and self.text[end] in " \t":
            end += 1
        return self.text[begin:end]
