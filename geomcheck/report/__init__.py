"""Report model and one renderer per format (``render(report, fmt)``)."""

from __future__ import annotations

import importlib

from geomcheck.errors import UsageError
from geomcheck.report.model import SCHEMA, Report, RobotSummary

# format name -> module under geomcheck.report exposing ``render(report) -> str``
FORMATS: dict[str, str] = {
    "full": "full",
    "text": "full",  # the name of the first release's format: an alias of full
    "concise": "concise",
    "json": "json_format",
    "github": "github",
    "sarif": "sarif",
    "junit": "junit",
    "html": "html",
}

# the formats that show the drawn sections (views, 3D scene) or carry them to a later render
DRAWN_FORMATS = frozenset({"html", "json"})


def render(report: Report, fmt: str) -> str:
    """``report`` as text in format ``fmt``; :class:`UsageError` naming the formats otherwise."""
    if fmt not in FORMATS:
        raise UsageError.bad_choice("output format", fmt, sorted(FORMATS))
    module = importlib.import_module(f"geomcheck.report.{FORMATS[fmt]}")
    return str(module.render(report))


__all__ = ["DRAWN_FORMATS", "FORMATS", "SCHEMA", "Report", "RobotSummary", "render"]
