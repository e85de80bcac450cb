"""JSON: the versioned report document (``geomcheck.report/1``)."""

from __future__ import annotations

import json

from geomcheck.report.model import Report


def render(report: Report) -> str:
    return json.dumps(report.to_dict(), indent=2, sort_keys=False, allow_nan=False) + "\n"
