"""``geomcheck check PATH...``: check descriptions and report their findings."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from geomcheck.cli.args import (
    LINE_FORMATS,
    add_cache_option,
    add_check_options,
    add_option_flags,
    add_quiet_option,
    add_source_options,
    flags_of,
)
from geomcheck.cli.common import (
    annotated_input_errors,
    bundle_for,
    checked,
    display_path,
    drawn_for,
    exit_status,
    output_format,
    render_reports,
    settings_for,
    write_output,
)
from geomcheck.cli.fix import add_fix_flags, cmd_fix
from geomcheck.errors import UsageError
from geomcheck.untrusted import add_untrusted_options


def add_check_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    check = sub.add_parser("check", help="check robot descriptions")
    check.add_argument("paths", nargs="+", metavar="PATH", help="root URDF, xacro, MJCF or SDFormat file(s)")
    add_source_options(check)
    add_check_options(check)
    base = check.add_argument_group("baseline")
    add_option_flags(base, flags_of("baseline"))
    base.add_argument("--write-baseline", metavar="FILE", help="record the current findings in FILE and exit 0")
    add_cache_option(check)
    add_quiet_option(check)
    add_untrusted_options(check)
    add_fix_flags(check, with_fix=True)
    check.set_defaults(func=cmd_check)


def cmd_check(ns: argparse.Namespace) -> int:
    from geomcheck.baseline import Baseline, apply_baseline
    from geomcheck.check_cache import cached_check

    if ns.fix or ns.diff:
        return cmd_fix(ns)

    runs = [(path, settings_for(ns, path)) for path in ns.paths]
    fmt = output_format(ns, runs[0][1])
    if len(runs) > 1 and fmt not in LINE_FORMATS and not ns.statistics:
        raise UsageError(f"--format {fmt} takes one description; run geomcheck once per description")
    with annotated_input_errors(fmt, ns.output):
        outputs = [ns.output] if ns.output else []
        reports = [
            cached_check(bundle_for(p, s), drawn_for(s.to_options(), fmt, ns), checked, outputs) for p, s in runs
        ]
    if ns.write_baseline:
        baseline = Baseline.from_diagnostics(d for r in reports for d in r.diagnostics)
        baseline.write(Path(ns.write_baseline))
        sys.stderr.write(f"geomcheck: wrote {len(baseline.entries)} findings to baseline {ns.write_baseline}\n")
        return 0
    baseline_files = {s.baseline for _, s in runs if s.baseline is not None}
    if len(baseline_files) > 1:
        raise UsageError("the descriptions' configurations name different baselines; pass --baseline FILE")
    if baseline_files:
        baseline_file = baseline_files.pop()
        label = display_path(baseline_file)
        reports, result = apply_baseline(reports, Baseline.load(baseline_file), label)
        if result.stale:
            sys.stderr.write(
                f"geomcheck: {len(result.stale)} baseline entries no longer occur; "
                f"update it with --write-baseline {label}\n"
            )
    write_output(render_reports(reports, fmt, ns.statistics), ns.output)
    return exit_status(any(r.failed for r in reports), ns)
