"""Golden reports: every corpus robot and the bundled example report exactly what
``tests/golden/reports.json`` recorded (timestamp and tool version aside).

A refactoring that must not change behaviour keeps these; a change of behaviour regenerates
the file with ``python scripts/golden.py --update`` in the same commit. On a difference the
test names the robot, the findings that appeared, disappeared or changed and the report parts
that differ, and keeps the normalised report under the test's temporary folder.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from tests.corpustools import CorpusReports
from tests.goldentools import golden_script

REPO = Path(__file__).resolve().parents[1]


golden = golden_script()
RECORDED: dict[str, Any] = golden.load_golden()
CORPUS_KEYS = sorted(key for key in RECORDED if key != golden.EXAMPLE)


def assert_golden(key: str, document: dict[str, Any], tmp_path: Path) -> None:
    lines = golden.differences(key, RECORDED[key], document)
    if lines:
        kept = tmp_path / "report.json"
        kept.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
        lines.append(f"  normalised report kept at {kept}; if intended: python scripts/golden.py --update")
        pytest.fail("\n".join(lines), pytrace=False)


def test_the_bundled_example_reports_as_recorded(tmp_path: Path) -> None:
    (example,) = golden.robots(None)
    assert example.key == golden.EXAMPLE
    assert_golden(example.key, golden.normalised_report(example), tmp_path)


@pytest.mark.corpus
def test_every_corpus_robot_is_recorded(corpus: Path) -> None:
    keys = [r.key for r in golden.robots(corpus) if r.key != golden.EXAMPLE]
    assert "pr2_2009_base" in keys  # the package the project started from
    assert sorted(keys) == CORPUS_KEYS, "robots.toml changed: python scripts/golden.py --update"


@pytest.mark.corpus
@pytest.mark.parametrize("key", CORPUS_KEYS)
def test_a_corpus_robot_reports_as_recorded(corpus_reports: CorpusReports, key: str, tmp_path: Path) -> None:
    assert_golden(key, golden.normalised(corpus_reports[key]), tmp_path)


def test_a_difference_names_the_finding_that_changed() -> None:
    document: dict[str, Any] = {
        "robot": {"name": "r"},
        "sections": {"links": []},
        "diagnostics": [
            {"code": "GC301", "fingerprint": "a" * 16, "link": "base", "about": "collision[0]", "message": "m1"},
            {"code": "GC102", "fingerprint": "b" * 16, "joint": "j", "message": "m2"},
        ],
    }
    recorded = golden.summary(document)
    assert golden.differences("r", recorded, document) == []
    changed = json.loads(json.dumps(document))
    changed["diagnostics"][0]["message"] = "m1 changed"
    changed["diagnostics"].pop(1)
    changed["diagnostics"].append({"code": "GC401", "fingerprint": "c" * 16, "links": ["a", "b"], "message": "m3"})
    changed["sections"]["links"] = [1]
    assert golden.differences("r", recorded, changed) == [
        "r: the normalised report differs from the golden one",
        f"  + GC401 a, b: m3 (fingerprint {'c' * 12})",
        f"  - GC102 fingerprint {'b' * 12} (no longer reported)",
        f"  ~ GC301 base collision[0]: m1 changed (fingerprint {'a' * 12}: entry changed)",
        "  part sections.links differs",
    ]


def test_where_the_corpus_lies_does_not_change_a_hash(tmp_path: Path) -> None:
    def report(corpus: Path) -> dict[str, Any]:
        mesh = f"file://{corpus}/arm/meshes/link1.stl"
        return {
            "created": "2026-11-26T10:00:00Z",
            "tool": {"version": "1.2.3"},
            "sections": {"links": [{"link": "link1", "visual_meshes": [{"filename": mesh}]}]},
            "diagnostics": [],
        }

    here, there = tmp_path / "a" / "corpus", tmp_path / "elsewhere" / "shared" / "corpus"
    normal_here, normal_there = golden.normalised(report(here), here), golden.normalised(report(there), there)
    assert normal_here == normal_there
    shown = normal_here["sections"]["links"][0]["visual_meshes"][0]["filename"]
    assert shown == "file://$GEOMCHECK_CORPUS/arm/meshes/link1.stl"
    assert golden.summary(normal_here) == golden.summary(normal_there)
