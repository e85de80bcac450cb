"""The ``fixes`` report section: each fixable finding's planned fix and the patches, made
when a report is built (the planner scans text: no geometry, no check run)."""

from __future__ import annotations

from collections.abc import Sequence

from geomcheck.diagnostics import Diagnostic
from geomcheck.fixes.model import Edit
from geomcheck.load import LoadedDescription
from geomcheck.patch.apply import fixed_sources, unified_diff
from geomcheck.patch.plan import plan_fixes
from geomcheck.patch.planner import Planner

FIXES_SECTION = "fixes"
FIX_SYNTAXES = ("urdf", "mjcf", "sdf")  # the formats whose files fixes write (loaded.format)


def fixes_section(loaded: LoadedDescription, diagnostics: Sequence[Diagnostic]) -> dict[str, object] | None:
    """The ``fixes`` report section: each fixable finding's planned fix, and the unified diffs
    of the safe fixes and of all of them (display paths; planned, not verified as
    ``geomcheck fix`` verifies them). ``None`` when no finding has a fix."""
    planner = Planner(loaded)
    safe = plan_fixes(loaded, diagnostics, unsafe=False, planner=planner)
    every = plan_fixes(loaded, diagnostics, unsafe=True, planner=planner)
    if not every.fixes:
        return None
    sources = planner.sources

    def patch(edits: Sequence[Edit]) -> str:
        after = fixed_sources(sources, edits)
        return unified_diff({f: sources[f] for f in after}, after)

    return {
        "fixes": [p.to_dict() for p in every.fixes],
        "safe_patch": patch(safe.edits),
        "unsafe_patch": patch(every.edits),
    }


__all__ = ["FIXES_SECTION", "FIX_SYNTAXES", "fixes_section"]
