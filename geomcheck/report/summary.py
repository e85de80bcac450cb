"""Pieces the line-oriented formats share: where a finding is, the summary line, and the
lines about a baseline or a diff (``baseline`` and ``diff`` report sections)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from geomcheck.diagnostics import Diagnostic
from geomcheck.report.model import Report
from geomcheck.report.section_changes import Regression, baseline_section, diff_section


def finding_file(d: Diagnostic, report: Report) -> str:
    """The file a finding points at: its location's, else the description's root file."""
    return d.location.file if d.location else report.robot.source


def excerpt_target(d: Diagnostic) -> int | None:
    """The excerpt's located line. The pipeline centres the excerpt on the line in the source
    file when it has that file's text, else on the line in the expanded document: of the
    two, the one in range and nearest the middle."""
    if d.location is None or not d.excerpt:
        return None
    first, last = d.excerpt[0][0], d.excerpt[-1][0]
    candidates = [c for c in (d.location.line, d.location.expanded_line) if c is not None and first <= c <= last]
    return min(candidates, key=lambda c: abs((c - first) - (last - c)), default=None)


def column(d: Diagnostic) -> int:
    """The 1-based column of a finding: its location's, else where the text of its line
    starts (the element's tag, when the excerpt shows the line), else 1."""
    if d.location is not None and d.location.column is not None:
        return d.location.column
    target = excerpt_target(d)
    if d.location is not None and target is not None and target == d.location.line:
        text = dict(d.excerpt)[target]
        return len(text) - len(text.lstrip()) + 1
    return 1


def location_label(d: Diagnostic, report: Report) -> str:
    """``file:line:col``; just ``file`` when the line is unknown."""
    file = finding_file(d, report)
    if d.location is None or d.location.line is None:
        return file
    return f"{file}:{d.location.line}:{column(d)}"


def _plural(count: int, word: str) -> str:
    return f"{count} {word}{'' if count == 1 else 's'}"


FIXABLE_MARKER = "[*]"  # as ruff marks findings it can fix


def fix_marker(d: Diagnostic) -> str:
    """``"[*] "`` before the message of a finding ``geomcheck fix`` can fix, else ``""``."""
    return f"{FIXABLE_MARKER} " if d.fix is not None else ""


def fixable_counts(report: Report) -> tuple[int, int]:
    """(findings with a safe fix, findings with an unsafe fix)."""
    kinds = [f.applicability.value for d in report.diagnostics if (f := d.fix) is not None]
    return kinds.count("safe"), kinds.count("unsafe")


def fix_command(d: Diagnostic) -> str | None:
    """The command that applies ``d``'s fix, when it has one."""
    fix = d.fix
    if fix is None:
        return None
    return "geomcheck fix" + (" --unsafe-fixes" if fix.applicability.value == "unsafe" else "")


def fixable_text(report: Report) -> str | None:
    """``[*] 2 fixable with geomcheck fix, 14 more with --unsafe-fixes``; ``None`` when nothing is."""
    safe, unsafe = fixable_counts(report)
    if not safe and not unsafe:
        return None
    if not safe:
        return f"{FIXABLE_MARKER} {unsafe} fixable with geomcheck fix --unsafe-fixes"
    more = f" ({unsafe} more with --unsafe-fixes)" if unsafe else ""
    return f"{FIXABLE_MARKER} {safe} fixable with geomcheck fix{more}"


def summary_line(report: Report) -> str:
    """One line: robot, counts per severity, verdict; baseline and diff counts when present."""
    r, counts = report.robot, report.counts
    parts = [
        f"{r.name}: {_plural(r.links, 'link')}, {_plural(r.joints, 'joint')}, "
        f"{r.meshes_loaded}/{r.meshes_total} meshes loaded",
        f"{_plural(counts['error'], 'error')}, {_plural(counts['warning'], 'warning')}, {counts['info']} info",
    ]
    fixable = fixable_text(report)
    if fixable:
        parts.append(fixable)
    baseline = baseline_section(report.sections)
    if baseline is not None:
        stale = len(baseline.stale)
        parts.append(
            f"baseline {baseline.file}: {baseline.matched} known, {stale} no longer occur"
            + ("" if stale == 0 else " (update it with --write-baseline)")
        )
    diff = diff_section(report.sections)
    if diff is not None:
        parts.append(f"against {diff.base}: {diff.new} new, {len(diff.fixed)} fixed, {len(diff.regressions)} regressed")
    verdict = "FAIL" if report.failed else "PASS"
    return "; ".join(parts) + f" -> {verdict} (fail on {report.fail_on.value})"


def _subject(d: Mapping[str, Any]) -> str:
    if d.get("links"):
        return f"links {d['links'][0]} / {d['links'][1]}"
    if d.get("joint"):
        return f"joint {d['joint']}"
    if d.get("link"):
        return f"link {d['link']}"
    return "robot"


def _num(value: Any) -> str:
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def _regressed_line(r: Regression) -> str:
    d = r.diagnostic
    changes = [f"{m.name} {_num(m.before)} -> {_num(m.after)}" for m in r.metrics]
    if r.severity_before != d["severity"]:
        changes.insert(0, f"severity {r.severity_before} -> {d['severity']}")
    return f"regressed: {d['code']} {_subject(d)}: {', '.join(changes)}"


def change_lines(report: Report) -> list[str]:
    """``fixed:`` and ``regressed:`` lines of a diff, ``no longer occurs:`` lines of a baseline."""
    lines = []
    diff = diff_section(report.sections)
    if diff is not None:
        if not diff.base_exists:
            lines.append(f"note: the description does not exist at {diff.base}; every finding is new")
        if diff.base_note:
            lines.append(f"note: {diff.base_note}")
        lines += [f"fixed: {d['code']} {_subject(d)}: {d['message']}" for d in diff.fixed]
        lines += [_regressed_line(r) for r in diff.regressions]
    baseline = baseline_section(report.sections)
    if baseline is not None:
        lines += [f"no longer occurs: {e.code} {e.subject}: {e.message}" for e in baseline.stale]
    return lines


def skipped_lines(report: Report) -> list[str]:
    return [f"skipped {s.check}{f' for {s.subject}' if s.subject else ''}: {s.reason}" for s in report.skipped]
