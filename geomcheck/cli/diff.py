"""``geomcheck diff``: what a change makes worse, against a revision or another copy."""

from __future__ import annotations

import argparse
from pathlib import Path

from geomcheck.cli.args import add_cache_option, add_check_options, add_quiet_option, add_source_options
from geomcheck.cli.common import (
    annotated_input_errors,
    bundle_for,
    checked,
    drawn_for,
    exit_status,
    output_format,
    render_reports,
    settings_for,
    write_output,
)
from geomcheck.errors import UsageError
from geomcheck.untrusted import add_untrusted_options


def add_diff_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    diff = sub.add_parser(
        "diff",
        help="report what a change did: new, fixed and regressed findings",
        description="geomcheck diff --base REV PATH compares PATH at git revision REV with the working tree; "
        "geomcheck diff OLD NEW compares two descriptions. Exit 1 when a new finding fails.",
    )
    diff.add_argument("paths", nargs="+", metavar="PATH", help="PATH with --base, else OLD NEW")
    diff.add_argument("--base", metavar="REV", help="git revision to compare the working tree with")
    diff.add_argument(
        "--fail-on-regression",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="report a kept finding that got worse (severity rose, or a metric past the tolerance) like a new "
        "one, so it fails at --fail-on (default: on)",
    )
    add_source_options(diff)
    add_check_options(diff)
    add_cache_option(diff)
    add_quiet_option(diff)
    add_untrusted_options(diff)
    diff.set_defaults(func=cmd_diff)


def cmd_diff(ns: argparse.Namespace) -> int:
    from geomcheck.check_cache import cached_check
    from geomcheck.diff import check_base_revision, check_other, diff_report

    if ns.base is not None and len(ns.paths) != 1:
        raise UsageError("diff --base REV takes one description: geomcheck diff --base REV PATH")
    if ns.base is None and len(ns.paths) != 2:
        raise UsageError("diff takes --base REV PATH, or two descriptions: geomcheck diff OLD NEW")
    head_path = ns.paths[-1]
    settings = settings_for(ns, head_path)
    fmt = output_format(ns, settings)
    options = drawn_for(settings.to_options(), fmt, ns)
    with annotated_input_errors(fmt, ns.output):
        outputs = [ns.output] if ns.output else []
        head = cached_check(bundle_for(head_path, settings), options, checked, outputs)
    if ns.base is not None:
        base, label, note = check_base_revision(ns.base, Path(head_path), settings, options)
    else:
        base, label, note = check_other(Path(ns.paths[0]), Path(head_path), settings, options)
    tolerance = options.thresholds.diff.metric_relative_tolerance
    report = diff_report(base, head, label, tolerance, base_note=note, gate_regressions=ns.fail_on_regression)
    write_output(render_reports([report], fmt, ns.statistics), ns.output)
    return exit_status(report.failed, ns)
