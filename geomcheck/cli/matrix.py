"""``geomcheck matrix``: the collision matrix as a MoveIt SRDF."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace

from geomcheck.cli.common import bundle_for, settings_for, write_output


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
