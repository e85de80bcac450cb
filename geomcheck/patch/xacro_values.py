"""Where an attribute's value comes from in xacro source: literal text, a property, a macro
parameter or an expression, and who else uses a property."""

from __future__ import annotations

import math
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

from geomcheck.patch.xmltext import Element, SourceText

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


SAME_RELATIVE = 1e-9  # xacro prints 0.45 computed as 0.45000000000000007: the same value
SAME_ABSOLUTE = 1e-12  # and 1e-17 where 0 was meant [m, rad, kg m^2]


def same_number(written: str, wanted: str) -> bool:
    """Whether two attribute components are the same value (``0.50`` and ``0.5``)."""
    try:
        return math.isclose(float(written), float(wanted), rel_tol=SAME_RELATIVE, abs_tol=SAME_ABSOLUTE)
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
        self._definitions: dict[str, list[Definition]] | None = None
        self._expressions: list[tuple[Use, frozenset[str]]] | None = None

    def definitions(self, name: str) -> list[Definition]:
        if self._definitions is None:
            self._definitions = {}
            for file, source in self.texts.items():
                for element in source.elements:
                    if element.name in PROPERTY_TAGS and (a := element.attribute("name")) is not None:
                        self._definitions.setdefault(a.value, []).append(Definition(file, element, element.first_line))
        return self._definitions.get(name, [])

    def uses(self, name: str) -> Iterator[Use]:
        if self._expressions is None:
            self._expressions = [
                (
                    Use(file, m.start(), m.end(), source.line_of(m.start())),
                    frozenset(IDENTIFIER.findall(m.group()[2:-1])),
                )
                for file, source in self.texts.items()
                for m in EXPRESSION.finditer(source.text)
            ]
        return (use for use, names in self._expressions if name in names)


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
