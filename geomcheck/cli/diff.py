"""``geomcheck diff``: what a change makes worse, against a revision or another copy."""

from __future__ import annotations

import argparse
from pathlib import Path

from geomcheck.cli.common import (
    annotated_input_errors,
    bundle_for,
    checked,
    exit_status,
    output_format,
    render_reports,
    settings_for,
    write_output,
)
from geomcheck.errors import UsageError


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
    options = settings.to_options()
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
