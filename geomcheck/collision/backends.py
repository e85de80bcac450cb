"""The collision engines by name.

The one module that imports the engines' adapters (:mod:`coal_backend`, :mod:`fcl_backend`),
each only when it is asked for: the adapters import the interface (:mod:`base`) and nothing
imports back, so interface and adapters form no import circle.
"""

from __future__ import annotations

from geomcheck.collision.base import CollisionBackend
from geomcheck.errors import UsageError

BACKEND_NAMES = ("coal", "fcl")


def get_backend(name: str) -> CollisionBackend:
    """The backend called ``name`` (``coal`` or ``fcl``); :class:`UsageError` naming both otherwise."""
    if name == "coal":
        from geomcheck.collision.coal_backend import CoalBackend

        return CoalBackend()
    if name == "fcl":
        from geomcheck.collision.fcl_backend import FclBackend

        return FclBackend()
    raise UsageError.bad_choice("collision backend", name, BACKEND_NAMES)


__all__ = ["BACKEND_NAMES", "get_backend"]
