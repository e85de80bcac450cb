"""``--statistics``: how many findings each rule produced, most frequent first, with a header
and a fixable column (as ruff prints them)."""

from __future__ import annotations

import json
from collections import Counter

from geomcheck.report.model import Report
from geomcheck.report.summary import FIXABLE_MARKER, fixable_text

HEADER = ("count", "code", "name", "severity", "fixable")


def rows(report: Report) -> list[dict[str, object]]:
    """``{code, name, severity, count, fixable}`` per rule and severity with findings, by
    count then code; ``fixable`` counts the findings ``geomcheck fix`` can fix (with
    ``--unsafe-fixes`` for some)."""
    counts = Counter((d.code, d.name, d.severity.value) for d in report.diagnostics)
    fixable = Counter((d.code, d.name, d.severity.value) for d in report.diagnostics if d.fix is not None)
    ordered = sorted(counts.items(), key=lambda item: (-item[1], item[0]))
    return [{"code": c, "name": n, "severity": s, "count": k, "fixable": fixable[c, n, s]} for (c, n, s), k in ordered]


def render_text(report: Report) -> str:
    table = rows(report)
    if not table:
        return "no findings\n"
    cells = [HEADER] + [
        (
            str(r["count"]),
            str(r["code"]),
            str(r["name"]),
            str(r["severity"]),
            f"{FIXABLE_MARKER} {r['fixable']}" if r["fixable"] else "",
        )
        for r in table
    ]
    widths = [max(len(row[i]) for row in cells) for i in range(len(HEADER))]
    lines = [
        "  ".join(cell.rjust(widths[i]) if i == 0 else cell.ljust(widths[i]) for i, cell in enumerate(row)).rstrip()
        for row in cells
    ]
    total = sum(int(str(r["count"])) for r in table)
    lines.append(f"Found {total} finding{'s' if total != 1 else ''}.")
    fixable = fixable_text(report)
    if fixable:
        lines.append(fixable)
    return "\n".join(lines) + "\n"


def render_json(report: Report) -> str:
    return json.dumps(rows(report), indent=2) + "\n"
