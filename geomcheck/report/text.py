"""Text: one line per finding with its help, then a summary (for people at a terminal)."""

from __future__ import annotations

from geomcheck.report.model import Report


def render(report: Report) -> str:
    lines = []
    for d in report.diagnostics:
        where = str(d.location) if d.location else report.robot.source
        lines.append(f"{where}: {d.code} [{d.severity.value}] {d.subject}: {d.message}")
        lines.append(f"    help: {d.help}")
    for s in report.skipped:
        subject = f" for {s.subject}" if s.subject else ""
        lines.append(f"skipped {s.check}{subject}: {s.reason}")
    counts = report.counts
    r = report.robot
    lines.append(
        f"{r.name}: {r.links} links, {r.joints} joints, {r.meshes_loaded}/{r.meshes_total} meshes loaded; "
        f"{counts['error']} errors, {counts['warning']} warnings, {counts['info']} info "
        f"-> {'FAIL' if report.failed else 'PASS'} (fail on {report.fail_on.value})"
    )
    return "\n".join(lines) + "\n"
