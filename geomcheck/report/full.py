"""Full: each finding with its rule name, the source excerpt around its location and the
help, then the sweep and matrix results, skipped checks and the summary line (the default
for people at a terminal)."""

from __future__ import annotations

from geomcheck.diagnostics import Diagnostic
from geomcheck.report.model import Report
from geomcheck.report.sections_text import matrix_lines, sweep_lines
from geomcheck.report.summary import (
    FIXABLE_MARKER,
    change_lines,
    excerpt_target,
    fix_command,
    location_label,
    skipped_lines,
    summary_line,
)


def excerpt_lines(d: Diagnostic) -> list[str]:
    """The excerpt with a line-number gutter and a caret under the located line."""
    if not d.excerpt:
        return []
    width = max(len(str(n)) for n, _ in d.excerpt)
    pad = " " * width
    out = [f"{pad} |"]
    target = excerpt_target(d)
    for number, text in d.excerpt:
        out.append(f"{number:>{width}} | {text}".rstrip())
        if number == target:
            indent = (d.location.column - 1) if d.location and d.location.column else len(text) - len(text.lstrip())
            out.append(f"{pad} | {' ' * indent}^ {d.name}")
    out.append(f"{pad} |")
    return out


def render_diagnostic(d: Diagnostic, where: str) -> list[str]:
    fix = d.fix
    marker = f" {FIXABLE_MARKER}" if fix is not None else ""
    lines = [f"{where}: {d.code} [{d.severity.value}] {d.name}{marker}", f"  {d.subject}: {d.message}"]
    excerpt = excerpt_lines(d)
    target = excerpt_target(d)
    if excerpt and d.location is not None and target is not None and target != d.location.line:
        lines.append(f"  (expanded URDF, line {target})")
    lines.extend(f"  {line}" for line in excerpt)
    lines.append(f"  = help: {d.help}")
    if fix is not None:
        lines.append(f"  = fix ({fix.applicability.value}): {fix.title} ({fix_command(d)})")
    return lines


def render(report: Report) -> str:
    lines: list[str] = []
    for d in report.diagnostics:
        lines.extend(render_diagnostic(d, location_label(d, report)))
        lines.append("")
    for block in (sweep_lines(report), matrix_lines(report)):
        if block:
            lines.extend([*block, ""])
    extra = change_lines(report) + skipped_lines(report)
    if extra:
        lines.extend([*extra, ""])
    lines.append(summary_line(report))
    return "\n".join(lines) + "\n"
