"""Verifying fixes before they reach the user's files: applied to a scratch copy of the
description's folder and checked again, in rounds.

A round's fixes are kept when each settles its finding and, for unsafe fixes, brings no new
fit or inertia finding about its own link (a shrunk sphere the link's inertia no longer fits
in) and, for collision fixes, no new self-collision finding with another link; otherwise the
round is undone and planned again, a colliding collision fix refitted clear of the links it
hits (:mod:`geomcheck.fix.clear`) once, and the other offending fixes withdrawn. The next round fixes what the
check reports then (a finding a fixed mesh path lets the fit check see), and tries the fixes
withdrawn so far again, judged against the fixed description, as a new run of fix would: the
rounds stop when a round changes nothing, so the outcome is a fixed point (fixing it again
changes nothing; bounded by :func:`rounds_bound`, and when the bound is reached no fix is
applied, so that the outcome is a fixed point on any input). ``--diff`` and the written files
are the outcome of the same verification. A fix is never written unchecked: when the
description's folder is too large to copy, every fix is refused, saying why.
"""

from __future__ import annotations

import tempfile
from collections import Counter
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

import geomcheck.progress as progress
from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError
from geomcheck.fix.clear import clear_fit
from geomcheck.fix.run import FixResult
from geomcheck.fix.scratch import MAX_SCRATCH_BYTES, MAX_SCRATCH_FILES, Scratch, description_folder, small_enough
from geomcheck.fixes.model import Applicability, PlannedFix, SuggestedFix
from geomcheck.load import LoadedDescription, load_description
from geomcheck.options import CheckOptions, Selection
from geomcheck.patch.apply import fixed_sources, unified_diff
from geomcheck.patch.plan import FixPlan, plan_fixes
from geomcheck.report.model import Report

MAX_ROUNDS = 12  # fix, check, fix what is left or was revealed, try the withdrawn again: ruff's loop, bounded
ROUNDS_PER_FIX = 3  # ... and more for many fixes: each round keeps, withdraws or refits at least one [rounds]
MOST_ROUNDS = 200  # whatever the number of fixes [rounds]
UNSETTLED = "the check still reports the finding once the fix is applied: withdrawn"
TOO_LARGE = (
    f"the description's folder is too large to copy and check the fix in (more than {MAX_SCRATCH_FILES} files or "
    f"{MAX_SCRATCH_BYTES >> 20} MiB): not applied unchecked"
)


@dataclass(frozen=True)
class Verified:
    """The outcome of :func:`verify`: every fix applied or refused (report order), the reports
    ``before`` and ``after`` (of the scratch copy: compare fingerprints, not paths), and each
    changed file's text ``original`` and ``final`` by display path. ``verified`` is false when
    the folder was too large to copy: every fix is then refused, and nothing changes."""

    fixes: tuple[PlannedFix, ...]
    before: Report
    after: Report
    original: Mapping[str, str]
    final: Mapping[str, str]
    verified: bool = True

    @property
    def applied(self) -> tuple[PlannedFix, ...]:
        return tuple(f for f in self.fixes if f.applicable)

    @property
    def refused(self) -> tuple[PlannedFix, ...]:
        return tuple(f for f in self.fixes if not f.applicable)

    @property
    def refitted(self) -> tuple[PlannedFix, ...]:
        """Applied fixes that write something other than their finding's suggested fix (a
        fitted primitive replaced by boxes clear of the links it would hit); their titles say why."""
        suggested = {d.fingerprint: d.fix for d in self.before.diagnostics}
        return tuple(p for p in self.applied if suggested.get(p.fingerprint, p.fix) != p.fix)

    @property
    def added(self) -> list[Diagnostic]:
        """Findings reported after the fixes and not before (checks a fix made possible, or consequences)."""
        known = {d.fingerprint for d in self.before.diagnostics}
        return [d for d in self.after.diagnostics if d.fingerprint not in known]

    @property
    def diff(self) -> str:
        return unified_diff(self.original, self.final)


def _link_of(d: Diagnostic | None) -> str | None:
    return d.link if d is not None else None


