"""The fixes a service offers as patches: verified exactly as ``geomcheck fix`` verifies its
edits (:mod:`geomcheck.fix.verify`), so a patch that would add a finding is never offered.

A check's report plans its fixes (``fixes`` section: each fixable finding's fix, and the
planned patches); where the patches are offered for download (the HTTP service, its web
page) they are replaced by the verified ones: the safe fixes, and all of them, each applied
to a scratch copy and checked again against every rule family in rounds.
"""

from __future__ import annotations

from typing import Any

import geomcheck.progress as progress
from geomcheck.fix.run import fix_loaded
from geomcheck.fix.verify import Verified, verify
from geomcheck.load import LoadedDescription
from geomcheck.options import CheckOptions
from geomcheck.patch.section import FIXES_SECTION
from geomcheck.report.model import Report


def _patch(verified: Verified) -> str:
    """The verified diff; empty when, applied, it would still add a finding (never offered)."""
    return "" if verified.added or not verified.verified else verified.diff


def verified_fixes(loaded: LoadedDescription, report: Report, options: CheckOptions) -> dict[str, Any] | None:
    """``report``'s ``fixes`` section with verified patches (``safe_patch``, ``unsafe_patch``),
    the fixes each applies and those verification withdrew (with why); ``None`` when the
    report has no fix."""
    planned = report.sections.get(FIXES_SECTION)
    if not isinstance(planned, dict):
        return None
    progress.stage("verifying safe fixes", 0, 2)
    safe = verify(fix_loaded(loaded, report, unsafe=False), options)
    progress.stage("verifying all fixes", 1, 2)
    every = verify(fix_loaded(loaded, report, unsafe=True), options)
    unsafe_patch = _patch(every)
    # a fix verification refitted (boxes clear of the links the fitted primitive would hit)
    # is listed as applied, with its title saying why it differs from the finding's help
    applied = {p.fingerprint: p.to_dict() for p in every.applied} if unsafe_patch else {}
    fixes = [applied.get(f.get("fingerprint"), f) for f in planned.get("fixes", [])]
    return {
        **planned,
        "fixes": fixes,
        "verified": True,
        "safe_patch": _patch(safe),
        "unsafe_patch": unsafe_patch,
        "applied": [p.fingerprint for p in every.applied] if unsafe_patch else [],
        "withdrawn": [{"fingerprint": p.fingerprint, "reason": p.reason} for p in every.refused],
    }


__all__ = ["verified_fixes"]
