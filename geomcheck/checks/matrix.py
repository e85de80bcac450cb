"""Checks of this family (not yet implemented: returns no findings)."""

from __future__ import annotations

from geomcheck.checks import CheckContext, FamilyResult


def run(ctx: CheckContext) -> FamilyResult:
    return FamilyResult()
