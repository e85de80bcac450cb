"""The one report model: rendered by the CLI, stored and served by the API, drawn as HTML.

Core fields are typed; ``sections`` hold the per-family detail (``links`` fit metrics,
``inertia``, ``sweeps``, ``matrix``, ``views``) as JSON-ready data, documented in
docs/report-schema.md, exactly as the families wrote it; readers parse a section into its
typed model (``geomcheck/report/section_*.py``) and use named fields. ``to_dict``/``from_dict``
round-trip exactly, so a stored report renders to the same bytes as a fresh one.
"""

from __future__ import annotations

import datetime as dt
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from geomcheck.diagnostics import (  # the findings' JSON form, re-exported with the report's
    Diagnostic,
    Severity,
    SkippedCheck,
    diagnostic_from_dict,
    diagnostic_to_dict,
)

SCHEMA = "geomcheck.report/1"


def report_timestamp() -> str:
    """Now in UTC to the second, or ``SOURCE_DATE_EPOCH`` when set (reproducible output)."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    moment = (
        dt.datetime.fromtimestamp(int(epoch), tz=dt.UTC)
        if epoch and epoch.isdigit()
        else dt.datetime.now(tz=dt.UTC).replace(microsecond=0)
    )
    return moment.isoformat().replace("+00:00", "Z")


@dataclass(frozen=True)
class RobotSummary:
    name: str
    source: str  # display path of the root file
    links: int
    joints: int
    meshes_total: int = 0  # distinct mesh files referenced
    meshes_loaded: int = 0


@dataclass(frozen=True)
class Report:
    robot: RobotSummary
    diagnostics: tuple[Diagnostic, ...]
    tool_version: str
    created: str  # ISO 8601 UTC; SOURCE_DATE_EPOCH when set
    fail_on: Severity = Severity.ERROR
    skipped: tuple[SkippedCheck, ...] = ()
    sections: Mapping[str, Any] = field(default_factory=dict)
    options: Mapping[str, Any] = field(default_factory=dict)  # what was asked, JSON-ready
    schema: str = SCHEMA

    @property
    def counts(self) -> dict[str, int]:
        """Number of diagnostics per severity, every severity present."""
        out = {s.value: 0 for s in Severity}
        for d in self.diagnostics:
            out[d.severity.value] += 1
        return out

    @property
    def failed(self) -> bool:
        """Whether any diagnostic reaches ``fail_on``."""
        return any(d.severity.rank >= self.fail_on.rank for d in self.diagnostics)

    def to_dict(self) -> dict[str, Any]:
        return {
            "schema": self.schema,
            "tool": {"name": "geomcheck", "version": self.tool_version},
            "created": self.created,
            "robot": {
                "name": self.robot.name,
                "source": self.robot.source,
                "links": self.robot.links,
                "joints": self.robot.joints,
                "meshes_total": self.robot.meshes_total,
                "meshes_loaded": self.robot.meshes_loaded,
            },
            "options": dict(self.options),
            "fail_on": self.fail_on.value,
            "verdict": "fail" if self.failed else "pass",
            "summary": self.counts,
            "diagnostics": [diagnostic_to_dict(d) for d in self.diagnostics],
            "skipped": [{"check": s.check, "subject": s.subject, "reason": s.reason} for s in self.skipped],
            "sections": dict(self.sections),
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Report:
        robot = data["robot"]
        return cls(
            schema=data["schema"],
            tool_version=data["tool"]["version"],
            created=data["created"],
            robot=RobotSummary(
                name=robot["name"],
                source=robot["source"],
                links=robot["links"],
                joints=robot["joints"],
                meshes_total=robot.get("meshes_total", 0),
                meshes_loaded=robot.get("meshes_loaded", 0),
            ),
            options=data.get("options", {}),
            fail_on=Severity(data.get("fail_on", "error")),
            diagnostics=tuple(diagnostic_from_dict(d) for d in data["diagnostics"]),
            skipped=tuple(SkippedCheck(s["check"], s["subject"], s["reason"]) for s in data.get("skipped", [])),
            sections=data.get("sections", {}),
        )
