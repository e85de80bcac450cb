"""Checks: one module per rule family, each with ``run(ctx) -> FamilyResult``.

``FAMILY_MODULES`` is the order they run in. Families share typed products, computed once
when a selected rule first needs them, through ``ctx.analyses``
(:class:`geomcheck.checks.analyses.Analyses`: kinematics, collision scene, fits, matrix ...),
never each other's diagnostics.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from geomcheck.checks.analyses import Analyses
from geomcheck.diagnostics import Diagnostic, SkippedCheck
from geomcheck.load import LoadedDescription, MeshStore
from geomcheck.model import Robot
from geomcheck.options import CheckOptions, Selection
from geomcheck.thresholds import Thresholds


@dataclass(frozen=True)
class CheckContext:
    """Everything a check may look at; ``analyses`` are the products the families of one run share."""

    loaded: LoadedDescription
    meshes: MeshStore
    options: CheckOptions
    analyses: Analyses = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "analyses", Analyses(self.loaded, self.meshes, self.options))

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

FAMILY_MODULES: tuple[str, ...] = (
    "structure",
    "meshes",
    "fit",
    "inertia",
    "selfcollision",
    "motion",
    "matrix",
    "views",
    "scene",
)
# the rule codes each family reports (views report none: they draw what fit measures; the
# scene, what the 3D view draws, runs with any family that reads geometry)
FAMILY_RULE_PREFIXES: dict[str, tuple[str, ...]] = {
    "structure": ("GC1",),
    "meshes": ("GC2",),
    "fit": ("GC3",),
    "inertia": ("GC5",),
    "selfcollision": ("GC40",),
    "motion": ("GC42",),
    "matrix": ("GC41",),
    "views": ("GC3",),
    "scene": ("GC2", "GC3", "GC4", "GC5"),
}


def family_selected(name: str, selection: Selection) -> bool:
    """Whether ``selection`` keeps at least one rule that family ``name`` reports."""
    from geomcheck.rules import all_rules, matches

    prefixes = FAMILY_RULE_PREFIXES[name]
    return any(
        r.code.startswith(prefixes)
        and any(matches(r.code, s) for s in selection.select)
        and not any(matches(r.code, s) for s in selection.ignore)
        for r in all_rules()
    )


# the families that draw what the others measure (report sections only, no finding)
DRAWING_FAMILIES = ("views", "scene")


def family_names(selection: Selection | None = None, drawing: bool = True) -> tuple[str, ...]:
    """The names of the check families :func:`family_runners` runs, in running order, without
    importing them: a run counts its stages before loading, and a file that does not load never
    needs the families' libraries."""
    return tuple(
        name
        for name in FAMILY_MODULES
        if (selection is None or family_selected(name, selection)) and (drawing or name not in DRAWING_FAMILIES)
    )


def family_runners(selection: Selection | None = None, drawing: bool = True) -> tuple[tuple[str, FamilyRunner], ...]:
    """``(name, run)`` of every check family, in running order; with ``selection``, only the
    families whose rules it keeps (the others, and the libraries only they need, are not
    even imported); without ``drawing``, none of :data:`DRAWING_FAMILIES`."""
    return tuple(
        (name, importlib.import_module(f"geomcheck.checks.{name}").run) for name in family_names(selection, drawing)
    )


__all__ = [
    "DRAWING_FAMILIES",
    "FAMILY_MODULES",
    "FAMILY_RULE_PREFIXES",
    "CheckContext",
    "FamilyResult",
    "FamilyRunner",
    "family_names",
    "family_runners",
    "family_selected",
]
