"""Checks: one module per rule family, each with ``run(ctx) -> FamilyResult``.

``FAMILY_RUNNERS`` is the order they run in; a family may read what an earlier one left in
``ctx.cache`` (for example fitted meshes or collision objects) but never its diagnostics.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from geomcheck.diagnostics import Diagnostic, SkippedCheck
from geomcheck.load import LoadedDescription, MeshStore
from geomcheck.model import Robot
from geomcheck.options import CheckOptions
from geomcheck.thresholds import Thresholds


@dataclass(frozen=True)
class CheckContext:
    """Everything a check may look at. ``cache`` is shared between families of one run."""

    loaded: LoadedDescription
    meshes: MeshStore
    options: CheckOptions
    cache: dict[str, Any] = field(default_factory=dict)

    @property
    def robot(self) -> Robot:
        return self.loaded.robot

    @property
    def thresholds(self) -> Thresholds:
        return self.options.thresholds


@dataclass
class FamilyResult:
    """What one family found: diagnostics, JSON-ready report ``sections`` and skipped checks."""

    diagnostics: list[Diagnostic] = field(default_factory=list)
    sections: dict[str, Any] = field(default_factory=dict)
    skipped: list[SkippedCheck] = field(default_factory=list)


FamilyRunner = Callable[[CheckContext], FamilyResult]

FAMILY_MODULES: tuple[str, ...] = ("structure", "meshes", "fit", "inertia", "selfcollision", "matrix", "views")


def family_runners() -> tuple[tuple[str, FamilyRunner], ...]:
    """``(name, run)`` of every check family, in running order."""
    out = []
    for name in FAMILY_MODULES:
        module = importlib.import_module(f"geomcheck.checks.{name}")
        out.append((name, module.run))
    return tuple(out)
