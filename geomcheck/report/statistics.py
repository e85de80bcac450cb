"""``--statistics``: how many findings each rule produced, most frequent first (like ruff)."""

from __future__ import annotations

import json
from collections import Counter

from geomcheck.report.model import Report


def rows(report: Report) -> list[dict[str, object]]:
    """``{code, name, severity, count}`` per rule with findings, by count then code."""
    counts = Counter((d.code, d.name, d.severity.value) for d in report.diagnostics)
    ordered = sorted(counts.items(), key=lambda item: (-item[1], item[0]))
    return [{"code": c, "name": n, "severity": s, "count": k} for (c, n, s), k in ordered]


def render_text(report: Report) -> str:
    table = rows(report)
    if not table:
        return "no findings\n"
    width = max(len(str(r["count"])) for r in table)
    name_width = max(len(str(r["name"])) for r in table)
    lines = [f"{r['count']:>{width}}  {r['code']}  {r['name']:<{name_width}}  {r['severity']}" for r in table]
    return "\n".join(line.rstrip() for line in lines) + "\n"


def render_json(report: Report) -> str:
    return json.dumps(rows(report), indent=2) + "\n"
