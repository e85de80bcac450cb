"""Every output format on a hand-built report: concise, full, github, sarif, junit, statistics."""

from __future__ import annotations

import json
from typing import Any

import attr
import jsonschema
import pytest
import sarif_om
from junitparser import Failure, JUnitXml

from geomcheck.diagnostics import Diagnostic, Severity, SkippedCheck
from geomcheck.model import SourceLocation
from geomcheck.report import FORMATS, render
from geomcheck.report import statistics as stats
from geomcheck.report.github import escape_data, escape_property
from geomcheck.report.model import Report, RobotSummary
from geomcheck.report.rules_markdown import prose
from geomcheck.rules import all_rules


def finding(
    code: str,
    severity: Severity,
    message: str,
    *,
    link: str | None = None,
    joint: str | None = None,
    links: tuple[str, str] | None = None,
    location: SourceLocation | None = None,
    excerpt: tuple[tuple[int, str], ...] = (),
    about: str = "",
) -> Diagnostic:
    return Diagnostic(
        code=code,
        name=f"rule-{code.lower()}",
        severity=severity,
        message=message,
        help=f"fix {code}",
        link=link,
        joint=joint,
        links=links,
        about=about,
        location=location,
        data={"coverage": 0.31},
        excerpt=excerpt,
    )


def sample_report(fail_on: Severity = Severity.ERROR) -> Report:
    diagnostics = (
        finding(
            "GC301",
            Severity.ERROR,
            "collision[0] covers 31% of the mesh, 100% wanted",
            link="base_link",
            about="collision[0]",
            location=SourceLocation("urdf/base.urdf.xacro", 12, None, 40),
            excerpt=((10, "  <collision>"), (11, '    <origin xyz="0 0 0.07"/>'), (12, '    <box size="1 1 1"/>')),
        ),
        finding(
            "GC120",
            Severity.WARNING,
            "axis 0,0,2: 50% too long, see: the spec",
            joint="fl_caster_rotation_joint",
            about="axis",
            location=SourceLocation("urdf/caster.urdf.xacro", 7, 5, 88),
        ),
        finding("GC401", Severity.INFO, "clearance 3 mm", links=("base_link", "fl_caster_rotation_link")),
    )
    return Report(
        robot=RobotSummary("pr2_base", "robots/pr2_base.urdf.xacro", 3, 2, 2, 2),
        diagnostics=diagnostics,
        tool_version="0.1.0",
        created="2026-01-01T00:00:00Z",
        fail_on=fail_on,
        skipped=(SkippedCheck("fit", "base_laser_link", "no visual mesh loaded"),),
        sections={"links": [{"link": "base_link"}, {"link": "fl_caster_rotation_link"}, {"link": "base_laser_link"}]},
    )


def test_every_format_is_registered_and_text_is_full() -> None:
    assert {"full", "concise", "json", "github", "sarif", "junit", "text"} <= set(FORMATS)
    assert render(sample_report(), "text") == render(sample_report(), "full")


def test_concise_is_one_line_per_finding_then_summary() -> None:
    lines = render(sample_report(), "concise").splitlines()
    assert lines[0] == (
        "urdf/base.urdf.xacro:12:5: GC301 [error] link base_link: collision[0] covers 31% of the mesh, 100% wanted"
    )
    assert lines[1].startswith("urdf/caster.urdf.xacro:7:5: GC120 [warning] joint fl_caster_rotation_joint: axis")
    assert (
        lines[2] == "robots/pr2_base.urdf.xacro: GC401 [info] links base_link / fl_caster_rotation_link: clearance 3 mm"
    )
    assert lines[3] == (
        "pr2_base: 3 links, 2 joints, 2/2 meshes loaded; 1 error, 1 warning, 1 info -> FAIL (fail on error)"
    )
    assert len(lines) == 4


def test_full_shows_excerpt_with_caret_and_help() -> None:
    text = render(sample_report(), "full")
    assert "urdf/base.urdf.xacro:12:5: GC301 [error] rule-gc301" in text
    assert "  link base_link: collision[0] covers 31%" in text
    assert '  12 |     <box size="1 1 1"/>\n     |     ^ rule-gc301\n' in text
    assert "  = help: fix GC301" in text
    assert "skipped fit for base_laser_link: no visual mesh loaded" in text
    assert text.rstrip().endswith("-> FAIL (fail on error)")


