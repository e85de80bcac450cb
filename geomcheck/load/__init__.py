"""Loading a description as ROS tools would: bundle, packages, xacro (modern and legacy),
hardened XML, URDF parsing into :mod:`geomcheck.model`, and meshes."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from geomcheck.load.bundle import Bundle, make_bundle
from geomcheck.thresholds import LoadLimits

if TYPE_CHECKING:
    from geomcheck.load.description import ExpandedDocument, LoadedDescription
    from geomcheck.load.meshes import LoadedMesh, MeshProblem, MeshResult, MeshStore, mesh_formats

# what needs numpy and the mesh readers is imported on first use: making a bundle (the CLI's
# cached check) costs no numpy
_LAZY = {
    "ExpandedDocument": "geomcheck.load.description",
    "LoadedDescription": "geomcheck.load.description",
    "LoadedMesh": "geomcheck.load.meshes",
    "MeshProblem": "geomcheck.load.meshes",
    "MeshResult": "geomcheck.load.meshes",
    "MeshStore": "geomcheck.load.meshes",
    "mesh_formats": "geomcheck.load.meshes",
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


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
    "mesh_formats",
]
