"""Concise: ``file:line:col: CODE [severity] subject: message``, one finding a line, then
the summary line (the format editors and CI logs parse)."""

from __future__ import annotations

from geomcheck.report.model import Report
from geomcheck.report.summary import change_lines, fix_marker, location_label, summary_line


def render(report: Report) -> str:
    lines = [
        f"{location_label(d, report)}: {d.code} [{d.severity.value}] {d.subject}: {fix_marker(d)}{d.message}"
        for d in report.diagnostics
    ]
    lines.extend(change_lines(report))
    lines.append(summary_line(report))
    return "\n".join(lines) + "\n"
