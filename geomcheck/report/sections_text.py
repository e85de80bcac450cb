"""The sweep and matrix sections as a few lines of text, for the full format: what a user at a
terminal needs to know about the caster and wheel turns and the collision matrix without
opening the JSON or HTML report (which hold every number)."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence

from geomcheck.report.html_common import mm, plural
from geomcheck.report.model import Report
from geomcheck.report.section_matrix import matrix_section
from geomcheck.report.section_sweeps import SweepPair, sweeps_section
from geomcheck.selfcollision.matrix import PairClass

FULL_TURN_SLACK_RAD = 0.05  # a contact range this close to 2 pi covers the whole turn (grid spacing 0.017) [rad]


def _degrees(angle: float) -> str:
    """The joint angle as written in the URDF's terms: signed, in degrees."""
    return f"{math.degrees(angle):.1f}°"


def _full_turn(ranges: Sequence[tuple[float, float]]) -> bool:
    return len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= 2 * math.pi - FULL_TURN_SLACK_RAD


def _pair_text(pair: SweepPair) -> str:
    """One pair of a sweep: where it comes closest, or where it is in contact."""
    name = pair.name + (" (adjacent)" if pair.adjacent else "")
    ranges = pair.colliding_ranges
    if not ranges:
        at = "" if pair.min_angle is None else f" at {_degrees(pair.min_angle)}"
        return f"{name} {mm(pair.min_clearance)}{at}"
    depth = mm(pair.max_depth)
    if _full_turn(ranges):
        return f"{name} overlap {depth} at every angle"
    spans = ", ".join(f"{_degrees(lo)} to {_degrees(hi)}" for lo, hi in ranges)
    return f"{name} from {spans}, {depth} deep"


def _closest_first(pair: SweepPair) -> tuple[float, tuple[str, ...]]:
    return (math.inf if pair.min_clearance is None else pair.min_clearance, pair.links)


def sweep_lines(report: Report) -> list[str]:
    """A heading and one line per swept joint: the pairs in contact, else the closest
    non-adjacent pair (the closest pair when all are adjacent), else how many pairs the
    broad phase proved out of reach."""
    sweeps = sweeps_section(report.sections)
    if not sweeps:
        return []
    grids = sorted({int(s.grid_points or 0) for s in sweeps})
    proven = all(s.proven for s in sweeps)
    how = f"clearance proven between {'/'.join(map(str, grids))} grid points" if proven else "some sweeps sampled only"
    lines = [f"Sweeps (each continuous joint over a full turn, the rest at the default pose; {how}):"]
    width = max(len(s.joint) for s in sweeps)
    for sweep in sweeps:
        moving = len(sweep.moving_links)
        head = f"  {sweep.joint:<{width}}  {moving:>2} moving link{' ' if moving == 1 else 's'}  "
        tail = "" if sweep.proven else " (sampled, not proven)"
        contact = [p for p in sweep.pairs if p.colliding_ranges and not p.adjacent]
        if contact:
            shown = "; ".join(_pair_text(p) for p in sorted(contact, key=lambda p: p.links))
            lines.append(f"{head}in contact: {shown}{tail}")
        elif sweep.pairs:
            others = [p for p in sweep.pairs if not p.adjacent] or sweep.pairs
            lines.append(f"{head}closest {_pair_text(min(others, key=_closest_first))}{tail}")
        else:
            lines.append(f"{head}all {plural(sweep.far_pairs or 0, 'pair')} out of reach{tail}")
    return lines


def matrix_lines(report: Report) -> list[str]:
    """One line of class counts (certified and witness-found pairs called out) and where to
    get the SRDF."""
    matrix = matrix_section(report.sections)
    if matrix is None:
        return []
    pairs = matrix.pairs
    counts = Counter(p.cls for p in pairs)
    certified = sum(1 for p in pairs if p.certified)
    searched = sum(1 for p in pairs if p.witness is not None and p.witness.source == "search")
    parts = []
    for cls in PairClass:
        text = f"{counts.get(cls.value, 0)} {cls.value}"
        if cls is PairClass.NEVER and certified:
            text += f" ({certified} certified)"
        if cls is PairClass.ENABLED and searched:
            text += f" ({searched} found by the witness search)"
        parts.append(text)
    semantics = ", pinocchio semantics" if matrix.semantics == "pinocchio" else ""
    return [
        f"Collision matrix ({matrix.samples} samples, seed {matrix.seed}, {matrix.backend}"
        f"{semantics}): "
        f"{len(pairs)} pairs: " + ", ".join(parts),
        "  write it as an SRDF with: geomcheck matrix PATH --srdf-out FILE",
    ]
