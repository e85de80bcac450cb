"""The sweep and matrix sections in the full text format (geomcheck.report.sections_text)."""

from __future__ import annotations

import math
from typing import Any

from geomcheck.diagnostics import Severity
from geomcheck.report import render
from geomcheck.report.model import Report, RobotSummary
from geomcheck.report.sections_text import matrix_lines, sweep_lines


def pair(links: list[str], clearance: float, angle: float, ranges: list[list[float]], adjacent: bool = False) -> dict:
    return {
        "links": links,
        "min_clearance": clearance,
        "min_angle": angle,
        "colliding_ranges": ranges,
        "max_depth": max(0.0, -clearance),
        "adjacent": adjacent,
    }


def sweep(joint: str, pairs: list[dict[str, Any]], moving: int, far: int = 0, proven: bool = True) -> dict[str, Any]:
    links = [f"{joint}_link{i}" for i in range(moving)]
    return {
        "joint": joint,
        "moving_links": links,
        "grid_points": 360,
        "proven": proven,
        "pairs": pairs,
        "far_pairs": far,
    }


def report(**sections: Any) -> Report:
    return Report(
        robot=RobotSummary("base", "robots/base.urdf", 4, 3, 1, 1),
        diagnostics=(),
        tool_version="0.1.0",
        created="2026-01-01T00:00:00Z",
        fail_on=Severity.ERROR,
        sections=sections,
    )


SWEEPS = [
    sweep(
        "caster_joint",
        [
            pair(["base_link", "caster_link"], 0.0853, math.radians(-111.0), []),
            pair(["base_link", "wheel_link"], -0.004, 0.7, [[0.5, 0.9]]),
            pair(["caster_link", "plate_link"], -0.01, 0.0, [[-math.pi, math.pi]], adjacent=True),
        ],
        moving=2,
    ),
    sweep("wheel_joint", [pair(["caster_link", "wheel_link"], -0.0113, 0.0, [[-math.pi, math.pi]], True)], moving=1),
    sweep("spinner_joint", [], moving=1, far=12),
]


def test_each_swept_joint_gets_its_contact_or_closest_pair() -> None:
    assert sweep_lines(report(sweeps=SWEEPS)) == [
        "Sweeps (each continuous joint over a full turn, the rest at the default pose; "
        "clearance proven between 360 grid points):",
        "  caster_joint    2 moving links  in contact: base_link / wheel_link from 28.6° to 51.6°, 4.0 mm deep",
        "  wheel_joint     1 moving link   closest caster_link / wheel_link (adjacent) overlap 11.3 mm at every angle",
        "  spinner_joint   1 moving link   all 12 pairs out of reach",
    ]


def test_a_clear_sweep_names_its_closest_non_adjacent_pair_and_unproven_sweeps_say_so() -> None:
    clear = sweep("caster_joint", [SWEEPS[0]["pairs"][0], SWEEPS[0]["pairs"][2]], moving=2, proven=False)
    assert sweep_lines(report(sweeps=[clear])) == [
        "Sweeps (each continuous joint over a full turn, the rest at the default pose; some sweeps sampled only):",
        "  caster_joint   2 moving links  closest base_link / caster_link 85.3 mm at -111.0° (sampled, not proven)",
    ]


def test_matrix_counts_with_certified_and_searched_pairs() -> None:
    pairs = [
        {"links": ["a", "b"], "class": "adjacent", "certified": False, "witness": None},
        {"links": ["a", "c"], "class": "never", "certified": True, "witness": None},
        {"links": ["a", "d"], "class": "never", "certified": False, "witness": None},
        {"links": ["b", "c"], "class": "enabled", "certified": False, "witness": {"source": "search"}},
        {"links": ["b", "d"], "class": "enabled", "certified": False, "witness": {"source": "sample"}},
        {"links": ["c", "d"], "class": "default", "certified": False, "witness": {"source": "default"}},
    ]
    matrix = {"samples": 500, "seed": 3, "backend": "fcl", "pairs": pairs}
    assert matrix_lines(report(matrix=matrix)) == [
        "Collision matrix (500 samples, seed 3, fcl): 6 pairs: 1 adjacent, 1 default, 0 always, "
        "2 never (1 certified), 2 enabled (1 found by the witness search)",
        "  write it as an SRDF with: geomcheck matrix PATH --srdf-out FILE",
    ]


def test_full_format_prints_the_sections_before_the_summary_and_concise_does_not() -> None:
    text = render(report(sweeps=SWEEPS[2:], matrix={"samples": 10, "seed": 0, "backend": "coal", "pairs": []}), "full")
    lines = text.splitlines()
    assert lines[0].startswith("Sweeps (") and lines[1] == "  spinner_joint   1 moving link   all 12 pairs out of reach"
    assert lines[3].startswith("Collision matrix (10 samples, seed 0, coal): 0 pairs")
    assert lines[-1].startswith("base: 4 links")
    assert "Sweeps" not in render(report(sweeps=SWEEPS), "concise")
    assert sweep_lines(report()) == [] and matrix_lines(report()) == []
