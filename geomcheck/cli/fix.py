"""``geomcheck fix PATH`` and ``geomcheck check --fix``: the command-line side of fixing.

With ``--diff`` the planned edits are printed as a unified diff and nothing is written
(exit 1 when there is something to fix, as ``ruff --diff``). Otherwise the files are
written, checked again, fixes that do not settle their finding are withdrawn, and the
remaining findings are reported as ``check`` would (exit status from them).
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the command line imports this module at start-up: the fixing machinery loads when used
    from geomcheck.fix.run import FixResult
    from geomcheck.fix.verify import Verified
    from geomcheck.fixes.model import PlannedFix


def add_fix_flags(p: argparse.ArgumentParser, with_fix: bool) -> None:
    """``--unsafe-fixes`` and ``--diff`` (and ``--fix`` on ``check``)."""
    group = p.add_argument_group("fixes")
    if with_fix:
        group.add_argument("--fix", action="store_true", help="apply the safe fixes to the description's files")
    group.add_argument(
        "--unsafe-fixes",
        action="store_true",
        help="also apply unsafe fixes: fitted collision primitives, inertias from the geometry",
    )
    group.add_argument("--diff", action="store_true", help="print the fixes as a unified diff; write nothing")


def add_fix_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    from geomcheck.cli.args import add_check_options, add_quiet_option, add_source_options
    from geomcheck.untrusted import add_untrusted_options

    fix = sub.add_parser(
        "fix",
        help="apply the fixes of a description's findings to its files (URDF/xacro, MJCF, SDFormat)",
        description="Check PATH and apply the fixes of its findings (safe ones; unsafe ones too with "
        "--unsafe-fixes), honouring --select/--ignore and the configuration. Only the text a fix must "
        "change is changed, in the file's own syntax (URDF/xacro, MJCF, SDFormat). --diff prints the change "
        "instead of writing it.",
    )
    fix.add_argument("paths", nargs="+", metavar="PATH", help="root URDF, xacro, MJCF or SDFormat file(s)")
    add_source_options(fix)
    add_check_options(fix)
    add_fix_flags(fix, with_fix=False)
    add_quiet_option(fix)
    add_untrusted_options(fix)  # a fork's description is as hostile to fix as to check
    fix.set_defaults(func=cmd_fix, fix=True)


def cmd_fix(ns: argparse.Namespace) -> int:
    """Fix each of ``ns.paths``; the exit status of the worst."""
    import geomcheck.progress as progress
    from geomcheck.cli.common import bundle_for, drawn_for, output_format, settings_for, write_output
    from geomcheck.fix.run import fix_bundle
    from geomcheck.fix.verify import verify
    from geomcheck.patch.apply import write_sources
    from geomcheck.pipeline import run_check
    from geomcheck.report import render

    status = 0
    texts = []
    for path in ns.paths:
        settings = settings_for(ns, path)
        options = settings.to_options()
        bundle = bundle_for(path, settings)
        # planning fixes reads the findings and the fixes section, never a drawing
        result = fix_bundle(bundle, replace(options, drawings=False), unsafe=ns.unsafe_fixes)
        progress.stage("verifying fixes", 0, 1)  # a stage list of its own: its rounds only move it forward
        verified = verify(result, options)
        if ns.diff:
            texts.append(verified.diff)
            progress.clear_display()
            sys.stderr.write("".join(f"geomcheck: {line}\n" for line in outcome_lines(result, verified, "would fix")))
            status = max(status, 1 if verified.final else 0)
            continue
        write_sources(bundle, verified.original, verified.final)
        progress.clear_display()  # the bar is drawn again by the check of the fixed files
        sys.stderr.write("".join(f"geomcheck: {line}\n" for line in outcome_lines(result, verified, "fixed")))
        fmt = output_format(ns, settings)
        after = run_check(bundle, drawn_for(options, fmt, ns))
        texts.append(render(after, fmt))
        status = max(status, 1 if after.failed and not ns.exit_zero else 0)
    write_output("".join(texts), ns.output)
    return status


def _plural(count: int, word: str) -> str:
    return f"{count} {word}{'' if count == 1 else 's'}"


def refused_lines(fixes: Sequence[PlannedFix]) -> list[str]:
    return [f"not fixed automatically: {p.code} {p.subject}: {p.fix.title}: {p.reason}" for p in fixes]


def refitted_lines(fixes: Sequence[PlannedFix]) -> list[str]:
    """Fixes that write something other than the finding's suggestion, each with why."""
    return [f"fixed otherwise than suggested: {p.code} {p.subject}: {p.fix.title}" for p in fixes]


def hidden_line(result: FixResult) -> list[str]:
    if result.unsafe:
        return []
    from geomcheck.fixes.derive import suggested_fix
    from geomcheck.fixes.model import Applicability

    hidden = sum(
        1
        for d in result.report.diagnostics
        if (f := suggested_fix(d)) is not None and f.applicability is Applicability.UNSAFE
    )
    return [f"{hidden} more fix{'' if hidden == 1 else 'es'} available with --unsafe-fixes"] if hidden else []


def unwritable_lines(result: FixResult) -> list[str]:
    """Findings whose fix would edit a file fixes may not write (outside the checked folder,
    behind a link): the report offers them no fix; here is why."""
    from geomcheck.errors import InputError
    from geomcheck.fixes.derive import suggested_fix
    from geomcheck.patch.apply import fix_tree, writable_path

    bundle = result.loaded.bundle
    lines = []
    for d in result.report.diagnostics:
        if d.editable or d.location is None or (fix := suggested_fix(d)) is None:
            continue
        if fix.applicability.value == "unsafe" and not result.unsafe:
            continue
        try:
            writable_path(bundle, d.location.file, fix_tree(bundle))
        except InputError as err:
            lines.append(f"not fixed automatically: {d.code} {d.subject}: {fix.title}: {err}")
    return lines


def outcome_lines(result: FixResult, verified: Verified, verb: str) -> list[str]:
    count = len(verified.applied)
    done = f"{verb} {_plural(count, 'finding')} in {', '.join(sorted(verified.final))}" if count else f"{verb} nothing"
    lines = [done, *refitted_lines(verified.refitted), *refused_lines(verified.refused), *unwritable_lines(result)]
    added = verified.added
    if added:
        by_code = ", ".join(f"{code} x{n}" for code, n in sorted(Counter(d.code for d in added).items()))
        lines.append(
            f"the fixed description has {_plural(len(added), 'finding')} it did not have ({by_code}): review them"
        )
    return [*lines, *hidden_line(result)]
