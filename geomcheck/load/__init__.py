"""Loading a description as ROS tools would: bundle, packages, xacro (modern and legacy),
hardened XML, URDF parsing into :mod:`geomcheck.model`, and meshes."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from geomcheck.diagnostics import Diagnostic
from geomcheck.load.bundle import Bundle, make_bundle
from geomcheck.load.meshes import LoadedMesh, MeshProblem, MeshResult, MeshStore
from geomcheck.model import Robot
from geomcheck.thresholds import LoadLimits

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
    # collision pairs the description itself turns off (MJCF <exclude>), read like an SRDF's
    # <disable_collisions> when no --srdf is given; None for URDF, which has no such element
    declared_collision_filter: Srdf | None = None


def load_description(
    bundle: Bundle,
    args: Mapping[str, str] | None = None,
    limits: LoadLimits | None = None,
) -> LoadedDescription:
    """Read, expand and parse the bundle's root file.

    Raises :class:`geomcheck.errors.InputError` when the description cannot be read at all
    (missing file, malformed XML, xacro failure, limits); every other problem is a
    diagnostic in the result.
    """
    from geomcheck.load.loader import load

    return load(bundle, dict(args or {}), limits or LoadLimits())


__all__ = [
    "Bundle",
    "ExpandedDocument",
    "LoadedDescription",
    "LoadedMesh",
    "MeshProblem",
    "MeshResult",
    "MeshStore",
    "load_description",
    "make_bundle",
]
