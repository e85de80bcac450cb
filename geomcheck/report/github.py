"""GitHub Actions workflow commands: one ``::error``/``::warning``/``::notice`` annotation per
finding (shown on the pull request's changed files), then the plain summary.

Paths are the report's display paths, relative to the folder geomcheck ran in: run it
from the repository root for the annotations to land on the right files.
"""

from __future__ import annotations

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.report.model import Report
from geomcheck.report.summary import change_lines, finding_file, summary_line

LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def escape_data(text: str) -> str:
    """A command's message, escaped as @actions/core does."""
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    """A command property value (file, title), escaped as @actions/core does."""
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def annotation(d: Diagnostic, report: Report) -> str:
    props = [f"file={escape_property(finding_file(d, report))}"]
    if d.location is not None and d.location.line is not None:
        props.append(f"line={d.location.line}")
        if d.location.column is not None:
            props.append(f"col={d.location.column}")
    props.append(f"title={escape_property(f'{d.code} {d.name}')}")
    message = f"{d.subject}: {d.message}\nhelp: {d.help}"
    return f"::{LEVELS[d.severity]} {','.join(props)}::{escape_data(message)}"


def render(report: Report) -> str:
    lines = [annotation(d, report) for d in report.diagnostics]
    lines.extend(change_lines(report))
    lines.append(summary_line(report))
    return "\n".join(lines) + "\n"
