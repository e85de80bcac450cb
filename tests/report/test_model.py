from __future__ import annotations

import json

from geomcheck.diagnostics import Diagnostic, Severity, SkippedCheck
from geomcheck.model import SourceLocation
from geomcheck.report import render
from geomcheck.report.model import Report, RobotSummary


def sample_report() -> Report:
    d = Diagnostic(
        code="GC301",
        name="collision-does-not-cover-mesh",
        severity=Severity.ERROR,
        message="covers 4%",
        help="make it taller",
        link="base_link",
        about="collision[0]",
        location=SourceLocation("base.urdf.xacro", 120, 7, 300),
        data={"coverage": 0.04},
        excerpt=((119, "<collision>"), (120, "<box/>")),
    )
    return Report(
        robot=RobotSummary("pr2", "robots/pr2.urdf.xacro", 72, 71, 30, 29),
        diagnostics=(d,),
        tool_version="0.1.0",
        created="2026-01-01T00:00:00Z",
        skipped=(SkippedCheck("fit", "head", "mesh missing"),),
        sections={"links": [{"link": "base_link"}]},
        options={"seed": 0},
    )


def test_round_trip_is_exact() -> None:
    report = sample_report()
    again = Report.from_dict(json.loads(render(report, "json")))
    assert again == report
    assert render(again, "json") == render(report, "json")


def test_json_carries_summary_and_verdict() -> None:
    data = json.loads(render(sample_report(), "json"))
    assert data["schema"] == "geomcheck.report/1"
    assert data["summary"] == {"error": 1, "warning": 0, "info": 0}
    assert data["verdict"] == "fail"
    assert data["diagnostics"][0]["location"] == {
        "file": "base.urdf.xacro",
        "line": 120,
        "column": 7,
        "expanded_line": 300,
    }
    assert data["robot"]["links"] == 72
