"""Planning: every finding's fix turned into edits of the source files, together.

Each fix is planned on its own by :class:`~geomcheck.patch.planner.Planner`. An element
written once in a macro is changed only when every link expanded from it gets the same
change. Two fixes that want different text at the same place are both refused; identical
edits are made once.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from geomcheck.diagnostics import Diagnostic
from geomcheck.fixes.derive import suggested_fix
from geomcheck.fixes.model import Applicability, Edit, PlannedFix, SuggestedFix, place
from geomcheck.load import LoadedDescription
from geomcheck.patch.planner import Planner

Target = tuple[str, str, int]  # (tag, file, line) of the source element a fix changes


@dataclass(frozen=True)
class FixPlan:
    """Every fixable finding's :class:`PlannedFix` (report order), the edits to make, and the
    text of every file they may edit (the description's sources, an SRDF), by display path."""

    fixes: tuple[PlannedFix, ...]
    edits: tuple[Edit, ...]
    sources: Mapping[str, str] = field(default_factory=dict)

    @property
    def applied(self) -> tuple[PlannedFix, ...]:
        return tuple(f for f in self.fixes if f.applicable)

    @property
    def refused(self) -> tuple[PlannedFix, ...]:
        return tuple(f for f in self.fixes if not f.applicable)


def _element_counts(loaded: LoadedDescription) -> Counter[Target]:
    """How many elements of the model come from each ``(tag, file, line)`` of the sources."""
    counts: Counter[Target] = Counter()
    robot = loaded.robot
    for link in robot.links:
        for shape in (*link.visuals, *link.collisions):
            if shape.location is not None and shape.location.line is not None:
                tag = "geom" if loaded.format == "mjcf" else shape.kind  # MJCF's visual and collision shapes
                counts[(tag, shape.location.file, shape.location.line)] += 1
        loc = link.inertial.location if link.inertial is not None else None
        if loc is not None and loc.line is not None:
            counts[("inertial", loc.file, loc.line)] += 1
    for joint in robot.joints:
        if joint.location is not None and joint.location.line is not None:
            counts[("joint", joint.location.file, joint.location.line)] += 1
    return counts


def _same_everywhere(
    planned: list[PlannedFix], targets: list[Target | None], counts: Counter[Target], weights: Sequence[int]
) -> list[PlannedFix]:
    """Fixes of elements written once for several links: kept when they agree for all of them
    (a finding grouping alike ones, ``weights[i]`` > 1, answers for every link it names)."""
    groups: dict[tuple[str, Target], list[int]] = defaultdict(list)
    for i, (p, target) in enumerate(zip(planned, targets, strict=True)):
        if p.applicable and not p.fix.context_free and target is not None:
            groups[(p.code, target)].append(i)
    out = list(planned)
    for (_, (tag, file, line)), members in groups.items():
        expected = counts.get((tag, file, line), len(members))
        if expected <= 1:
            continue
        variants = {frozenset(planned[i].edits) for i in members}
        subjects = ", ".join(planned[i].subject for i in members)
        where = place(file, line)
        if sum(weights[i] for i in members) < expected:
            reason = (
                f"the <{tag}> at {where} is written once for {expected} elements; "
                f"this fix applies to {len(members)} of them ({subjects})"
            )
        elif len(variants) > 1:
            reason = f"the <{tag}> at {where} is written once for {expected} elements whose fixes differ ({subjects})"
        else:
            continue
        for i in members:
            out[i] = planned[i].refused(reason, where)
    return out


def _overlaps(a: Edit, b: Edit) -> bool:
    if a.file != b.file:
        return False
    if a.start == a.end or b.start == b.end:  # insertions collide at the same point or inside a replacement
        return a.start == b.start or (b.start < a.start < b.end) or (a.start < b.start < a.end)
    return a.start < b.end and b.start < a.end


def _without_conflicts(planned: list[PlannedFix]) -> tuple[list[PlannedFix], list[Edit]]:
    accepted: list[Edit] = []
    owner: dict[Edit, PlannedFix] = {}
    out = []
    for p in planned:
        if not p.applicable:
            out.append(p)
            continue
        clash = next((a for e in p.edits for a in accepted if a != e and _overlaps(a, e)), None)
        if clash is not None:
            other = owner[clash]
            out.append(p.refused(f"conflicts with the fix of {other.code} {other.subject}", clash.file))
            continue
        for e in p.edits:
            if e not in owner:
                accepted.append(e)
                owner[e] = p
        out.append(p)
    return out, accepted


def plan_fixes(
    loaded: LoadedDescription,
    diagnostics: Iterable[Diagnostic],
    unsafe: bool = False,
    planner: Planner | None = None,
    overrides: Mapping[str, SuggestedFix] | None = None,
) -> FixPlan:
    """The fixes of ``diagnostics`` (already selected) for ``loaded``'s sources; unsafe ones
    only with ``unsafe``. Fixes are planned in the diagnostics' order; a ``planner`` of
    ``loaded`` passed in keeps its scanned sources for the next call; ``overrides`` gives the
    fix of a finding (by fingerprint) in place of the one its data suggests."""
    planner = planner or Planner(loaded)
    planned: list[PlannedFix] = []
    targets: list[Target | None] = []
    weights: list[int] = []  # the elements a finding stands for: itself and those it groups (also)
    for d in diagnostics:
        if not d.editable:  # its file is one fixes may not write, or its format has no fixes
            continue
        fix = (overrides or {}).get(d.fingerprint) or suggested_fix(d)
        if fix is None or (fix.applicability is Applicability.UNSAFE and not unsafe):
            continue
        p = planner.plan_one(d, fix)
        loc = d.location
        target = (fix.element, loc.file, loc.line) if loc is not None and loc.line is not None else None
        if p.applicable and target is not None:
            p = PlannedFix(p.code, p.subject, p.fingerprint, p.fix, p.edits, "", (place(target[1], target[2]),))
        planned.append(p)
        targets.append(target)
        weights.append(1 + len(d.data.get("also", ())))
    planned = _same_everywhere(planned, targets, _element_counts(loaded), weights)
    planned, edits = _without_conflicts(planned)
    return FixPlan(tuple(planned), tuple(sorted(edits, key=lambda e: (e.file, e.start, e.end))), planner.sources)