# The families of findings about its own link an unsafe fix of each family is answerable
# for: a collision element bounds the link's geometry (fit, inertia bounds), an inertia only
# itself. Self-collision findings (GC4xx) a collision fix brings with other links are held
# against it too (:func:`_collisions`): it is refitted clear of them once, else withdrawn.
ANSWERABLE = {"GC3": ("GC3", "GC5"), "GC5": ("GC5",)}


def _brought(fix: PlannedFix, finding: Diagnostic | None, new: Iterable[Diagnostic]) -> list[Diagnostic]:
    """New findings about the link an unsafe fix changed, of the families it answers for."""
    link = _link_of(finding)
    families = ANSWERABLE.get(fix.code[:3], ())
    if fix.fix.applicability is not Applicability.UNSAFE or link is None:
        return []
    return [d for d in new if d.link == link and d.code[:3] in families]


def _brought_reason(link: str, found: list[Diagnostic]) -> str:
    counts = ", ".join(f"{code} x{n}" for code, n in sorted(Counter(d.code for d in found).items()))
    return f"brings {len(found)} new finding{'s' if len(found) > 1 else ''} on {link} ({counts}): withdrawn"


def _collisions(fix: PlannedFix, finding: Diagnostic | None, new: Iterable[Diagnostic]) -> list[Diagnostic]:
    """New self-collision findings (GC4xx) of a pair holding the link a collision fix changed."""
    link = _link_of(finding)
    if fix.code[:3] != "GC3" or link is None:
        return []
    return [d for d in new if d.code[:3] == "GC4" and link in (d.links or ())]


def _collisions_reason(found: list[Diagnostic]) -> str:
    counts = ", ".join(f"{code} x{n}" for code, n in sorted(Counter(d.code for d in found).items()))
    pairs = sorted({"/".join(d.links or ()) for d in found})
    shown = ", ".join(pairs[:3]) + (f" and {len(pairs) - 3} more" if len(pairs) > 3 else "")
    s = "s" if len(found) > 1 else ""
    return f"brings {len(found)} new self-collision finding{s} ({counts}: {shown}): withdrawn"


UNLOADED = ("missing-file", "unresolved-package")  # mesh problems that leave a link without its mesh


def unloaded_link(d: Diagnostic | None) -> str | None:
    """The link of a finding about a mesh that could not be found (its fix makes the link's
    mesh load, and the checks that needed it run), else ``None``."""
    return d.link if d is not None and d.code[:3] == "GC2" and d.data.get("kind") in UNLOADED else None


def _subjects(d: Diagnostic) -> set[str]:
    return {name for name in (d.link, *(d.links or ())) if name}


def _neighbours(loaded: LoadedDescription, links: set[str]) -> set[str]:
    """``links`` and the links one joint away from them."""
    out = set(links)
    for joint in loaded.robot.joints:
        if joint.parent in links or joint.child in links:
            out |= {joint.parent, joint.child}
    return out


def _orphans_reason(found: list[Diagnostic]) -> str:
    more = f" and {len(found) - 3} more" if len(found) > 3 else ""
    shown = ", ".join(f"{d.code} {d.subject}" for d in found[:3]) + more
    s = "s" if len(found) > 1 else ""
    return f"with it applied the check reports {len(found)} new finding{s} ({shown}): withdrawn"


def _blamed(
    applied: Iterable[PlannedFix],
    findings: Mapping[str, Diagnostic],
    orphans: list[Diagnostic],
    loaded: LoadedDescription,
) -> list[PlannedFix]:
    """The fixes of a round to withdraw for ``orphans``, new findings no fix answered for (on
    another link: a foot's inertia after its calf's box changed): the fixes on or next to
    their links, else every unsafe fix of the round. A fix is never kept when the description
    has more findings with it than without."""
    near = _neighbours(loaded, {name for d in orphans for name in _subjects(d)})
    unsafe = [p for p in applied if p.fix.applicability is Applicability.UNSAFE]
    close = [p for p in unsafe if _link_of(findings.get(p.fingerprint)) in near]
    return close or unsafe or list(applied)


