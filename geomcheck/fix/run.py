"""One fix run: check the description, plan the fixes of its findings, compute the new text."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from geomcheck.load import Bundle, LoadedDescription
from geomcheck.options import CheckOptions
from geomcheck.patch.apply import fixed_sources, unified_diff, write_sources
from geomcheck.patch.plan import FixPlan, plan_fixes
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
    after = fixed_sources(plan.sources, plan.edits)
    before = {file: plan.sources[file] for file in after}
    return FixResult(loaded, report, plan, before, after, unsafe)


def fix_bundle(bundle: Bundle, options: CheckOptions, unsafe: bool = False) -> FixResult:
    """Load and check ``bundle``, then plan its fixes; nothing is written."""
    from geomcheck.pipeline import load_and_check

    loaded, report = load_and_check(bundle, options)
    return fix_loaded(loaded, report, unsafe)
