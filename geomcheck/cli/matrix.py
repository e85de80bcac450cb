"""``geomcheck matrix``: the collision matrix as a MoveIt SRDF."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace

from geomcheck.cli.args import (
    add_cache_option,
    add_config_options,
    add_load_arguments,
    add_option_flags,
    add_quiet_option,
    flags_of,
)
from geomcheck.cli.common import bundle_for, settings_for, write_output
from geomcheck.untrusted import add_untrusted_options


def add_matrix_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    matrix = sub.add_parser(
        "matrix",
        help="compute the collision matrix and write it as a MoveIt SRDF",
        description="Classify every pair of links with collision geometry as MoveIt's Setup Assistant does "
        "(Adjacent, Default, Always, Never), with certified-never pairs and a witness search, and write the "
        "<disable_collisions> list (to stdout without --srdf-out).",
    )
    add_load_arguments(matrix)
    matrix.add_argument("--srdf-out", metavar="FILE", help="write the SRDF to FILE and a summary to stdout")
    add_option_flags(matrix, flags_of("checks", "matrix"))
    add_config_options(matrix)
    add_cache_option(matrix)
    add_quiet_option(matrix)
    add_untrusted_options(matrix)
    matrix.set_defaults(func=cmd_matrix)


def cmd_matrix(ns: argparse.Namespace) -> int:
    """The collision matrix as a MoveIt SRDF ``<disable_collisions>`` list (file or stdout)."""
    from geomcheck.checks.matrix import load_and_compute
    from geomcheck.report.srdf import render_srdf

    settings = settings_for(ns, ns.path)
    options = replace(settings.to_options(), matrix=True, sweep=False)
    loaded, matrix = load_and_compute(bundle_for(ns.path, settings), options)
    write_output(render_srdf(matrix, loaded.robot.name), ns.srdf_out)
    if ns.srdf_out:
        counts = matrix.counts()
        tally = ", ".join(f"{counts[c]} {c}" for c in ("adjacent", "default", "always", "never", "enabled"))
        sys.stdout.write(
            f"{loaded.robot.name}: {len(matrix.pairs)} pairs of {len(matrix.links)} links: {tally} "
            f"({counts['certified']} never pairs certified); {matrix.samples} samples, seed {matrix.seed}, "
            f"backend {matrix.backend}, {matrix.stats.seconds:.1f} s; wrote {ns.srdf_out}\n"
        )
    return 0
