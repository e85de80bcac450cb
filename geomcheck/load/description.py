"""What loading a description yields: the expanded document and the robot model with the
load-time findings (one module below the loaders, so that they import it, not the package)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from geomcheck.diagnostics import Diagnostic
from geomcheck.load.bundle import Bundle
from geomcheck.model import Robot


@dataclass(frozen=True)
class ExpandedDocument:
    """The URDF text after xacro expansion (the file itself for plain URDF).

    ``sources`` maps the display path of every file read (root first, then includes in
    reading order) to its text, so excerpts can be shown without the files.
    """

    text: str
    root: str
    sources: Mapping[str, str]
    is_xacro: bool


@dataclass(frozen=True)
class LoadedDescription:
    bundle: Bundle
    robot: Robot
    document: ExpandedDocument
    diagnostics: tuple[Diagnostic, ...]


__all__ = ["ExpandedDocument", "LoadedDescription"]
