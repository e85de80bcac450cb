"""The input formats geomcheck reads, and how a file's format is recognised.

Each loader declares what it reads (:class:`InputFormat`): the root elements of its documents
and the file name suffixes it is known by. A file is recognised by its content first, the
local name of its root element (``<robot>`` URDF/xacro, ``<mujoco>`` MJCF, ``<sdf>`` SDFormat), because suffixes
lie (MJCF and URDF are both ``.xml`` in the wild); the suffix decides only when the root
element cannot be read, and URDF/xacro is the fallback whose loader reports why a file is
not a robot description.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import PurePath
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from lxml import etree

    from geomcheck.load.bundle import Bundle
    from geomcheck.load.description import LoadedDescription
    from geomcheck.thresholds import LoadLimits

# bundle, xacro arguments, limits, the root file's bytes and its parsed root (None when the
# strict parse failed in a way the loader may still recover from, e.g. an undeclared xacro prefix)
LoadFunction = Callable[
    ["Bundle", Mapping[str, str], "LoadLimits", bytes, "etree._Element | None"], "LoadedDescription"
]


@dataclass(frozen=True)
class InputFormat:
    """One description format: ``name`` as reports and ``robots.toml`` say it, the local
    names of the root elements that identify its documents, its usual suffixes (lower case,
    with the dot) and the function that loads a bundle whose root file is in it."""

    name: str
    summary: str
    root_tags: tuple[str, ...]
    suffixes: tuple[str, ...]
    load: LoadFunction


_FORMATS: dict[str, InputFormat] = {}
FALLBACK = "urdf"  # what a document no format claims is read as: the URDF loader names the problem


def register(fmt: InputFormat) -> InputFormat:
    """Declare ``fmt``; a second declaration of a name replaces the first."""
    _FORMATS[fmt.name] = fmt
    return fmt


def _declared() -> dict[str, InputFormat]:
    """The formats declared so far: the loaders declare theirs when :mod:`geomcheck.load.loader`
    is imported (as :func:`geomcheck.load.load_description` does), which alone calls :func:`detect`."""
    return _FORMATS


def formats() -> tuple[InputFormat, ...]:
    """The declared formats in declaration order (import :mod:`geomcheck.load.loader` first)."""
    return tuple(_declared().values())


def root_tag(root: etree._Element | None) -> str | None:
    """Local name of ``root`` (namespace dropped), ``None`` when there is no element."""
    if root is None or not isinstance(root.tag, str):
        return None
    return root.tag.rpartition("}")[2]


def detect(root: etree._Element | None, filename: str) -> InputFormat:
    """The format of a document with root element ``root`` read from ``filename``: by root
    element when it is known, else by suffix, else the URDF/xacro fallback."""
    declared = _declared()
    tag = root_tag(root)
    if tag is not None:
        for fmt in declared.values():
            if tag in fmt.root_tags:
                return fmt
    # no root element, or one no format claims: the suffix names the format whose loader says
    # what is wrong (an ``.sdf`` file whose root is not <sdf> gets SDFormat's message)
    suffix = PurePath(filename).suffix.lower()
    for fmt in declared.values():
        if suffix in fmt.suffixes and fmt.name != FALLBACK:
            return fmt
    return declared[FALLBACK]
