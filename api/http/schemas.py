"""Response models of the HTTP API (they make the OpenAPI document; see docs/report-schema.md
for the report itself). Report sections are open objects: each check family documents its own."""

from __future__ import annotations

import datetime as dt
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

Status = Literal["queued", "running", "succeeded", "failed", "cancelled"]


class ErrorOut(BaseModel):
    detail: str = Field(description="one line saying what was wrong")


class SummaryOut(BaseModel):
    error: int
    warning: int
    info: int


class LocationOut(BaseModel):
    file: str = Field(description="path relative to the upload root")
    line: int | None = None
    column: int | None = None
    expanded_line: int | None = Field(None, description="line in the expanded URDF")


class DiagnosticOut(BaseModel):
    model_config = ConfigDict(extra="allow")

    code: str = Field(examples=["GC301"])
    name: str = Field(examples=["collision-misses-visual"])
    severity: Literal["error", "warning", "info"]
    message: str
    help: str
    link: str | None = None
    joint: str | None = None
    links: list[str] | None = Field(None, description="the link pair, sorted, for pair findings")
    about: str = Field("", description="part of the subject: collision[0], axis, inertia")
    location: LocationOut | None = None
    fingerprint: str
    data: dict[str, Any] = Field(default_factory=dict, description="metrics behind the message, SI units")
    excerpt: list[tuple[int, str]] = Field(default_factory=list, description="[line, text] around the location")


class SkippedOut(BaseModel):
    check: str
    subject: str
    reason: str


class ToolOut(BaseModel):
    name: str
    version: str


class RobotOut(BaseModel):
    name: str
    source: str = Field(description="root file, relative to the upload root")
    links: int
    joints: int
    meshes_total: int
    meshes_loaded: int


class ReportOut(BaseModel):
    """The ``geomcheck.report/1`` document, byte for byte what ``geomcheck check --format json`` writes."""

    model_config = ConfigDict(extra="allow", populate_by_name=True)

    schema_: str = Field(alias="schema", examples=["geomcheck.report/1"])
    tool: ToolOut
    created: str = Field(description="ISO 8601 UTC")
    robot: RobotOut
    options: dict[str, Any]
    fail_on: Literal["error", "warning", "info"]
    verdict: Literal["pass", "fail"]
    summary: SummaryOut
    diagnostics: list[DiagnosticOut]
    skipped: list[SkippedOut]
    sections: dict[str, Any] = Field(description="per-family detail: links, inertia, sweeps, matrix, views")


class CheckLinks(BaseModel):
    self: str
    report_json: str
    report_html: str
    report_sarif: str = Field(description="the report as SARIF 2.1.0 (code scanning)")
    report_junit: str = Field(description="the report as JUnit XML (CI test reports)")
    fixes_patch: str = Field(description="the safe fixes as a unified diff (?unsafe=true: all of them)")
    collision_matrix_srdf: str | None = Field(None, description="present when a collision matrix was computed")


class ProgressOut(BaseModel):
    """How far a running check has come: its stage and the fraction done; after its report, how
    far the verification of its fixes has come (``phase`` "fixes")."""

    stage: str = Field(
        description="the stage running: loading, then each check family (structure, meshes, fit, inertia, "
        "selfcollision with its continuous-joint sweeps, matrix with its samples, ...); in the phase 'fixes', "
        "'verifying safe fixes' then 'verifying all fixes'",
        examples=["selfcollision"],
    )
    stage_index: int = Field(ge=0, description="index of the stage, from 0")
    stages: int = Field(ge=1, description="number of stages of the phase")
    stage_fraction: float = Field(ge=0.0, le=1.0, description="fraction of the stage done [0, 1]")
    fraction: float = Field(
        ge=0.0,
        le=1.0,
        description="fraction done [0, 1] of the phase, its stages counted alike; it never goes backwards within "
        "a phase (the rounds verifying fixes each take their part of their stage)",
    )
    phase: Literal["check", "fixes"] = Field(
        "check", description="check: the check runs; fixes: its offered fixes are verified, after its report"
    )


class FixesOut(BaseModel):
    """The state of the fixes a succeeded check's report offers (its ``fixes`` section and ``fixes.patch``)."""

    status: Literal["verifying", "verified", "unverified", "failed"] = Field(
        description="verifying: the report is out and its fixes are being verified (the patches are the planned "
        "ones until then); verified: each applied to a copy and checked again, as `geomcheck fix` does; "
        "unverified: verification was turned off (verify_fixes=false); failed: it did not finish (see reason), "
        "the planned patches stay"
    )
    reason: str | None = Field(None, description="why the verification did not finish")


class RootOut(BaseModel):
    """The root file a check read, and how it was chosen."""

    path: str = Field(description="relative to the upload root")
    given: bool = Field(description="named by the request (root=...); false: chosen by the service")
    reason: str = Field(description="why this file: what it does that the others do not")
    alternatives: list[str] = Field(default_factory=list, description="the other candidates, likeliest first")


class CheckOut(BaseModel):
    """A check: its state, the figures of its report, and the report once it succeeded."""

    id: str = Field(description="unguessable identifier")
    status: Status
    created: dt.datetime
    started: dt.datetime | None = None
    finished: dt.datetime | None = None
    source: str = Field(description="root file, relative to the upload root")
    robot: str | None = None
    verdict: Literal["pass", "fail"] | None = None
    summary: SummaryOut | None = None
    http_status: int | None = Field(None, description="for failed checks: the status the failure maps to")
    reason: str | None = Field(None, description="for failed checks: why, in one line")
    seconds: float | None = Field(None, description="run time of the check process [s]")
    progress: ProgressOut | None = Field(
        None,
        description="while the check runs: its stage and the fraction done, updated a few times a second; "
        "null while it waits to start and once it finished",
    )
    options: dict[str, Any] = Field(description="the options asked for")
    cached: bool = Field(
        False, description="answered from an identical earlier check (or sharing one in flight) instead of run again"
    )
    cached_from: str | None = Field(None, description="for cached checks: the id of the check whose report this is")
    fixes: FixesOut | None = Field(
        None, description="the offered fixes' verification, once the check succeeded; null when none is offered"
    )
    root: RootOut | None = Field(None, description="the root file read and how it was chosen (absent for old checks)")
    links: CheckLinks
    report: ReportOut | None = Field(None, description="the report, once the check succeeded")


class CheckPage(BaseModel):
    items: list[CheckOut] = Field(description="newest first, without reports")
    next_cursor: str | None = Field(None, description="pass as ?cursor= for the next page; null on the last")


class RuleOut(BaseModel):
    code: str
    name: str
    severity: Literal["error", "warning", "info"]
    family: str
    family_title: str
    summary: str
    what: str
    why: str
    example: str
    fix: str


class HealthOut(BaseModel):
    status: Literal["ok", "degraded"]
    version: str
    database: Literal["ok", "unavailable"]
    workers: int = Field(description="checks that can run at once")
    running: int = Field(description="check processes running now")
    pending: int = Field(description="checks queued or running")