def _unloadable(applied: Iterable[PlannedFix]) -> list[PlannedFix]:
    """The fixes of a round whose text does not load: the unsafe ones (they write numbers a
    compiler may refuse, a tensor breaking the triangle inequality) when there are, else all."""
    fixes = list(applied)
    unsafe = [p for p in fixes if p.fix.applicability is Applicability.UNSAFE]
    return unsafe or fixes


def _others(link: str, found: Iterable[Diagnostic]) -> set[str]:
    return {other for d in found for other in (d.links or ()) if other != link}


def verify(result: FixResult, options: CheckOptions) -> Verified:
    """Apply ``result``'s fixes to a scratch copy in checked rounds (module docstring); the
    user's files are not touched."""
    loaded = result.loaded
    folder = description_folder(loaded, options.srdf)
    if not small_enough(folder):  # a fix is never written unchecked: none is applied
        refused = tuple(p.refused(TOO_LARGE, *p.locations) if p.applicable else p for p in result.plan.fixes)
        return Verified(refused, result.report, result.report, {}, {}, verified=False)
    with tempfile.TemporaryDirectory(prefix="geomcheck-fix-") as tmp:
        scratch = Scratch(loaded.bundle, folder, Path(tmp))
        return Rounds(result, options, scratch, scratch.options(options)).run()


def rounds_bound(fixes: int) -> int:
    """The rounds verification may take for ``fixes`` planned fixes: every round keeps some (each
    settling its finding, so fewer findings are left), or withdraws or refits one (each at most
    once per fixed state), so the loop ends well within this; when it does not, nothing is
    applied (:func:`verify`)."""
    return min(MOST_ROUNDS, max(MAX_ROUNDS, ROUNDS_PER_FIX * fixes + 2))


def _every_rule(options: CheckOptions) -> CheckOptions:
    """``options`` with every rule selected at its own severity: a fix is verified against
    every family, whatever the run selected (a collision box fitted for GC3 may hit a wheel,
    which only GC4 sees)."""
    return replace(options, selection=Selection())


@dataclass
class _Judgement:
    """One round's verdict on the fixes it applied: those withdrawn (each refused saying why),
    whether a collision fix was refitted (the round is then planned again with it), and those
    whose finding the check still reports."""

    rejected: dict[str, PlannedFix] = field(default_factory=dict)
    retried: bool = False
    unsettled: list[PlannedFix] = field(default_factory=list)

    @property
    def undone(self) -> bool:
        """Whether the round is undone and planned again."""
        return bool(self.rejected) or self.retried


