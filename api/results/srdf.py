"""The ``collision-matrix.srdf`` download: the stored report's ``matrix`` section written by
the library's SRDF writer (:func:`geomcheck.report.srdf.render_srdf`).

The writer takes a :class:`CollisionMatrix`; a stored report holds its section (JSON), so
the matrix is rebuilt from it with what the writer reads (classes, certification, bounds).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from geomcheck.report.srdf import render_srdf
from geomcheck.selfcollision.matrix import CollisionMatrix, PairClass, PairResult


def matrix_from_section(section: Mapping[str, Any]) -> CollisionMatrix:
    """The :class:`CollisionMatrix` of a report's ``matrix`` section (witnesses and sample counts of collisions
    are not in the section and stay empty; the SRDF does not use them)."""
    pairs = tuple(
        PairResult(
            links=(p["links"][0], p["links"][1]),
            cls=PairClass(p["class"]),
            tested=int(p.get("tested") or 0),
            min_distance=p.get("min_distance"),
            certified=bool(p.get("certified")),
            clearance_bound=p.get("clearance_bound"),
        )
        for p in section["pairs"]
    )
    return CollisionMatrix(
        samples=int(section["samples"]),
        seed=int(section["seed"]),
        backend=str(section["backend"]),
        semantics=str(section.get("semantics", "moveit")),
        always_fraction=float(section["always_fraction"]),
        links=tuple(section["links"]),
        pairs=pairs,
        default_configuration={},
    )


def matrix_srdf(report: Mapping[str, Any]) -> str:
    """The SRDF of the report's collision matrix (``KeyError`` when it has none)."""
    return render_srdf(matrix_from_section(report["sections"]["matrix"]), report["robot"]["name"])