def test_github_annotations_one_per_finding_escaped() -> None:
    lines = render(sample_report(), "github").splitlines()
    annotations = [line for line in lines if line.startswith("::")]
    assert len(annotations) == 3
    assert annotations[0] == (
        "::error file=urdf/base.urdf.xacro,line=12,title=GC301 rule-gc301::"
        "link base_link: collision[0] covers 31%25 of the mesh, 100%25 wanted%0Ahelp: fix GC301"
    )
    assert annotations[1].startswith("::warning file=urdf/caster.urdf.xacro,line=7,col=5,title=GC120 rule-gc120::")
    assert "axis 0,0,2: 50%25 too long, see: the spec" in annotations[1]
    assert annotations[2].startswith("::notice file=robots/pr2_base.urdf.xacro,title=GC401 rule-gc401::")
    assert lines[-1].endswith("-> FAIL (fail on error)")


def test_github_escaping_rules() -> None:
    assert escape_data("a%b\r\nc") == "a%25b%0D%0Ac"
    assert escape_property("a:b,c%\n") == "a%3Ab%2Cc%25%0A"


# A focused schema of what SARIF 2.1.0 and GitHub code scanning require of our output.
SARIF_SCHEMA: dict[str, Any] = {
    "$schema": "http://json-schema.org/draft-07/schema#",
    "definitions": {
        "message": {"type": "object", "required": ["text"], "properties": {"text": {"type": "string"}}},
        "multiformat": {
            "type": "object",
            "required": ["text"],
            "properties": {"text": {"type": "string", "minLength": 1}, "markdown": {"type": "string"}},
        },
        "rule": {
            "type": "object",
            "required": ["id", "shortDescription", "fullDescription", "help", "defaultConfiguration"],
            "properties": {
                "id": {"type": "string", "pattern": "^GC[1-9][0-9]{2}$"},
                "name": {"type": "string"},
                "shortDescription": {"$ref": "#/definitions/multiformat"},
                "fullDescription": {"$ref": "#/definitions/multiformat"},
                "help": {
                    "allOf": [{"$ref": "#/definitions/multiformat"}, {"required": ["text", "markdown"]}],
                },
                "defaultConfiguration": {
                    "type": "object",
                    "properties": {"level": {"enum": ["none", "note", "warning", "error"]}},
                },
            },
        },
        "location": {
            "type": "object",
            "required": ["physicalLocation"],
            "properties": {
                "physicalLocation": {
                    "type": "object",
                    "required": ["artifactLocation", "region"],
                    "properties": {
                        "artifactLocation": {
                            "type": "object",
                            "required": ["uri"],
                            "properties": {
                                "uri": {"type": "string", "pattern": "^[^/]"},
                                "uriBaseId": {"const": "%SRCROOT%"},
                            },
                        },
                        "region": {
                            "type": "object",
                            "required": ["startLine"],
                            "properties": {
                                "startLine": {"type": "integer", "minimum": 1},
                                "startColumn": {"type": "integer", "minimum": 1},
                            },
                        },
                    },
                }
            },
        },
        "result": {
            "type": "object",
            "required": ["ruleId", "ruleIndex", "level", "message", "locations", "partialFingerprints"],
            "properties": {
                "ruleId": {"type": "string"},
                "ruleIndex": {"type": "integer", "minimum": 0},
                "level": {"enum": ["none", "note", "warning", "error"]},
                "message": {"$ref": "#/definitions/message"},
                "locations": {"type": "array", "minItems": 1, "items": {"$ref": "#/definitions/location"}},
                "partialFingerprints": {
                    "type": "object",
                    "minProperties": 1,
                    "additionalProperties": {"type": "string"},
                },
            },
        },
    },
    "type": "object",
    "required": ["version", "runs", "$schema"],
    "properties": {
        "version": {"const": "2.1.0"},
        "runs": {
            "type": "array",
            "minItems": 1,
            "items": {
                "type": "object",
                "required": ["tool", "results"],
                "properties": {
                    "tool": {
                        "type": "object",
                        "required": ["driver"],
                        "properties": {
                            "driver": {
                                "type": "object",
                                "required": ["name", "rules"],
                                "properties": {
                                    "name": {"const": "geomcheck"},
                                    "rules": {"type": "array", "items": {"$ref": "#/definitions/rule"}},
                                },
                            }
                        },
                    },
                    "results": {"type": "array", "items": {"$ref": "#/definitions/result"}},
                },
            },
        },
    },
}