class Rounds:
    """Verification in rounds (module docstring): what the rounds have kept, refused, withdrawn
    and refitted so far, and the description and report the next round starts from."""

    def __init__(self, result: FixResult, options: CheckOptions, scratch: Scratch, copy_options: CheckOptions) -> None:
        from geomcheck.pipeline import check_loaded

        self.result, self.options, self.scratch, self.copy_options = result, options, scratch, copy_options
        self.everything = _every_rule(copy_options)
        reference = (
            result.report
            if options.selection == Selection()
            else check_loaded(result.loaded, _every_rule(options), findings_only=True)
        )
        self.known = {d.fingerprint for d in reference.diagnostics}  # what the description has before any fix
        self.original: dict[str, str] = {}  # each written file's text before the first round that changed it
        self.kept: dict[str, PlannedFix] = {}
        self.refused: dict[str, PlannedFix] = {}
        self.withdrawn: set[str] = set()
        self.second_chance: set[str] = set()  # unsettled fixes tried again without the others of their round
        self.refitted: dict[str, SuggestedFix] = {}  # collision fixes refitted clear of the links they hit
        self.loaded, self.report, self.in_copy = result.loaded, result.report, False
        self.bound = rounds_bound(len(result.plan.fixes))

    def run(self) -> Verified:
        """Every round until one changes nothing (within :func:`rounds_bound`), and the outcome."""
        if not any(self.round(number) for number in range(1, self.bound + 1)):
            self.give_up()
        return self.outcome()

    def round(self, number: int) -> bool:
        """Round ``number``: plan, write, load and check the copy, keep or undo the round's fixes.
        True when there is nothing left to change (the fixed point)."""
        findings = {d.fingerprint: d for d in self.report.diagnostics}
        plan = self.plan()
        texts = fixed_sources(plan.sources, plan.edits)
        if not texts:
            return True
        previous = self.write(plan, texts)
        try:
            after_loaded = load_description(self.scratch.bundle, self.options.args, self.options.thresholds.limits)
        except InputError as err:  # the format's own loader (MuJoCo's compiler) refuses the fixed text
            self.undo(previous, _unloadable(plan.applied), f"the fixed description does not load ({err}): withdrawn")
            return False
        after_all = self.check(after_loaded, number)
        judgement = self.judge(plan, findings, after_all, after_loaded)
        if judgement.undone:
            self.scratch.write(previous)
            self.withdrawn |= set(judgement.rejected)
            self.refused.update(judgement.rejected)
        else:
            self.keep(plan, after_loaded, after_all)
        return False

    def plan(self) -> FixPlan:
        """The round's fixes, planned against where the rounds have got to (withdrawn ones left out)."""
        selected = [d for d in self.report.diagnostics if d.fingerprint not in self.withdrawn]
        plan = plan_fixes(self.loaded, selected, self.result.unsafe, overrides=self.refitted)
        for p in plan.refused:
            self.refused.setdefault(p.fingerprint, p)
        return plan

    def write(self, plan: FixPlan, texts: Mapping[str, str]) -> dict[str, str]:
        """Write the round's texts into the copy; the texts they replace, by original display path."""
        name: Callable[[str], str] = self.scratch.original_display if self.in_copy else (lambda d: d)
        previous = {name(f): plan.sources[f] for f in texts}
        for file, text in previous.items():
            self.original.setdefault(file, text)
        self.scratch.write({name(f): t for f, t in texts.items()})
        return previous

    def undo(self, previous: Mapping[str, str], suspects: Iterable[PlannedFix], reason: str) -> None:
        """The round's texts taken back and ``suspects`` withdrawn for ``reason``."""
        self.scratch.write(previous)
        for p in suspects:
            self.withdrawn.add(p.fingerprint)
            self.refused[p.fingerprint] = p.refused(reason, *p.locations)

    def check(self, loaded: LoadedDescription, number: int) -> Report:
        """The copy checked against every rule family."""
        from geomcheck.pipeline import check_loaded

        # round n checks again within its part of the caller's stage, 1 - 2^-(n-1) to 1 - 2^-n:
        # the stage's fraction only grows, however many rounds it takes
        with progress.nested(1 - 0.5 ** (number - 1), 1 - 0.5**number):
            return check_loaded(loaded, self.everything, findings_only=True)

    def judge(
        self, plan: FixPlan, findings: Mapping[str, Diagnostic], after: Report, loaded: LoadedDescription
    ) -> _Judgement:
        """Each applied fix judged by what the check reports with the round applied."""
        remaining = {d.fingerprint for d in after.diagnostics}
        new = [d for d in after.diagnostics if d.fingerprint not in self.known]
        judgement = _Judgement()
        for p in plan.applied:
            self.judge_fix(p, findings.get(p.fingerprint), remaining, new, loaded, judgement)
        self.blame_orphans(plan, findings, new, loaded, judgement)
        self.settle(judgement)
        return judgement

    def judge_fix(
        self,
        p: PlannedFix,
        finding: Diagnostic | None,
        remaining: set[str],
        new: list[Diagnostic],
        loaded: LoadedDescription,
        judgement: _Judgement,
    ) -> None:
        """``p`` unsettled (its finding remains), withdrawn (it brings findings it answers for),
        refitted clear of the links it now hits, or kept (nothing said)."""
        if p.fingerprint in remaining:
            judgement.unsettled.append(p)
        elif found := _brought(p, finding, new):
            judgement.rejected[p.fingerprint] = p.refused(_brought_reason(_link_of(finding) or "", found), *p.locations)
        elif hits := _collisions(p, finding, new):
            assert finding is not None and finding.link is not None
            # the boxes clear of other links are written as URDF collision elements only
            refit = (
                None
                if p.fingerprint in self.refitted or p.fix.syntax != "urdf"
                else clear_fit(loaded, self.copy_options, finding, _others(finding.link, hits))
            )
            if refit is None:
                judgement.rejected[p.fingerprint] = p.refused(_collisions_reason(hits), *p.locations)
            else:
                self.refitted[p.fingerprint], judgement.retried = refit, True

    def blame_orphans(
        self,
        plan: FixPlan,
        findings: Mapping[str, Diagnostic],
        new: list[Diagnostic],
        loaded: LoadedDescription,
        judgement: _Judgement,
    ) -> None:
        """New findings no fix answers for withdraw the fixes :func:`_blamed` names, when the
        round is not undone already."""
        answered = {
            id(d)
            for p in plan.applied
            for d in (*_brought(p, findings.get(p.fingerprint), new), *_collisions(p, findings.get(p.fingerprint), new))
        }
        # a mesh that did not load before the round is read now: what the check then finds on its
        # link was there all along, revealed, not brought (the next round fixes what it can of it)
        revealed = {name for p in plan.applied if (name := unloaded_link(findings.get(p.fingerprint)))}
        orphans = [d for d in new if id(d) not in answered and not _subjects(d) & revealed]
        if orphans and not judgement.undone:
            for p in _blamed(plan.applied, findings, orphans, loaded):
                judgement.rejected[p.fingerprint] = p.refused(_orphans_reason(orphans), *p.locations)

    def settle(self, judgement: _Judgement) -> None:
        """Unsettled fixes withdrawn, but for a second chance when the round is undone anyway."""
        # a fix can leave its finding because of another fix of the round (a neighbour's
        # element its fit borrows): when others are withdrawn or refitted, it is tried again once
        for p in judgement.unsettled:
            if judgement.undone and p.fingerprint not in self.second_chance:
                self.second_chance.add(p.fingerprint)
            else:
                judgement.rejected[p.fingerprint] = p.refused(UNSETTLED, *p.locations)

    def keep(self, plan: FixPlan, loaded: LoadedDescription, after_all: Report) -> None:
        """The round's fixes kept: the fixed copy is where the next round starts."""
        from geomcheck.pipeline import apply_selection

        for p in plan.applied:
            self.kept.setdefault(p.fingerprint, p)
        # the fixed description is where a new run of fix would start: the next round is that
        # run's first (every fix planned again, a withdrawn one too, judged against what the
        # description has now), so that fixing the result again changes nothing
        self.known = {d.fingerprint for d in after_all.diagnostics}
        self.withdrawn.clear()
        self.second_chance.clear()
        self.refitted.clear()
        after = replace(
            after_all, diagnostics=tuple(apply_selection(after_all.diagnostics, self.copy_options.selection))
        )
        self.loaded, self.report, self.in_copy = loaded, after, True

    def give_up(self) -> None:
        """No fixed point within the bound (a second run would change the files again): none applied."""
        reason = f"the fixes reach no fixed point within {self.bound} rounds of checking: none is applied"
        self.refused = {**self.refused, **{f: p.refused(reason, *p.locations) for f, p in self.kept.items()}}
        self.kept, self.report = {}, self.result.report
        self.scratch.write(self.original)

    def outcome(self) -> Verified:
        """The fixes, the reports before and after, and the text of every file they change."""
        final = {f: self.scratch.read(f) for f in self.original}
        changed = sorted(f for f in self.original if final[f] != self.original[f])
        return Verified(
            self.decided(),
            self.result.report,
            self.report,
            {f: self.original[f] for f in changed},
            {f: final[f] for f in changed},
        )

    def decided(self) -> tuple[PlannedFix, ...]:
        """Every fix kept, and every refused one whose finding is left, in report order."""
        left = {
            d.fingerprint for d in self.report.diagnostics
        }  # a withdrawn fix whose finding another fix settled is no news
        kept, refused = self.kept, self.refused
        fixes = [*kept.values(), *(p for f, p in refused.items() if f not in kept and f in left)]
        fixes.sort(key=_order(self.result.report))
        return tuple(fixes)


def _order(report: Report) -> Callable[[PlannedFix], int]:
    rank = {d.fingerprint: i for i, d in enumerate(report.diagnostics)}
    return lambda p: rank.get(p.fingerprint, len(rank))
