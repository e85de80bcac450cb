"""Where an attribute's value comes from in xacro source: literal text, a property, a macro
parameter or an expression, and who else uses a property."""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

from geomcheck.fix.xmltext import Element, SourceText

REFERENCE = re.compile(r"^\$\{\s*([A-Za-z_]\w*)\s*\}$")
EXPRESSION = re.compile(r"\$\{[^}]*\}")
IDENTIFIER = re.compile(r"[A-Za-z_]\w*")
PROPERTY_TAGS = ("property", "xacro:property")
MACRO_TAGS = ("macro", "xacro:macro")


def tokens(value: str) -> list[tuple[int, int]]:
    """Spans of the whitespace-separated parts of ``value``; ``${...}`` and ``$(...)`` stay whole."""
    out: list[tuple[int, int]] = []
    i, n = 0, len(value)
    while i < n:
        if value[i].isspace():
            i += 1
            continue
        start, depth = i, 0
        while i < n and (depth > 0 or not value[i].isspace()):
            if value.startswith(("${", "$("), i):
                depth += 1
                i += 2
                continue
            if value[i] in "})" and depth > 0:
                depth -= 1
            i += 1
        out.append((start, i))
    return out


def same_number(written: str, wanted: str) -> bool:
    """Whether two attribute components are the same value (``0.50`` and ``0.5``)."""
    try:
        return float(written) == float(wanted)
    except ValueError:
        return written == wanted


@dataclass(frozen=True)
class Use:
    """A ``${...}`` expression of ``file`` naming a property, span ``start``..``end``."""

    file: str
    start: int
    end: int
    line: int


@dataclass(frozen=True)
class Definition:
    file: str
    element: Element
    line: int


class XacroSources:
    """The description's source files, scanned once, for property look-ups."""

    def __init__(self, texts: Mapping[str, SourceText]) -> None:
        self.texts = texts

    def definitions(self, name: str) -> list[Definition]:
        out = []
        for file, source in self.texts.items():
            for element in source.elements:
                if element.name in PROPERTY_TAGS and (a := element.attribute("name")) is not None and a.value == name:
                    out.append(Definition(file, element, element.first_line))
        return out

    def uses(self, name: str) -> Iterator[Use]:
        for file, source in self.texts.items():
            for match in EXPRESSION.finditer(source.text):
                if name in IDENTIFIER.findall(match.group()[2:-1]):
                    yield Use(file, match.start(), match.end(), source.line_of(match.start()))


def macro_parameter(element: Element, name: str) -> Element | None:
    """The enclosing macro that declares parameter ``name`` (``*block``, ``x:=1``, ``^`` forms)."""
    for ancestor in element.ancestors():
        if ancestor.name not in MACRO_TAGS:
            continue
        params = ancestor.attribute("params")
        declared = {
            re.split(r":?=", p, maxsplit=1)[0].lstrip("*").rstrip("^|")
            for p in (params.value.split() if params else [])
        }
        if name in declared:
            return ancestor
    return None
