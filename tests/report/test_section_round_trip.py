"""The typed report sections (geomcheck/report/section_*.py) parse the sections the check
families write and serialise them back to the same JSON, key order included: the bundled
example here, every corpus robot with ``$GEOMCHECK_CORPUS``."""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import Any

import pytest

from geomcheck.baseline import Baseline, apply_baseline
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.diff import diff_report
from geomcheck.model import SourceLocation
from geomcheck.report.model import Report, RobotSummary
from geomcheck.report.section_changes import BaselineSection, DiffSection, baseline_section, diff_section
from geomcheck.report.section_inertia import InertiaEntry, inertia_section
from geomcheck.report.section_links import ElementFit, LinkFit, links_section
from geomcheck.report.section_matrix import MatrixSection, matrix_section
from geomcheck.report.section_model import ModelSection, model_section
from geomcheck.report.section_scene import Scene
from geomcheck.report.section_sweeps import JointSweep, sweeps_section
from geomcheck.report.section_views import LinkViews
from tests.corpustools import CorpusReports
from tests.goldentools import golden_script

PARSERS: Mapping[str, Callable[[Mapping[str, Any]], Any]] = {
    "views": LinkViews.from_dict,
    "sweeps": JointSweep.from_dict,
    "inertia": InertiaEntry.from_dict,
    "links": LinkFit.from_dict,
    "matrix": MatrixSection.from_dict,
    "model": ModelSection.from_dict,
    "scene": Scene.from_dict,
}


def typed_round_trip(sections: Mapping[str, Any]) -> dict[str, int]:
    """Entries per typed section, asserting each serialises back to its own JSON text."""
    counts = {}
    for name, parse in PARSERS.items():
        entries = sections.get(name) or []
        # the matrix, the model and the scene are one object each
        entries = [entries] if isinstance(entries, dict) else entries
        for entry in entries:
            again = parse(entry).to_dict()
            assert json.dumps(again) == json.dumps(entry), f"{name} entry {entry.get('link') or entry.get('joint')}"
        counts[name] = len(entries)
    return counts


@pytest.fixture(scope="module")
def example_sections() -> dict[str, Any]:
    golden = golden_script()
    (example,) = golden.robots(None)
    return golden.normalised_report(example)["sections"]


def test_the_bundled_example_sections_round_trip(example_sections: dict[str, Any]) -> None:
    counts = typed_round_trip(example_sections)
    assert counts["views"] >= 3 and counts["sweeps"] >= 1 and counts["inertia"] >= 3
    assert counts["links"] >= 3 and counts["model"] == 1
    assert counts["links"] >= 3 and counts["scene"] == 1


def test_every_corpus_robot_sections_round_trip(corpus_reports: CorpusReports) -> None:
    totals: dict[str, int] = {}
    for name in corpus_reports.robots:
        for section, n in typed_round_trip(corpus_reports[name]["sections"]).items():
            totals[section] = totals.get(section, 0) + n
    assert all(n > 0 for n in totals.values()) and set(totals) == set(PARSERS), totals


def test_the_model_section_reads_by_name_and_tolerates_missing_keys() -> None:
    found = model_section(
        {
            "model": {
                "links": [{"name": "base", "visuals": [{"index": 0, "type": "capsule", "geometry": {"radius": 0.1}}]}],
                "joints": [{"name": "u", "type": "universal", "parent": "a", "child": "b", "axis2": [0, 1, 0]}],
            }
        }
    )
    assert found is not None and model_section({}) is None
    base = found.link("base")
    assert base is not None and base.inertial is None and base.collisions == ()
    assert base.visuals[0].type == "capsule" and base.visuals[0].origin.xyz == (0.0, 0.0, 0.0)
    joint = found.joint("u")
    assert joint is not None and (joint.axis, joint.axis2, joint.limit) == (None, (0, 1, 0), None)
    assert (
        joint.to_dict()["axis2"] == [0, 1, 0]
        and "axis2" not in found.joints[0].__class__("j", "fixed", "a", "b", joint.origin, None, None, None).to_dict()
    )


def test_a_views_entry_reads_by_name_and_tolerates_missing_keys() -> None:
    entry = LinkViews.from_dict(
        {"link": "wheel", "front": {"axes": ["y", "z"], "bounds": [0, -1, 2, 1], "mesh": [[[0, 0], [1, 1]]]}}
    )
    assert entry.link == "wheel" and entry.scale_m is None and entry.side is None
    assert entry.front is not None and entry.front.axes == ("y", "z") and entry.front.bounds == (0.0, -1.0, 2.0, 1.0)
    assert entry.front.collision == () and [name for name, _ in entry.views()] == ["front", "side", "top"]
    assert LinkViews.from_dict({"link": "x", "top": {"axes": ["x", "y"], "bounds": None}}).top.bounds is None


def test_a_sweep_reads_by_name_and_tolerates_missing_keys() -> None:
    (sweep,) = sweeps_section(
        {
            "sweeps": [
                {
                    "joint": "caster",
                    "grid_points": 360,
                    "pairs": [{"links": ["a", "b"], "min_clearance": -0.004, "colliding_ranges": [[0.5, 0.9], [1.0]]}],
                }
            ]
        }
    )
    assert (sweep.joint, sweep.grid_points, sweep.proven, sweep.far_pairs, sweep.moving_links) == (
        "caster",
        360,
        None,
        None,
        (),
    )
    (pair,) = sweep.pairs
    assert pair.name == "a / b" and pair.min_clearance == -0.004 and pair.min_angle is None and not pair.adjacent
    assert pair.colliding_ranges == ((0.5, 0.9),)  # a range without its end is dropped
    assert sweeps_section({}) == () and sweeps_section({"sweeps": None}) == ()


