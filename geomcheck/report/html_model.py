"""The view model of the HTML report: plain dicts and ready markup, built from a Report.

Everything the templates show is decided here (order, grouping, formatting, pictures);
the templates only lay it out. The input is the report alone (sections as documented in
docs/report-schema.md), so a stored report renders exactly like a fresh one.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.errors import UsageError
from geomcheck.report.html_common import Anchors, count_label, plural, subjects_of
from geomcheck.report.html_scene import view3d_model
from geomcheck.report.html_sections import inertia_model, links_model, listed_links, matrix_model, sweeps_model
from geomcheck.report.model import Report
from geomcheck.report.summary import fix_command, fixable_text
from geomcheck.rules import FAMILY_TITLES, get_rule

EXCERPTS_OPEN_UP_TO = 20  # findings; with more, source excerpts start collapsed


def location_text(d: Diagnostic) -> str | None:
    loc = d.location
    if loc is None:
        return None
    if loc.line is not None:
        return str(loc)
    if loc.expanded_line is not None:
        return f"{loc.file} (expanded URDF line {loc.expanded_line})"
    return loc.file


def excerpt_lines(d: Diagnostic) -> list[dict[str, Any]]:
    """The excerpt with the located line marked (the file's line, else the expanded one)."""
    if not d.excerpt or d.location is None:
        return []
    numbers = {n for n, _ in d.excerpt}
    here = d.location.line if d.location.line in numbers else d.location.expanded_line
    width = len(str(max(numbers)))
    return [{"number": str(n).rjust(width), "text": t, "here": n == here} for n, t in d.excerpt]


def findings_model(report: Report, anchor: Anchors) -> list[dict[str, Any]]:
    out = []
    for number, d in enumerate(sorted(report.diagnostics, key=Diagnostic.sort_key), start=1):
        subject_links = subjects_of(d)
        out.append(
            {
                "id": f"finding-{number}",
                "severity": d.severity.value,
                "code": d.code,
                "name": d.name,
                "rule_href": "#" + anchor("rule", d.code),
                "subject": d.subject,
                "about": d.about,
                "links": [anchor.link_ref(x) for x in subject_links],
                "message": d.message,
                "help": d.help,
                "fix": None
                if (fix := d.fix) is None
                else {"applicability": fix.applicability.value, "title": fix.title, "command": fix_command(d)},
                "location": location_text(d),
                "excerpt": excerpt_lines(d),
            }
        )
    return out


def finding_groups(findings: Sequence[dict[str, Any]], anchor: Anchors) -> list[dict[str, Any]]:
    """Consecutive findings of one rule and severity, with their common help when they share one."""
    groups: list[dict[str, Any]] = []
    for f in findings:
        if groups and groups[-1]["code"] == f["code"] and groups[-1]["severity"] == f["severity"]:
            groups[-1]["findings"].append(f)
            continue
        groups.append(
            {
                "id": anchor("group", f"{f['code']}-{f['severity']}"),
                "code": f["code"],
                "name": f["name"],
                "severity": f["severity"],
                "rule_href": f["rule_href"],
                "findings": [f],
            }
        )
    for group in groups:
        helps = {f["help"] for f in group["findings"]}
        group["help"] = helps.pop() if len(helps) == 1 else None
        group["count"] = plural(len(group["findings"]), "finding")
    return groups


def rules_model(report: Report, anchor: Anchors) -> list[dict[str, Any]]:
    """Documentation of the rules that occur in the report, by code."""
    out = []
    for code in sorted({d.code for d in report.diagnostics}):
        names = sorted({d.name for d in report.diagnostics if d.code == code})
        try:
            rule = get_rule(code)
        except UsageError:  # a stored report from another version may name a rule this one lacks
            out.append({"id": anchor("rule", code), "code": code, "name": names[0], "known": False})
            continue
        out.append(
            {
                "id": anchor("rule", code),
                "code": rule.code,
                "name": rule.name,
                "known": True,
                "severity": rule.severity.value,
                "family": FAMILY_TITLES.get(rule.family, rule.family),
                "summary": rule.summary,
                "what": rule.what,
                "why": rule.why,
                "example": rule.example,
                "fix": rule.fix,
            }
        )
    return out


def options_model(report: Report) -> list[dict[str, str]]:
    """What was asked, as label/value pairs (only what differs from nothing)."""
    opts = report.options
    out = []
    if opts.get("args"):
        out.append({"label": "xacro args", "value": " ".join(f"{k}={v}" for k, v in opts["args"].items())})
    if opts.get("srdf"):
        out.append({"label": "SRDF", "value": str(opts["srdf"])})
    if opts.get("backend"):
        out.append({"label": "backend", "value": str(opts["backend"])})
    if "sweep" in opts:
        out.append({"label": "sweep", "value": "on" if opts["sweep"] else "off"})
    if "matrix" in opts:
        matrix = "off"
        if opts["matrix"]:
            matrix = f"{opts.get('samples')} samples, seed {opts.get('seed')}"
        out.append({"label": "matrix", "value": matrix})
    if opts.get("pose_name"):
        out.append({"label": "pose", "value": str(opts["pose_name"])})
    elif opts.get("pose"):
        out.append({"label": "pose", "value": " ".join(f"{k}={v}" for k, v in opts["pose"].items())})
    return out


def page_model(report: Report) -> dict[str, Any]:
    """Everything the page template needs."""
    anchor = Anchors(listed_links(report))
    findings = findings_model(report, anchor)
    links = links_model(report, findings, anchor)
    view3d = view3d_model(report, findings)
    sweeps = sweeps_model(report, anchor)
    matrix = matrix_model(report, anchor)
    inertia = inertia_model(report, anchor)
    rules = rules_model(report, anchor)
    skipped = [{"check": s.check, "subject": s.subject or "robot", "reason": s.reason} for s in report.skipped]
    counts = report.counts
    sections = [
        ("findings", "Findings", len(findings)),
        ("skipped", "Skipped checks", len(skipped)),
        ("view3d", "3D view", len(view3d["findings"]) if view3d else 0),
        ("links", "Links", len(links)),
        ("sweeps", "Casters and wheels", len(sweeps)),
        ("matrix", "Collision matrix", matrix["pairs"] if matrix else 0),
        ("inertia", "Inertia", len(inertia)),
        ("rules", "Rules", len(rules)),
    ]
    present = {"findings": True, "skipped": bool(skipped), "links": bool(links), "sweeps": "sweeps" in report.sections}
    present["view3d"] = view3d is not None
    present |= {"matrix": matrix is not None, "inertia": "inertia" in report.sections, "rules": bool(rules)}
    robot = report.robot
    return {
        "title": f"{robot.name}: geomcheck report",
        "robot": robot,
        "created": report.created,
        "version": report.tool_version,
        "schema": report.schema,
        "verdict": "fail" if report.failed else "pass",
        "fail_on": report.fail_on.value,
        "counts": [
            {"severity": s.value, "count": counts[s.value], "label": count_label(s, counts[s.value])} for s in Severity
        ],
        "fixable": fixable_text(report),
        "options": options_model(report),
        "nav": [{"id": key, "title": t, "count": n} for key, t, n in sections if present[key]],
        "present": present,
        "findings": findings,
        "groups": finding_groups(findings, anchor),
        "excerpts_open": len(findings) <= EXCERPTS_OPEN_UP_TO,
        "skipped": skipped,
        "view3d": view3d,
        "links": links,
        "links_open": sum(1 for link in links if link["open"]),
        "sweeps": sweeps,
        "matrix": matrix,
        "inertia": inertia,
        "inertia_flagged": sum(1 for r in inertia if r["flags"]),
        "rules": rules,
    }
