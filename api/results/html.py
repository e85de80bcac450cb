"""The HTML view of a stored report: the library's HTML renderer when it has one, else a plain page."""

from __future__ import annotations

import html
import re
from typing import Any

from geomcheck.report import FORMATS, Report, render

_UNSAFE_FILENAME = re.compile(r"[^A-Za-z0-9._-]+")


def download_name(robot: str | None, suffix: str) -> str:
    """``<robot><suffix>`` with every character outside ``[A-Za-z0-9._-]`` replaced (a header-safe filename)."""
    stem = _UNSAFE_FILENAME.sub("_", robot or "").strip("._") or "robot"
    return f"{stem[:100]}{suffix}"


def report_html(data: dict[str, Any]) -> str:
    """The report ``data`` (a ``geomcheck.report/1`` document) as an HTML page."""
    if "html" in FORMATS:
        return render(Report.from_dict(data), "html")
    return plain_page(data)


def _cell(value: object) -> str:
    return html.escape("" if value is None else str(value))


def plain_page(data: dict[str, Any]) -> str:
    """A self-contained page: robot summary, verdict, every finding with its help, skipped checks."""
    robot = data["robot"]
    summary = data["summary"]
    rows = []
    for d in data["diagnostics"]:
        loc = d.get("location") or {}
        where = loc.get("file", "") + (f":{loc['line']}" if loc.get("line") else "")
        subject = " / ".join(d["links"]) if d.get("links") else d.get("joint") or d.get("link") or "robot"
        rows.append(
            f'<tr class="{_cell(d["severity"])}"><td>{_cell(d["code"])}<br><small>{_cell(d["name"])}</small></td>'
            f"<td>{_cell(d['severity'])}</td><td>{_cell(subject)}</td><td><code>{_cell(where)}</code></td>"
            f"<td>{_cell(d['message'])}<br><small>help: {_cell(d['help'])}</small></td></tr>"
        )
    skipped = "".join(
        f"<li>{_cell(s['check'])}{' for ' + _cell(s['subject']) if s['subject'] else ''}: {_cell(s['reason'])}</li>"
        for s in data.get("skipped", [])
    )
    title = f"{robot['name']}: geomcheck report"
    findings = (
        "<table><thead><tr><th>rule</th><th>severity</th><th>subject</th><th>location</th><th>finding</th>"
        f"</tr></thead><tbody>{''.join(rows)}</tbody></table>"
        if rows
        else "<p>No findings.</p>"
    )
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{_cell(title)}</title>
<style>
body {{ font-family: system-ui, sans-serif; margin: 2em; color: #222; }}
table {{ border-collapse: collapse; width: 100%; }}
th, td {{ border-bottom: 1px solid #ddd; padding: 0.4em; text-align: left; vertical-align: top; }}
tr.error td:nth-child(2) {{ color: #b00020; font-weight: bold; }}
tr.warning td:nth-child(2) {{ color: #9a6700; }}
.verdict-fail {{ color: #b00020; }} .verdict-pass {{ color: #1a7f37; }}
</style></head>
<body>
<h1>{_cell(robot["name"])}</h1>
<p><code>{_cell(robot["source"])}</code>: {_cell(robot["links"])} links, {_cell(robot["joints"])} joints,
{_cell(robot.get("meshes_loaded", 0))}/{_cell(robot.get("meshes_total", 0))} meshes loaded.</p>
<p class="verdict-{_cell(data["verdict"])}"><strong>{_cell(data["verdict"]).upper()}</strong>
(fail on {_cell(data["fail_on"])}): {summary["error"]} errors, {summary["warning"]} warnings,
{summary["info"]} info.</p>
<h2>Findings</h2>
{findings}
<h2>Skipped checks</h2>
{"<ul>" + skipped + "</ul>" if skipped else "<p>None.</p>"}
<footer><small>{_cell(data["tool"]["name"])} {_cell(data["tool"]["version"])}, {_cell(data["created"])},
schema {_cell(data["schema"])}</small></footer>
</body></html>
"""
