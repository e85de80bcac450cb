"""One check run: load -> model -> checks -> report."""

from __future__ import annotations

import contextlib
import functools
import os
import sys
from collections.abc import Iterable
from dataclasses import replace

import geomcheck.progress as progress
from geomcheck.checks import CheckContext, family_names, family_runners
from geomcheck.checks.analyses import reads_meshes
from geomcheck.diagnostics import Diagnostic, SkippedCheck
from geomcheck.load import Bundle, LoadedDescription, MeshStore, load_description, mesh_formats
from geomcheck.model import Mesh
from geomcheck.options import CheckOptions, Selection
from geomcheck.repeats import group_repeats
from geomcheck.report.model import Report, RobotSummary, report_timestamp
from geomcheck.rules import matches
from geomcheck.version import __version__

EXCERPT_CONTEXT_LINES = 2
EXCERPT_MAX_CHARACTERS = 240  # of one excerpt line: a minified file is one line [characters]
MAX_FINDINGS_PER_RULE = 500  # findings of one rule in a report; the rest are counted in ``skipped`` [count]
HEAP_TOP_PAD_BYTES = 64 << 20  # glibc's heap grows, and is kept on trimming, in steps of this [bytes]
_M_TOP_PAD = -2  # glibc's mallopt parameter number of the top pad


@functools.cache
def keep_heap() -> None:
    """Let glibc's malloc grow its heap, and keep it when freeing, in steps of
    :data:`HEAP_TOP_PAD_BYTES` instead of 128 kB: the checks allocate and free large numpy
    temporaries by the thousand, and each fresh page costs a fault (0.2 s of CPU on the
    full PR2 once its fits come from the cache). Once per process; nothing elsewhere."""
    if not sys.platform.startswith("linux"):
        return
    with contextlib.suppress(ValueError, OSError, AttributeError):
        if not (os.confstr("CS_GNU_LIBC_VERSION") or "").startswith("glibc"):
            return
        import ctypes

        ctypes.CDLL(None).mallopt(_M_TOP_PAD, HEAP_TOP_PAD_BYTES)


def is_selected(d: Diagnostic, selection: Selection) -> bool:
    """Whether ``d`` survives ``select``/``ignore`` and the per-subject ignores."""
    if not any(matches(d.code, s) for s in selection.select):
        return False
    if any(matches(d.code, s) for s in selection.ignore):
        return False
    subjects = [d.link, *(d.links or ())]
    for name in subjects:
        if name and any(matches(d.code, s) for s in selection.per_link_ignore.get(name, ())):
            return False
    return not (d.joint and any(matches(d.code, s) for s in selection.per_joint_ignore.get(d.joint, ())))


def apply_selection(diagnostics: Iterable[Diagnostic], selection: Selection) -> list[Diagnostic]:
    """Selected diagnostics with severity overrides applied (longest matching selector wins)."""
    out = []
    for d in diagnostics:
        if not is_selected(d, selection):
            continue
        overrides = [(len(k), sev) for k, sev in selection.severity.items() if matches(d.code, k)]
        if overrides:
            d = replace(d, severity=max(overrides, key=lambda o: o[0])[1])
        out.append(d)
    return out


def with_excerpt(d: Diagnostic, loaded: LoadedDescription) -> Diagnostic:
    """``d`` with a few lines of source around its location, from the file or the expanded document."""
    loc = d.location
    if loc is None:
        return d
    text, line = None, None
    if loc.line is not None and loc.file in loaded.document.sources:
        text, line = loaded.document.sources[loc.file], loc.line
    elif loc.expanded_line is not None:
        text, line = loaded.document.text, loc.expanded_line
    if text is None or line is None:
        return d
    lines = text.splitlines()
    lo = max(1, line - EXCERPT_CONTEXT_LINES)
    hi = min(len(lines), line + EXCERPT_CONTEXT_LINES)
    column = loc.column if loc.line is not None else None
    return replace(d, excerpt=tuple((n, clip_line(lines[n - 1], column)) for n in range(lo, hi + 1)))


