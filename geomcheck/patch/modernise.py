"""The edits that modernise a file's pre-2013 xacro syntax (GC103's safe fix): bare xacro
instructions get their ``xacro:`` prefix (``<property>`` -> ``<xacro:property>``, end tags
too), bare macro calls become ``<xacro:NAME>``, and the root declares xacro's namespace
(or its wrong URI is corrected).

The expansion is unchanged: these are the tags geomcheck's loader (and ROS 1 xacro) already
read as xacro instructions (:func:`geomcheck.load.legacy.legacy_tag`'s rules: a bare tag with
the attribute its instruction needs; a bare ``<include>`` with element children is Gazebo's,
not xacro's), and only the spelling changes.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

from geomcheck.fixes.model import Edit
from geomcheck.load.legacy import ACCEPTED_XACRO_URIS, LEGACY_TAGS, XACRO_NS
from geomcheck.patch.xmltext import Element, SourceText

_MACRO_NAME = re.compile(r"<(?:xacro:)?macro\s+[^>]*?\bname\s*=\s*[\"']([^\"']+)[\"']")


def macro_names(sources: Iterable[str]) -> set[str]:
    """Names of the macros the description's files define (bare or prefixed)."""
    return {m.group(1) for text in sources for m in _MACRO_NAME.finditer(text)}


def _is_legacy(element: Element, macros: set[str]) -> bool:
    if ":" in element.name:
        return False
    required = LEGACY_TAGS.get(element.name)
    if required is not None:
        if element.attribute(required) is None:
            return False
        return not (element.name == "include" and element.children)
    return element.name in macros and not any(a.name == "xmlns" for a in element.attributes)


def _prefixed(file: str, element: Element) -> list[Edit]:
    edits = [Edit(file, element.name_start, element.name_start, "xacro:")]
    if element.end_name is not None:
        edits.append(Edit(file, element.end_name[0], element.end_name[0], "xacro:"))
    return edits


def _namespace(file: str, root: Element) -> list[Edit]:
    declared = root.attribute("xmlns:xacro")
    if declared is None:
        end = root.name_start + len(root.name)
        return [Edit(file, end, end, f' xmlns:xacro="{XACRO_NS}"')]
    if declared.value not in ACCEPTED_XACRO_URIS:
        return [Edit(file, declared.value_start, declared.value_end, XACRO_NS)]
    return []


def modernising_edits(file: str, text: str, sources: Mapping[str, str]) -> list[Edit]:
    """The edits that modernise ``file`` (its ``text``), macro names from every file of ``sources``."""
    source = SourceText(text)
    if not source.elements:
        return []
    macros = macro_names(sources.values()) - set(LEGACY_TAGS)
    edits = [e for element in source.elements if _is_legacy(element, macros) for e in _prefixed(file, element)]
    return edits + _namespace(file, source.elements[0])


__all__ = ["macro_names", "modernising_edits"]
