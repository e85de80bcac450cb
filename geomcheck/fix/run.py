"""One fix run: check the description, plan the fixes of its findings, compute the new text."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

from geomcheck.diagnostics import Diagnostic
from geomcheck.fix.apply import fixed_sources, source_path, unified_diff, write_sources
from geomcheck.fix.model import PlannedFix
from geomcheck.fix.plan import FixPlan, plan_fixes
from geomcheck.load import Bundle, LoadedDescription, load_description
from geomcheck.options import CheckOptions
from geomcheck.report.model import Report


@dataclass(frozen=True)
class FixResult:
    """The ``report`` the fixes come from, their ``plan``, and the text of each changed file
    ``before`` and ``after`` (display paths)."""

    loaded: LoadedDescription
    report: Report
    plan: FixPlan
    before: Mapping[str, str]
    after: Mapping[str, str]
    unsafe: bool = False

    @property
    def diff(self) -> str:
        """Unified diff of every changed file (empty when nothing changes)."""
        return unified_diff(self.before, self.after)

    def write(self) -> None:
        """Write the changed files (:class:`geomcheck.errors.InputError` if one changed meanwhile)."""
        write_sources(self.loaded.bundle, self.before, self.after)


def fix_loaded(loaded: LoadedDescription, report: Report, unsafe: bool = False) -> FixResult:
    """The fixes of ``report``'s findings (selection and configuration already applied) on ``loaded``."""
    plan = plan_fixes(loaded, report.diagnostics, unsafe)
    after = fixed_sources(loaded.document.sources, plan.edits)
    before = {file: loaded.document.sources[file] for file in after}
    return FixResult(loaded, report, plan, before, after, unsafe)


def fix_bundle(bundle: Bundle, options: CheckOptions, unsafe: bool = False) -> FixResult:
    """Load and check ``bundle``, then plan its fixes; nothing is written."""
    from geomcheck.pipeline import check_loaded

    loaded = load_description(bundle, options.args, options.thresholds.limits)
    return fix_loaded(loaded, check_loaded(loaded, options), unsafe)


MAX_ROUNDS = 3  # a fix that does not settle its finding is withdrawn; each round withdraws at least one
UNSETTLED = "applied, the check still reports the finding: withdrawn"


@dataclass(frozen=True)
class Applied:
    """What :func:`apply_verified` did: the final ``plan`` (withdrawn fixes refused), the
    reports ``before`` and ``after`` the files were written, and the files ``written``."""

    plan: FixPlan
    before: Report
    after: Report
    written: tuple[Path, ...]

    @property
    def added(self) -> list[Diagnostic]:
        """Findings the fixes brought: reported after, not before."""
        known = {d.fingerprint for d in self.before.diagnostics}
        return [d for d in self.after.diagnostics if d.fingerprint not in known]


def apply_verified(result: FixResult, options: CheckOptions) -> Applied:
    """Write ``result``'s fixes, check again, and withdraw (rewriting the files) every fix
    whose finding is still reported: a fix is kept only when it settles its finding."""
    from geomcheck.pipeline import run_check

    loaded, sources = result.loaded, result.loaded.document.sources
    result.write()
    touched = set(result.after)
    plan, withdrawn = result.plan, set[str]()
    after = run_check(loaded.bundle, options)
    for _ in range(MAX_ROUNDS):
        remaining = {d.fingerprint for d in after.diagnostics}
        unsettled = {p.fingerprint for p in plan.applied} & remaining
        if not unsettled:
            break
        withdrawn |= unsettled
        kept = [d for d in result.report.diagnostics if d.fingerprint not in withdrawn]
        plan = plan_fixes(loaded, kept, result.unsafe)
        texts = fixed_sources(sources, plan.edits)
        for file in touched:
            source_path(loaded.bundle, file).write_bytes(texts.get(file, sources[file]).encode("utf-8"))
        touched |= set(texts)
        after = run_check(loaded.bundle, options)
    refused = [p.refused(UNSETTLED, *p.locations) for p in result.plan.fixes if p.fingerprint in withdrawn]
    final = replace(plan, fixes=tuple(sorted((*plan.fixes, *refused), key=_order(result.report))))
    changed = {
        f for f in touched if source_path(loaded.bundle, f).read_bytes().decode("utf-8", "replace") != sources[f]
    }
    return Applied(final, result.report, after, tuple(sorted(source_path(loaded.bundle, f) for f in changed)))


def _order(report: Report) -> Callable[[PlannedFix], int]:
    rank = {d.fingerprint: i for i, d in enumerate(report.diagnostics)}
    return lambda p: rank.get(p.fingerprint, len(rank))
