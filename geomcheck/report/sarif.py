"""SARIF 2.1.0, as GitHub code scanning reads it.

``tool.driver.rules`` lists every registered rule with its documentation (help as text and
Markdown) and default level; each result has ``ruleId``/``ruleIndex``, ``level``, the
message, a physical location relative to ``%SRCROOT%`` (the folder geomcheck ran in: the
repository root in CI) and ``partialFingerprints`` from :attr:`Diagnostic.fingerprint`, so
code scanning tracks a finding across commits that move it. Checks that could not run are
tool execution notifications.
"""

from __future__ import annotations

import json
from typing import Any
from urllib.parse import quote

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.report.model import Report
from geomcheck.report.rules_markdown import rule_body
from geomcheck.report.summary import finding_file
from geomcheck.rules import FAMILIES, FAMILY_TITLES, Rule, all_rules

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
SARIF_VERSION = "2.1.0"
FINGERPRINT_KEY = "geomcheck/v1"
LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def rule_descriptor(rule: Rule) -> dict[str, Any]:
    text = f"{rule.what}\n\nWhy it matters: {rule.why}\n\nExample:\n{rule.example}\n\nFix: {rule.fix}"
    return {
        "id": rule.code,
        "name": rule.name,
        "shortDescription": {"text": rule.summary},
        "fullDescription": {"text": rule.what},
        "help": {"text": text, "markdown": rule_body(rule)},
        "defaultConfiguration": {"level": LEVELS[rule.severity]},
        "properties": {"tags": [FAMILY_TITLES.get(rule.family, rule.family), FAMILIES.get(rule.family, "")]},
    }


def unregistered_descriptor(d: Diagnostic) -> dict[str, Any]:
    """A descriptor for a code the registry no longer has (a stored report of an older version)."""
    return {
        "id": d.code,
        "name": d.name,
        "shortDescription": {"text": d.name},
        "fullDescription": {"text": d.name},
        "help": {"text": d.help, "markdown": d.help},
        "defaultConfiguration": {"level": LEVELS[d.severity]},
    }


def artifact_uri(path: str) -> str:
    """A relative URI reference for a display path (posix, percent-encoded)."""
    return quote(path, safe="/._-~")


def location(d: Diagnostic, report: Report) -> dict[str, Any]:
    region: dict[str, Any] = {"startLine": 1}
    if d.location is not None and d.location.line is not None:
        region = {"startLine": d.location.line}
        if d.location.column is not None:
            region["startColumn"] = d.location.column
    physical = {
        "artifactLocation": {"uri": artifact_uri(finding_file(d, report)), "uriBaseId": "%SRCROOT%"},
        "region": region,
    }
    logical = [{"name": name, "kind": "element"} for name in (*(d.links or ()), d.link, d.joint) if name]
    out: dict[str, Any] = {"physicalLocation": physical}
    if logical:
        out["logicalLocations"] = logical
    return out


def result(d: Diagnostic, report: Report, index: dict[str, int]) -> dict[str, Any]:
    return {
        "ruleId": d.code,
        "ruleIndex": index[d.code],
        "level": LEVELS[d.severity],
        "message": {"text": f"{d.subject}: {d.message} (help: {d.help})"},
        "locations": [location(d, report)],
        "partialFingerprints": {FINGERPRINT_KEY: d.fingerprint},
        "properties": {
            "name": d.name,
            "subject": d.subject,
            "about": d.about,
            "data": dict(d.data),
        },
    }


def sarif_log(report: Report) -> dict[str, Any]:
    rules = [rule_descriptor(r) for r in all_rules()]
    index = {r["id"]: i for i, r in enumerate(rules)}
    for d in report.diagnostics:
        if d.code not in index:
            index[d.code] = len(rules)
            rules.append(unregistered_descriptor(d))
    notifications = [
        {
            "level": "note",
            "message": {"text": f"skipped {s.check}{f' for {s.subject}' if s.subject else ''}: {s.reason}"},
        }
        for s in report.skipped
    ]
    run: dict[str, Any] = {
        "tool": {
            "driver": {
                "name": "geomcheck",
                "version": report.tool_version,
                "semanticVersion": report.tool_version,
                "rules": rules,
            }
        },
        "invocations": [{"executionSuccessful": True, "toolExecutionNotifications": notifications}],
        "results": [result(d, report, index) for d in report.diagnostics],
        "columnKind": "unicodeCodePoints",
        "properties": {"robot": report.robot.name, "source": report.robot.source, "verdict": _verdict(report)},
    }
    for key in ("diff", "baseline"):
        if key in report.sections:
            run["properties"][key] = report.sections[key]
    return {"$schema": SARIF_SCHEMA, "version": SARIF_VERSION, "runs": [run]}


def _verdict(report: Report) -> str:
    return "fail" if report.failed else "pass"


def render(report: Report) -> str:
    return json.dumps(sarif_log(report), indent=2, ensure_ascii=False, allow_nan=False) + "\n"