# SARIF property -> sarif_om class of its value (objects, or items of arrays)
SARIF_CLASSES: dict[str, type] = {
    "runs": sarif_om.Run,
    "tool": sarif_om.Tool,
    "driver": sarif_om.ToolComponent,
    "rules": sarif_om.ReportingDescriptor,
    "shortDescription": sarif_om.MultiformatMessageString,
    "fullDescription": sarif_om.MultiformatMessageString,
    "help": sarif_om.MultiformatMessageString,
    "defaultConfiguration": sarif_om.ReportingConfiguration,
    "invocations": sarif_om.Invocation,
    "toolExecutionNotifications": sarif_om.Notification,
    "results": sarif_om.Result,
    "message": sarif_om.Message,
    "locations": sarif_om.Location,
    "physicalLocation": sarif_om.PhysicalLocation,
    "artifactLocation": sarif_om.ArtifactLocation,
    "region": sarif_om.Region,
    "logicalLocations": sarif_om.LogicalLocation,
}


def build_sarif_om(cls: type, data: dict[str, Any]) -> Any:
    """Construct the sarif_om object for ``data``: unknown property names and missing
    required properties raise (attrs checks the keyword arguments)."""
    names = {f.metadata["schema_property_name"]: f.name for f in attr.fields(cls)}
    kwargs = {}
    for key, value in data.items():
        assert key in names, f"{cls.__name__} has no property {key!r}"
        if key in SARIF_CLASSES and key != "properties":
            sub = SARIF_CLASSES[key]
            value = [build_sarif_om(sub, v) for v in value] if isinstance(value, list) else build_sarif_om(sub, value)
        kwargs[names[key]] = value
    return cls(**kwargs)


def test_sarif_is_structurally_valid_with_rule_help_and_locations() -> None:
    log = json.loads(render(sample_report(), "sarif"))
    jsonschema.validate(log, SARIF_SCHEMA)
    built = build_sarif_om(sarif_om.SarifLog, log)
    assert built.version == "2.1.0"
    run = log["runs"][0]
    rules = run["tool"]["driver"]["rules"]
    assert [r["id"] for r in rules[: len(all_rules())]] == [r.code for r in all_rules()]
    results = run["results"]
    assert [r["ruleId"] for r in results] == ["GC301", "GC120", "GC401"]
    first = results[0]
    assert first["level"] == "error"
    assert first["locations"][0]["physicalLocation"] == {
        "artifactLocation": {"uri": "urdf/base.urdf.xacro", "uriBaseId": "%SRCROOT%"},
        "region": {"startLine": 12},
    }
    assert first["locations"][0]["logicalLocations"] == [{"name": "base_link", "kind": "element"}]
    assert first["partialFingerprints"]["geomcheck/v1"] == sample_report().diagnostics[0].fingerprint
    assert results[1]["level"] == "warning"
    assert results[1]["locations"][0]["physicalLocation"]["region"] == {"startLine": 7, "startColumn": 5}
    assert results[2]["level"] == "note"
    # a finding without a location points at the root file
    assert results[2]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "robots/pr2_base.urdf.xacro"
    for result in results:
        rule = rules[result["ruleIndex"]]
        assert rule["id"] == result["ruleId"]
    notes = run["invocations"][0]["toolExecutionNotifications"]
    assert notes == [{"level": "note", "message": {"text": "skipped fit for base_laser_link: no visual mesh loaded"}}]


def test_sarif_rules_carry_help_markdown() -> None:
    rules = all_rules()
    if not rules:
        pytest.skip("no rules registered yet")
    log = json.loads(render(sample_report(), "sarif"))
    descriptor = log["runs"][0]["tool"]["driver"]["rules"][0]
    assert descriptor["help"]["markdown"].startswith("**What it does.**")
    assert descriptor["shortDescription"]["text"] == rules[0].summary
    assert descriptor["defaultConfiguration"]["level"] in ("error", "warning", "note")


def test_sarif_uri_is_percent_encoded() -> None:
    report = sample_report()
    d = finding("GC301", Severity.ERROR, "m", link="a", location=SourceLocation("my robot/base #1.urdf", 3))
    log = json.loads(render(Report(report.robot, (d,), "0.1.0", report.created), "sarif"))
    uri = log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
    assert uri == "my%20robot/base%20%231.urdf"


