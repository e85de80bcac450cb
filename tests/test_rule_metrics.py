"""Every rule declares the metrics its findings carry in ``data`` (name, unit, which way is
better), and the declarations match what the checks write: on the bundled example and, with
the corpus, on every corpus robot, each key of each finding is declared by its rule and
every metric the rule does not mark optional is there; every declared metric is written by
some check."""

from __future__ import annotations

import re
import string
from collections.abc import Iterable
from functools import cache
from pathlib import Path
from typing import Any

import pytest

from geomcheck.diagnostics import UNITS
from geomcheck.rules import all_rules, get_rule
from tests.corpustools import CorpusReports
from tests.goldentools import golden_script

REPO = Path(__file__).resolve().parents[1]
# where findings' data are built: the checks, the loaders, the fits and the SRDF audit
WRITERS = ("checks", "load", "geometry", "selfcollision")


golden = golden_script()


def undeclared_and_missing(findings: Iterable[dict[str, Any]]) -> tuple[set[str], set[str]]:
    """``CODE key`` of data keys no declaration names, and of required metrics a finding lacks."""
    undeclared, missing = set(), set()
    for d in findings:
        rule = get_rule(d["code"])
        undeclared |= {f"{d['code']} {key}" for key in d["data"] if rule.metric(key) is None}
        missing |= {f"{d['code']} {m.name}" for m in rule.metrics if not m.optional and m.name not in d["data"]}
    return undeclared, missing


@cache
def written_names() -> str:
    """The source of every module that builds findings' data."""
    return "\n".join(
        path.read_text(encoding="utf-8")
        for folder in WRITERS
        for path in sorted((REPO / "geomcheck" / folder).rglob("*.py"))
    )


def test_declarations_are_complete() -> None:
    """A unit from the vocabulary, a description, a direction only for numbers; no rule
    without metrics except those whose findings carry no data."""
    bare = []
    for rule in all_rules():
        if not rule.metrics:
            bare.append(rule.code)
        for m in rule.metrics:
            where = f"{rule.code} {m.name}"
            assert m.unit in UNITS, where
            assert m.better in ("lower", "higher", "none"), where
            assert m.description.strip(), where
            assert m.numeric or m.better == "none", f"{where}: a {m.unit} value has no direction"
            assert re.fullmatch(r"[a-z][a-z0-9_]*", m.name), where
    # GC101 carries only its location
    assert bare == ["GC101"]


def test_every_declared_metric_is_written_by_a_check() -> None:
    """Each declared name is written somewhere: as a key (``"name"``) or a keyword argument
    of the loader's ``report(..., name=...)``."""
    source = written_names()
    unused = sorted(
        f"{rule.code} {m.name}"
        for rule in all_rules()
        for m in rule.metrics
        if f'"{m.name}"' not in source and not re.search(rf"\b{m.name}=", source)
    )
    assert unused == []


def test_directions_of_the_fit_and_sweep_metrics() -> None:
    """What ``geomcheck diff`` reads: the numbers that measure the defect have a direction."""
    covers = get_rule("GC301")
    assert [(m.name, m.unit, m.better) for m in covers.metrics if m.better != "none"] == [
        ("coverage", "1", "higher"),
        ("protrusion_max_mm", "mm", "lower"),
        ("protrusion_p95_mm", "mm", "lower"),
        ("slack", "1", "lower"),
        ("mesh_inside", "1", "higher"),
        ("in_hull", "1", "higher"),
    ]
    sweep = get_rule("GC401")
    assert {m.name: m.better for m in sweep.metrics if m.better != "none"} == {
        "min_clearance": "higher",
        "min_clearance_mm": "higher",
        "max_depth": "lower",
        "max_depth_mm": "lower",
    }


def test_the_bundled_example_carries_only_declared_metrics() -> None:
    (example,) = golden.robots(None)
    findings = golden.normalised_report(example)["diagnostics"]
    assert {d["code"] for d in findings} >= {"GC301", "GC505"}
    assert undeclared_and_missing(findings) == (set(), set())


