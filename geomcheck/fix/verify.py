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

import os
import shutil
import tempfile
from collections import Counter
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import geomcheck.progress as progress
from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError
from geomcheck.fix.clear import clear_fit
from geomcheck.fix.run import FixResult
from geomcheck.fixes.model import Applicability, PlannedFix, SuggestedFix
from geomcheck.load import Bundle, LoadedDescription, load_description
from geomcheck.model import Mesh
from geomcheck.options import CheckOptions, Selection
from geomcheck.patch.apply import fixed_sources, unified_diff
from geomcheck.patch.plan import plan_fixes
from geomcheck.report.model import Report

MAX_ROUNDS = 12  # fix, check, fix what is left or was revealed, try the withdrawn again: ruff's loop, bounded
ROUNDS_PER_FIX = 3  # ... and more for many fixes: each round keeps, withdraws or refits at least one [rounds]
MOST_ROUNDS = 200  # whatever the number of fixes [rounds]
MAX_SCRATCH_FILES = 20_000  # a description folder larger than this is not copied [files]
MAX_SCRATCH_BYTES = 1 << 30  # ... nor one larger than this [bytes]
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


def _description_folder(loaded: LoadedDescription, srdf: Path | None) -> Path:
    """The folder a scratch copy needs: the root file, every source file (what fixes write), the
    SRDF and the folder of every mesh named relative to the root file. Meshes named by an
    absolute path, or in a package that holds no source file, are read where they are: the
    copy's bundle keeps packages outside the folder in place (a robot whose meshes lie in
    another package, far off in a workspace, is verified all the same)."""
    bundle = loaded.bundle
    places = [bundle.root_file.parent, *([srdf.absolute().parent] if srdf is not None else [])]
    places += [Path(os.path.normpath(bundle.display_root / f)) for f in loaded.document.sources]
    for link in loaded.robot.links:
        for shape in (*link.visuals, *link.collisions):
            if not isinstance(shape.geometry, Mesh):
                continue
            filename = shape.geometry.filename
            if "://" in filename and not filename.startswith("file://"):
                continue  # package://: found through the package map, in place when outside the folder
            path = Path(filename.removeprefix("file://"))
            if not path.is_absolute():  # relative to the root file: the copy must hold it where it is
                places.append(Path(os.path.normpath(bundle.root_file.parent / path)).parent)
    return Path(os.path.commonpath([str(p) for p in places]))


def _small_enough(folder: Path) -> bool:
    files, size = 0, 0
    for _, _, names in os.walk(folder):
        files += len(names)
        if files > MAX_SCRATCH_FILES:
            return False
    for path in folder.rglob("*"):
        if path.is_file() and not path.is_symlink():
            size += path.stat().st_size
            if size > MAX_SCRATCH_BYTES:
                return False
    return True


class Scratch:
    """A copy of the description's folder under ``tmp`` (the folder keeps its name: packages
    found by folder name still are) and a bundle reading it, with maps between the two."""

    def __init__(self, bundle: Bundle, folder: Path, tmp: Path) -> None:
        self.original, self.folder = bundle, folder
        self.copy = tmp / folder.name
        shutil.copytree(folder, self.copy, symlinks=True)
        display_root = self.inside(bundle.display_root) if bundle.display_root.is_relative_to(folder) else self.copy
        self.bundle = Bundle(
            root_file=self.inside(bundle.root_file),
            packages={n: self.inside(d) if d.is_relative_to(folder) else d for n, d in bundle.packages.items()},
            display_root=display_root,
            confined=bundle.confined,
            allowed_roots=tuple(self.inside(r) if r.is_relative_to(folder) else r for r in bundle.allowed_roots),
            search_roots=tuple(self.inside(r) if r.is_relative_to(folder) else r for r in bundle.search_roots),
            allowed_env=bundle.allowed_env,
            env=bundle.env,
            uploaded=bundle.uploaded,
        )

    def inside(self, path: Path) -> Path:
        return self.copy / path.relative_to(self.folder)

    def options(self, options: CheckOptions) -> CheckOptions:
        """``options`` reading the copy's SRDF."""
        srdf = options.srdf.absolute() if options.srdf is not None else None
        return (
            replace(options, srdf=self.inside(srdf))
            if srdf is not None and srdf.is_relative_to(self.folder)
            else options
        )

    def original_display(self, display: str) -> str:
        """The original bundle's display path of the copy's display path ``display``."""
        copied = Path(os.path.normpath(self.bundle.display_root / display))
        return self.original.display(self.folder / copied.relative_to(self.copy))


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
    folder = _description_folder(loaded, options.srdf)
    if not _small_enough(folder):  # a fix is never written unchecked: none is applied
        refused = tuple(p.refused(TOO_LARGE, *p.locations) if p.applicable else p for p in result.plan.fixes)
        return Verified(refused, result.report, result.report, {}, {}, verified=False)
    with tempfile.TemporaryDirectory(prefix="geomcheck-fix-") as tmp:
        scratch = Scratch(loaded.bundle, folder, Path(tmp))
        return _rounds(result, options, scratch, scratch.options(options))


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