def test_junit_parses_with_a_case_per_subject_and_family() -> None:
    xml = JUnitXml.fromstring(render(sample_report(), "junit").encode())
    suites = {s.name: s for s in xml}
    assert list(suites) == [
        "GC1xx Syntax and structure",
        "GC2xx Meshes and files",
        "GC3xx Collision-vs-visual fit",
        "GC4xx Self-collision",
        "GC5xx Inertia and mass",
    ]
    fit = suites["GC3xx Collision-vs-visual fit"]
    cases = {c.name: c for c in fit}
    assert list(cases) == ["link base_link", "link fl_caster_rotation_link", "link base_laser_link"]
    failed = cases["link base_link"]
    assert failed.classname == "geomcheck.fit"
    assert isinstance(failed.result[0], Failure)
    assert failed.result[0].type == "GC301"
    assert "urdf/base.urdf.xacro:12:5: GC301 [error]" in failed.result[0].text
    assert cases["link base_laser_link"].is_passed
    assert fit.tests == 3 and fit.failures == 1
    structure = {c.name: c for c in suites["GC1xx Syntax and structure"]}
    # the warning does not fail (fail on error) but is reported in system-out
    joint_case = structure["joint fl_caster_rotation_joint"]
    assert joint_case.is_passed
    assert "GC120 [warning]" in joint_case.system_out
    pair_case = {c.name: c for c in suites["GC4xx Self-collision"]}["links base_link / fl_caster_rotation_link"]
    assert pair_case.is_passed


def test_junit_fails_warnings_when_failing_on_warnings() -> None:
    xml = JUnitXml.fromstring(render(sample_report(Severity.WARNING), "junit").encode())
    structure = {c.name: c for c in next(iter(xml))}
    assert not structure["joint fl_caster_rotation_joint"].is_passed
    assert xml.failures == 2


def test_statistics_counts_per_rule() -> None:
    report = sample_report()
    doubled = Report(report.robot, (*report.diagnostics, report.diagnostics[0]), "0.1.0", report.created)
    lines = stats.render_text(doubled).splitlines()
    assert [line.split()[:4] for line in lines[:4]] == [
        ["count", "code", "name", "severity"],
        ["2", "GC301", "rule-gc301", "error"],
        ["1", "GC120", "rule-gc120", "warning"],
        ["1", "GC401", "rule-gc401", "info"],
    ]
    assert lines[4] == "Found 4 findings."
    first = json.loads(stats.render_json(doubled))[0]
    assert {k: first[k] for k in ("code", "name", "severity", "count")} == {
        "code": "GC301",
        "name": "rule-gc301",
        "severity": "error",
        "count": 2,
    }


def test_diff_and_baseline_sections_reach_the_summary() -> None:
    report = sample_report()
    sections = {
        "diff": {
            "base": "HEAD~1",
            "base_exists": True,
            "new": 3,
            "fixed": [{"code": "GC302", "link": "wheel", "joint": None, "links": None, "message": "gone"}],
            "regressions": [
                {
                    "diagnostic": {
                        "code": "GC301",
                        "link": "base_link",
                        "joint": None,
                        "links": None,
                        "severity": "error",
                    },
                    "severity_before": "warning",
                    "metrics": [{"name": "coverage", "before": 0.9, "after": 0.31}],
                }
            ],
            "unchanged": 0,
        }
    }
    text = render(Report(report.robot, report.diagnostics, "0.1.0", report.created, sections=sections), "concise")
    assert "fixed: GC302 link wheel: gone" in text
    assert "regressed: GC301 link base_link: severity warning -> error, coverage 0.9 -> 0.31" in text
    assert "against HEAD~1: 3 new, 1 fixed, 1 regressed" in text


def test_markdown_prose_quotes_markup() -> None:
    assert prose("bare <property> and `<ok/>`") == "bare `<property>` and `<ok/>`"


def test_full_marks_an_excerpt_of_the_expanded_document() -> None:
    d = finding(
        "GC301",
        Severity.ERROR,
        "m",
        link="a",
        location=SourceLocation("robots/gen.urdf.xacro", None, None, 40),
        excerpt=((38, "<link>"), (39, "<collision>"), (40, "  <box/>"), (41, "</collision>"), (42, "</link>")),
    )
    report = sample_report()
    text = render(Report(report.robot, (d,), "0.1.0", report.created), "full")
    assert "robots/gen.urdf.xacro: GC301 [error] rule-gc301\n" in text
    assert "  (expanded URDF, line 40)\n" in text
    assert "  40 |   <box/>\n     |   ^ rule-gc301\n" in text
