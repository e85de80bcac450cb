"""What loading a description yields: the expanded document and the robot model with the
load-time findings (one module below the loaders, so that they import it, not the package)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from geomcheck.diagnostics import Diagnostic, SkippedCheck
from geomcheck.load.bundle import Bundle
from geomcheck.model import Robot

if TYPE_CHECKING:
    from geomcheck.load.srdf import Srdf


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
    format: str = "urdf"  # the name of its :class:`geomcheck.load.formats.InputFormat`
    # collision pairs the description itself turns off (MJCF <exclude> and contact bits,
    # SDFormat's <self_collide>), read like an SRDF's <disable_collisions> when no --srdf is
    # given; None for URDF, which has no such element
    declared_collision_filter: Srdf | None = None
    # elements the loader leaves out of every check (an SDFormat <polyline>, a <submesh>), and why
    skipped: tuple[SkippedCheck, ...] = ()


__all__ = ["ExpandedDocument", "LoadedDescription"]
