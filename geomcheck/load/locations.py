"""Source locations: where an element of the expanded document, or a xacro error, really is.

Elements keep the file and line they were read from (see :mod:`geomcheck.load.xacro_expand`);
what cannot be traced that way is found by searching the files read for a pattern, best
effort, and otherwise falls back to the root file without a line.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from geomcheck.model import SourceLocation


@dataclass(frozen=True)
class TextPosition:
    file: str
    line: int
    column: int


def position_of(text: str, offset: int) -> tuple[int, int]:
    """1-based (line, column) of character ``offset`` in ``text``."""
    line = text.count("\n", 0, offset) + 1
    column = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return line, column


def search_sources(
    sources: Mapping[str, str], patterns: Iterable[re.Pattern[str]], files: Iterable[str] = ()
) -> TextPosition | None:
    """First match of the first pattern that matches, trying ``files`` in order and then every source."""
    order = list(dict.fromkeys([*(f for f in files if f in sources), *sources]))
    for pattern in patterns:
        for name in order:
            match = pattern.search(sources[name])
            if match is not None:
                line, column = position_of(sources[name], match.start())
                return TextPosition(name, line, column)
    return None


def element_pattern(tag: str, name: str | None) -> re.Pattern[str]:
    """Opening tag ``<tag ... name="name"`` (any quoting, other attributes first)."""
    if name is None:
        return re.compile(rf"<{re.escape(tag)}[\s/>]")
    return re.compile(rf"<{re.escape(tag)}\s[^>]*?\bname\s*=\s*([\"']){re.escape(name)}\1")


class LocationResolver:
    """Maps elements of the expanded document to :class:`SourceLocation`.

    ``origins`` holds, per element in document order, the ``(file, line)`` the element was
    read from, or ``None`` when xacro created it; ``None`` for the whole list when the
    document is the root file itself (plain URDF: the line is the expanded line).
    """

    def __init__(
        self,
        root: str,
        sources: Mapping[str, str],
        origins: list[tuple[str, int] | None] | None,
    ) -> None:
        self.root = root
        self.sources = sources
        self.origins = origins

    def locate(self, index: int, expanded_line: int | None, tag: str, name: str | None) -> SourceLocation:
        """Location of the ``index``-th element (document order) of the expanded document."""
        if self.origins is None:
            return SourceLocation(self.root, expanded_line, None, expanded_line)
        origin = self.origins[index] if index < len(self.origins) else None
        if origin is not None:
            return SourceLocation(origin[0], origin[1], None, expanded_line)
        if name:
            found = search_sources(self.sources, [element_pattern(tag, name)])
            if found is not None:
                return SourceLocation(found.file, found.line, found.column, expanded_line)
        return SourceLocation(self.root, None, None, expanded_line)
