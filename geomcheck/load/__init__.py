"""Loading a description as ROS tools would: bundle, packages, xacro (modern and legacy),
hardened XML, URDF parsing into :mod:`geomcheck.model`, and meshes."""

from __future__ import annotations

from collections.abc import Mapping

from geomcheck.load.bundle import Bundle, make_bundle
from geomcheck.load.description import ExpandedDocument, LoadedDescription
from geomcheck.load.meshes import LoadedMesh, MeshProblem, MeshResult, MeshStore
from geomcheck.thresholds import LoadLimits


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