def clip_line(text: str, column: int | None) -> str:
    """``text`` cut to :data:`EXCERPT_MAX_CHARACTERS` around ``column`` (1-based) when longer."""
    if len(text) <= EXCERPT_MAX_CHARACTERS:
        return text
    centre = (column or 1) - 1
    start = max(0, min(centre - EXCERPT_MAX_CHARACTERS // 2, len(text) - EXCERPT_MAX_CHARACTERS))
    clipped = text[start : start + EXCERPT_MAX_CHARACTERS]
    return ("..." if start > 0 else "") + clipped + ("..." if start + EXCERPT_MAX_CHARACTERS < len(text) else "")


def cap_per_rule(diagnostics: list[Diagnostic], cap: int) -> tuple[list[Diagnostic], list[SkippedCheck]]:
    """At most ``cap`` findings of each rule (in report order); a ``skipped`` entry counts the rest."""
    kept: list[Diagnostic] = []
    left_out: dict[str, int] = {}
    seen: dict[str, int] = {}
    for d in diagnostics:
        seen[d.code] = seen.get(d.code, 0) + 1
        if seen[d.code] <= cap:
            kept.append(d)
        else:
            left_out[d.code] = left_out.get(d.code, 0) + 1
    notes = [
        SkippedCheck("findings", code, f"{count} more {code} findings left out (at most {cap} per rule)")
        for code, count in sorted(left_out.items())
    ]
    return kept, notes


def mesh_counts(ctx: CheckContext, read: bool = True) -> tuple[int, int]:
    """(distinct mesh files referenced, of which loaded). The total comes from the model; the
    loaded ones are counted only when ``read`` (the run's rules read meshes, so the store holds
    them), else 0: no mesh is read only to be counted."""
    filenames = sorted(
        {
            (s.geometry.filename, s.geometry.scale)
            for link in ctx.robot.links
            for s in (*link.visuals, *link.collisions)
            if isinstance(s.geometry, Mesh)
        }
    )
    total = len({filename for filename, _ in filenames})
    if not read:
        return total, 0
    from geomcheck.load.meshes import LoadedMesh

    results = {}
    for filename, scale in filenames:
        r = ctx.meshes.get(Mesh(filename, scale))
        results[filename] = isinstance(r, LoadedMesh)
    return total, sum(results.values())


def writable_source(bundle: Bundle, d: Diagnostic) -> bool:
    """Whether ``d``'s fix, if it has one, edits a file fixes may write (its location's file)."""
    if d.location is None or d.fix is None:
        return True
    from geomcheck.patch.apply import writable

    return writable(bundle, d.location.file)


def options_summary(options: CheckOptions) -> dict[str, object]:
    sc = options.thresholds.self_collision
    # the variables' values the user gave are named only when there are (reports without them
    # are as they always were)
    given = {"env": dict(sorted(options.env.items()))} if options.env else {}
    return {
        "args": dict(sorted(options.args.items())),
        **given,
        "srdf": options.srdf.name if options.srdf else None,
        "backend": options.backend,
        "semantics": options.semantics,
        "matrix": options.matrix,
        "sweep": options.sweep,
        "samples": options.samples if options.samples is not None else sc.samples,
        "seed": options.seed if options.seed is not None else sc.seed,
        "pose": dict(sorted(options.pose.items())),
        "pose_name": options.pose_name,
        "view_3d": options.view_3d,
    }


def check_loaded(
    loaded: LoadedDescription,
    options: CheckOptions,
    first_stage: int = 0,
    stage_label: str = "",
    findings_only: bool = False,
) -> Report:
    """Run every check family on an already loaded description (each family a progress
    stage, counted after ``first_stage`` stages already done and named after ``stage_label``:
    :mod:`geomcheck.progress`). With ``findings_only`` the report has the findings and the
    sections the measuring families write, but nothing drawn (views, 3D scene) and no fixes
    section: what verifying a fix reads of a check."""
    keep_heap()
    meshes = MeshStore(loaded.bundle, options.thresholds.limits, mesh_formats(loaded.format))
    ctx = CheckContext(loaded=loaded, meshes=meshes, options=options)
    diagnostics: list[Diagnostic] = list(loaded.diagnostics)
    skipped: list[SkippedCheck] = list(loaded.skipped)
    sections: dict[str, object] = {}
    runners = family_runners(options.selection, drawing=options.drawings and not findings_only)
    try:
        for index, (name, run) in enumerate(runners):
            progress.stage(stage_label + name, first_stage + index, first_stage + len(runners))
            result = run(ctx)
            diagnostics.extend(result.diagnostics)
            skipped.extend(result.skipped)
            sections.update(result.sections)
    except MemoryError:
        # a limit that still stops a check names the mesh it was busy with and its size
        raise MemoryError(ctx.meshes.memory_hint() or "") from None
    selected = group_repeats(sorted(apply_selection(diagnostics, options.selection), key=Diagnostic.sort_key))
    selected, left_out = cap_per_rule(selected, MAX_FINDINGS_PER_RULE)
    skipped.extend(left_out)
    selected = fixable([with_excerpt(d, loaded) for d in selected], loaded, sections, findings_only)
    total, ok = mesh_counts(ctx, read=reads_meshes([name for name, _ in runners]))
    robot = loaded.robot
    return Report(
        robot=RobotSummary(
            name=robot.name,
            source=loaded.document.root,
            links=len(robot.authored_links),  # as the format's own tool counts them
            joints=len(robot.authored_joints),
            meshes_total=total,
            meshes_loaded=ok,
        ),
        diagnostics=tuple(selected),
        tool_version=__version__,
        created=report_timestamp(),
        fail_on=options.fail_on,
        skipped=tuple(sorted(set(skipped), key=lambda s: (s.check, s.subject, s.reason))),
        sections=sections,
        options=options_summary(options),
    )


def fixable(
    selected: list[Diagnostic], loaded: LoadedDescription, sections: dict[str, object], findings_only: bool
) -> list[Diagnostic]:
    """``selected`` marked as fixes can or cannot edit them, with their advice in the format's
    own syntax; unless ``findings_only``, the fixes section added to ``sections``."""
    from geomcheck.fixes.help_syntax import help_in_syntax
    from geomcheck.patch.section import FIX_SYNTAXES, FIXES_SECTION, fixes_section  # the planner: text, no geometry

    # fixes are written in the description's own syntax (URDF and xacro, MJCF, SDFormat); a
    # format fixes cannot write keeps its findings' advice but gets no patch
    if loaded.format not in FIX_SYNTAXES:
        return [replace(d, editable=False) for d in selected]
    # a finding in a file fixes may not write (outside the checked folder, behind a link)
    # is not fixable: `geomcheck fix` would refuse it, so it is neither marked nor counted
    selected = [d if writable_source(loaded.bundle, d) else replace(d, editable=False) for d in selected]
    if loaded.format != "urdf":  # the advice and the fix in the format's own syntax
        selected = [replace(d, syntax=loaded.format, help=help_in_syntax(d.help, loaded.format)) for d in selected]
    if not findings_only and (fixes := fixes_section(loaded, selected)) is not None:
        sections[FIXES_SECTION] = fixes
    return selected


def load_and_check(bundle: Bundle, options: CheckOptions) -> tuple[LoadedDescription, Report]:
    """Load ``bundle`` (the first progress stage) and check it; the loaded description with
    its report. Raises :class:`geomcheck.errors.InputError` when it cannot be read."""
    progress.stage("loading", 0, 1 + len(family_names(options.selection, drawing=options.drawings)))
    loaded = load_description(bundle, options.args, options.thresholds.limits)
    return loaded, check_loaded(loaded, options, first_stage=1)


def run_check(bundle: Bundle, options: CheckOptions | None = None) -> Report:
    """Load ``bundle`` and check it. Raises :class:`geomcheck.errors.InputError` when it cannot be read."""
    return load_and_check(bundle, options or CheckOptions())[1]


__all__ = [
    "EXCERPT_CONTEXT_LINES",
    "EXCERPT_MAX_CHARACTERS",
    "MAX_FINDINGS_PER_RULE",
    "apply_selection",
    "cap_per_rule",
    "check_loaded",
    "clip_line",
    "is_selected",
    "keep_heap",
    "load_and_check",
    "mesh_counts",
    "options_summary",
    "report_timestamp",
    "run_check",
    "with_excerpt",
]