def _rounds(result: FixResult, options: CheckOptions, scratch: Scratch, copy_options: CheckOptions) -> Verified:
    from geomcheck.pipeline import apply_selection, check_loaded

    everything = _every_rule(copy_options)
    reference = result.report if options.selection == Selection() else check_loaded(result.loaded, _every_rule(options))
    known = {d.fingerprint for d in reference.diagnostics}  # what the description has before any fix
    original: dict[str, str] = {}  # each written file's text before the first round that changed it
    kept: dict[str, PlannedFix] = {}
    refused: dict[str, PlannedFix] = {}
    withdrawn: set[str] = set()
    second_chance: set[str] = set()  # unsettled fixes tried again without the others of their round
    refitted: dict[str, SuggestedFix] = {}  # collision fixes refitted clear of the links they hit
    loaded, report, in_copy = result.loaded, result.report, False
    bound = rounds_bound(len(result.plan.fixes))
    converged = False
    for round_number in range(1, bound + 1):
        findings = {d.fingerprint: d for d in report.diagnostics}
        selected = [d for d in report.diagnostics if d.fingerprint not in withdrawn]
        plan = plan_fixes(loaded, selected, result.unsafe, overrides=refitted)
        for p in plan.refused:
            refused.setdefault(p.fingerprint, p)
        texts = fixed_sources(plan.sources, plan.edits)
        if not texts:
            converged = True
            break
        name: Callable[[str], str] = scratch.original_display if in_copy else (lambda d: d)
        previous = {name(f): plan.sources[f] for f in texts}
        for file, text in previous.items():
            original.setdefault(file, text)
        _write(scratch, {name(f): t for f, t in texts.items()})
        try:
            after_loaded = load_description(scratch.bundle, options.args, options.thresholds.limits)
        except InputError as err:  # the format's own loader (MuJoCo's compiler) refuses the fixed text
            _write(scratch, previous)
            suspects = _unloadable(plan.applied)
            reason = f"the fixed description does not load ({err}): withdrawn"
            withdrawn |= {p.fingerprint for p in suspects}
            refused.update({p.fingerprint: p.refused(reason, *p.locations) for p in suspects})
            continue
        # round n checks again within its part of the caller's stage, 1 - 2^-(n-1) to 1 - 2^-n:
        # the stage's fraction only grows, however many rounds it takes
        with progress.nested(1 - 0.5 ** (round_number - 1), 1 - 0.5**round_number):
            after_all = check_loaded(after_loaded, everything)
        after = replace(after_all, diagnostics=tuple(apply_selection(after_all.diagnostics, copy_options.selection)))
        remaining = {d.fingerprint for d in after_all.diagnostics}
        new = [d for d in after_all.diagnostics if d.fingerprint not in known]
        rejected, retried, unsettled = {}, False, []
        for p in plan.applied:
            finding = findings.get(p.fingerprint)
            if p.fingerprint in remaining:
                unsettled.append(p)
            elif found := _brought(p, finding, new):
                rejected[p.fingerprint] = p.refused(_brought_reason(_link_of(finding) or "", found), *p.locations)
            elif hits := _collisions(p, finding, new):
                assert finding is not None and finding.link is not None
                # the boxes clear of other links are written as URDF collision elements only
                refit = (
                    None
                    if p.fingerprint in refitted or p.fix.syntax != "urdf"
                    else clear_fit(after_loaded, copy_options, finding, _others(finding.link, hits))
                )
                if refit is None:
                    rejected[p.fingerprint] = p.refused(_collisions_reason(hits), *p.locations)
                else:
                    refitted[p.fingerprint], retried = refit, True
        answered = {
            id(d)
            for p in plan.applied
            for d in (*_brought(p, findings.get(p.fingerprint), new), *_collisions(p, findings.get(p.fingerprint), new))
        }
        orphans = [d for d in new if id(d) not in answered]
        if orphans and not rejected and not retried:
            for p in _blamed(plan.applied, findings, orphans, after_loaded):
                rejected[p.fingerprint] = p.refused(_orphans_reason(orphans), *p.locations)
        # a fix can leave its finding because of another fix of the round (a neighbour's
        # element its fit borrows): when others are withdrawn or refitted, it is tried again once
        for p in unsettled:
            if (rejected or retried) and p.fingerprint not in second_chance:
                second_chance.add(p.fingerprint)
            else:
                rejected[p.fingerprint] = p.refused(UNSETTLED, *p.locations)
        if rejected or retried:
            _write(scratch, previous)
            withdrawn |= set(rejected)
            refused.update(rejected)
            continue
        for p in plan.applied:
            kept.setdefault(p.fingerprint, p)
        # the fixed description is where a new run of fix would start: the next round is that
        # run's first (every fix planned again, a withdrawn one too, judged against what the
        # description has now), so that fixing the result again changes nothing
        known = remaining
        withdrawn.clear()
        second_chance.clear()
        refitted.clear()
        loaded, report, in_copy = after_loaded, after, True
    if not converged:  # no fixed point within the bound: a second run would change the files again
        reason = f"the fixes reach no fixed point within {bound} rounds of checking: none is applied"
        refused = {**refused, **{f: p.refused(reason, *p.locations) for f, p in kept.items()}}
        kept, report = {}, result.report
        _write(scratch, original)
    final = {f: _read(scratch, f) for f in original}
    changed = sorted(f for f in original if final[f] != original[f])
    left = {d.fingerprint for d in report.diagnostics}  # a withdrawn fix whose finding another fix settled is no news
    fixes = [*kept.values(), *(p for f, p in refused.items() if f not in kept and f in left)]
    fixes.sort(key=_order(result.report))
    return Verified(
        tuple(fixes),
        result.report,
        report,
        {f: original[f] for f in changed},
        {f: final[f] for f in changed},
    )


def _copied_path(scratch: Scratch, display: str) -> Path:
    return scratch.inside(Path(os.path.normpath(scratch.original.display_root / display)))


def _write(scratch: Scratch, texts: Mapping[str, str]) -> None:
    """Write the fixed texts into the copy; the copy keeps the description's symbolic links
    (they may point anywhere), so nothing is written through one."""
    from geomcheck.patch.apply import refuse_links, write_regular

    for display, text in texts.items():
        path = _copied_path(scratch, display)
        refuse_links(scratch.copy, path, display)
        write_regular(path, text.encode("utf-8"), display)


def _read(scratch: Scratch, display: str) -> str:
    return _copied_path(scratch, display).read_bytes().decode("utf-8", errors="replace")


def _order(report: Report) -> Callable[[PlannedFix], int]:
    rank = {d.fingerprint: i for i, d in enumerate(report.diagnostics)}
    return lambda p: rank.get(p.fingerprint, len(rank))