def test_an_inertia_entry_reads_by_name_with_nested_lists_as_tuples() -> None:
    (entry,) = inertia_section(
        {
            "inertia": [
                {
                    "link": "wheel",
                    "mass": 2,
                    "principal_axes": [[1.0, 0.0, 0.0], None, None],
                    "bounds": [[-0.1, -0.1, -0.02], [0.1, 0.1, 0.02]],
                    "within_geometry": False,
                }
            ]
        }
    )
    assert (entry.link, entry.mass, entry.within_geometry, entry.positive_definite) == ("wheel", 2, False, None)
    assert entry.principal_axes == ((1.0, 0.0, 0.0), None, None)
    assert entry.bounds == ((-0.1, -0.1, -0.02), (0.1, 0.1, 0.02))
    again = entry.to_dict()
    assert list(again)[:4] == ["link", "mass", "com", "principal_moments"] and len(again) == 21
    assert again["principal_axes"] == [[1.0, 0.0, 0.0], None, None] and again["copied_from"] is None


def test_a_links_entry_reads_by_name_and_keeps_a_mesh_comparison_apart() -> None:
    fit = {"coverage": 0.31, "gaps_mm": {"radial": -4.0}, "reverse_coverage": 1.0, "overshoot_max_mm": 4.0}
    (entry,) = links_section(
        {"links": [{"link": "arm", "collisions": [{"index": 0, "type": "mesh", "fit": fit}, {"type": "box"}]}]}
    )
    first, second = entry.collisions
    assert (entry.link, entry.skipped, entry.precision) == ("arm", (), None)
    assert first.label == "collision[0]" and second.label == "collision[?]" and second.fit is None
    assert first.fit is not None and first.fit.coverage == 0.31 and first.fit.gaps_mm == {"radial": -4.0}
    assert first.fit.comparison is not None and first.fit.comparison.overshoot_max_mm == 4.0
    assert first.fit.axis_alternative is None and first.fit.suggested is None
    written = first.fit.to_dict()
    assert list(written)[-7:] == [
        "reverse_coverage",
        "overshoot_max_mm",
        "overshoot_p95_mm",
        "surface_distance_max_mm",
        "surface_distance_p95_mm",
        "capsule_cap",
        "covers_neighbour",
    ]
    assert "reverse_coverage" not in ElementFit().to_dict()


def test_a_matrix_reads_by_name_and_keeps_the_class_key() -> None:
    pair = {"links": ["a", "b"], "class": "never", "certified": True, "witness": {"configuration": {"j1": 0.5}}}
    section = matrix_section(
        {"matrix": {"samples": 1000, "semantics": "pinocchio", "links": ["a", "b"], "pairs": [pair]}}
    )
    assert section is not None and (section.samples, section.seed, section.semantics) == (1000, None, "pinocchio")
    (read,) = section.pairs
    assert (read.name, read.cls, read.certified, read.tested) == ("a / b", "never", True, None)
    assert read.witness is not None and read.witness.configuration == {"j1": 0.5} and read.witness.source is None
    assert read.to_dict()["class"] == "never" and "cls" not in read.to_dict()
    assert matrix_section({}) is None and matrix_section({"matrix": {}}) is None


def finding(code: str, link: str, severity: Severity = Severity.ERROR, **data: Any) -> Diagnostic:
    return Diagnostic(
        code, "x", severity, "m", "h", link=link, about="collision[0]", location=SourceLocation("r.urdf", 1), data=data
    )


def test_the_diff_and_baseline_sections_round_trip_and_read_by_name() -> None:
    head = Report(
        RobotSummary("r", "r.urdf", 3, 2),
        (finding("GC301", "a", coverage=0.3), finding("GC302", "b", Severity.WARNING)),
        "0.1.0",
        "2026-01-01T00:00:00Z",
    )
    out = diff_report([finding("GC301", "a", coverage=0.9), finding("GC501", "c")], head, "main", base_note="n")
    written = out.sections["diff"]
    diff = diff_section(out.sections)
    assert diff is not None and json.dumps(diff.to_dict()) == json.dumps(written)
    assert (diff.base, diff.base_exists, diff.base_note, diff.new, diff.gated) == ("main", True, "n", 1, True)
    assert [d["code"] for d in diff.fixed] == ["GC501"]
    (regression,) = diff.regressions
    assert regression.diagnostic["link"] == "a" and [(m.name, m.before, m.after) for m in regression.metrics] == [
        ("coverage", 0.9, 0.3)
    ]
    (kept,), _ = apply_baseline(
        [head], Baseline.from_diagnostics([finding("GC301", "a"), finding("GC1", "z")]), "b.json"
    )
    baseline = baseline_section(kept.sections)
    assert baseline is not None and json.dumps(baseline.to_dict()) == json.dumps(kept.sections["baseline"])
    assert (baseline.file, baseline.matched, [e.subject for e in baseline.stale]) == ("b.json", 1, ["link z"])
    assert diff_section({}) is None and baseline_section({}) is None
    assert DiffSection.from_dict({}).base_exists and BaselineSection.from_dict({}).stale == ()