@pytest.mark.corpus
def test_every_corpus_robot_carries_only_declared_metrics(corpus_reports: CorpusReports) -> None:
    findings = []
    for name in corpus_reports.robots:
        findings += corpus_reports[name]["diagnostics"]
    codes = {d["code"] for d in findings}
    assert len(codes) >= 15
    assert undeclared_and_missing(findings) == (set(), set())
    # every metric of a rule the corpus exercises is seen there, or declared optional
    seen = {(d["code"], key) for d in findings for key in d["data"]}
    unseen = sorted(
        f"{code} {m.name}"
        for code in codes
        for m in get_rule(code).metrics
        if (code, m.name) not in seen and not m.optional
    )
    assert unseen == []


# --- message templates ---------------------------------------------------------------------


def test_the_fit_and_inertia_rules_own_their_message_templates() -> None:
    """Every GC3xx and GC5xx rule declares its messages; each template's fields are names,
    and each variant is filled by its family's checks."""
    folder = REPO / "geomcheck" / "checks"
    checks = {
        "GC3": "".join(p.read_text(encoding="utf-8") for p in sorted((folder / "fit").glob("*.py"))),
        "GC5": "".join(p.read_text(encoding="utf-8") for p in sorted((folder / "inertia").glob("*.py"))),
    }
    for rule in all_rules():
        if rule.family not in checks:
            continue
        assert rule.messages, rule.code
        for variant, template in rule.messages.items():
            fields = [f for _, f, _, _ in string.Formatter().parse(template) if f is not None]
            assert all(re.fullmatch(r"[a-z][a-z0-9_]*", f) for f in fields), (rule.code, variant, fields)
            used = f'"{variant}"' in checks[rule.family] if variant else ".message(" in checks[rule.family]
            assert used, (rule.code, variant)


def test_a_template_fills_as_the_message_did() -> None:
    oversized = get_rule("GC302").message(label="collision[0]", kind="sphere", slack=12.345, fitted_slack=1.5)
    assert oversized == (
        "collision[0] sphere has 12.3 times the volume of the mesh's convex hull; a fitted sphere would have 1.5 times"
    )
    mass = get_rule("GC502")
    assert mass.message("not_finite", mass=float("nan")) == "mass is nan kg, not a finite number"
    assert mass.message("negative", mass=-2.5) == "mass is negative: -2.5 kg"
    with pytest.raises(KeyError):
        get_rule("GC302").message(label="collision[0]", kind="sphere", slack=12.3)


def test_the_rules_reference_lists_each_rules_metrics() -> None:
    from geomcheck.report.rules_markdown import metrics_table, metrics_text

    table = metrics_table(get_rule("GC506")).splitlines()
    assert table[2:4] == ["| key | unit | better | meaning |", "| --- | --- | --- | --- |"]
    assert (
        table[5] == "| `distance` | m | lower | How far the centre of mass lies outside the geometry's convex hull. |"
    )
    assert table[6] == "| `bounds` | m | — | The lower and upper corners of the geometry's bounding box. |"
    assert table[7].endswith("*(optional)* |")
    text = metrics_text(get_rule("GC506")).splitlines()
    assert text[0] == "Metrics (data key, unit, better)"
    assert text[2].split()[:3] == ["distance", "[m]", "lower"]
    assert metrics_table(get_rule("GC101")) == metrics_text(get_rule("GC101")) == ""


def test_every_rule_says_how_the_severity_policy_applies_to_it() -> None:
    from geomcheck.rules import SEVERITY_POLICY, all_rules

    assert SEVERITY_POLICY.startswith("error: a consumer")
    missing = [r.code for r in all_rules() if len(r.severity_reason.split()) < 8]
    assert missing == [], "give these rules a severity_reason (geomcheck/rules/__init__.py SEVERITY_POLICY)"
