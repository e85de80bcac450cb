"""The suite's compiled validator (tests/schematools.py: fastjsonschema on the schema rewritten
to draft 7) gives jsonschema's verdict on docs/report-schema.json (draft 2020-12): on whole
reports, and on reports broken one value at a time at places spread over the whole document."""

from __future__ import annotations

import copy
import json
import random
from pathlib import Path
from typing import Any

import pytest

from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report.json_format import render
from tests.schematools import draft7, fast_errors, reference_errors

REPO = Path(__file__).resolve().parents[2]
EXAMPLE_ROOT = REPO / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"
BROKEN = 120  # one-value breakages tried [count]
KEPT_ITEMS = 4  # items kept of each list: the schema's longest fixed length (a 4 x 4 transform) [count]


@pytest.fixture(scope="module")
def document() -> dict[str, Any]:
    """The bundled example's report (findings with excerpts and fixes, and every section), its
    long lists cut to their first items: every kind of value is still there, and the reference
    validator reads each broken copy in milliseconds instead of a fifth of a second."""
    loaded: dict[str, Any] = shortened(json.loads(render(run_check(make_bundle(EXAMPLE_ROOT), CheckOptions()))))
    return loaded


def shortened(node: Any) -> Any:
    """``node`` with every list longer than ``KEPT_ITEMS`` cut to its first ``KEPT_ITEMS``."""
    if isinstance(node, dict):
        return {k: shortened(v) for k, v in node.items()}
    if isinstance(node, list):
        return [shortened(v) for v in node[:KEPT_ITEMS]]
    return node


def places(node: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """The path of every value in ``node`` (dict keys and list indexes), the root excluded."""
    out: list[tuple[Any, ...]] = []
    children = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for key, value in children:
        out.append((*path, key))
        out.extend(places(value, (*path, key)))
    return out


def broken(document: dict[str, Any], path: tuple[Any, ...], rng: random.Random) -> dict[str, Any]:
    """``document`` with the value at ``path`` deleted, given another type, made negative, or
    its list grown by a copy of its last item."""
    out = copy.deepcopy(document)
    parent = out
    for key in path[:-1]:
        parent = parent[key]
    key = path[-1]
    value = parent[key]
    how = rng.choice(("delete", "retype", "negative", "grow"))
    if how == "delete" and isinstance(parent, dict):
        del parent[key]
    elif how == "negative" and isinstance(value, int | float) and not isinstance(value, bool):
        parent[key] = -abs(value) - 1
    elif how == "grow" and isinstance(value, list) and value:
        value.append(copy.deepcopy(value[-1]))
    else:
        others = [v for v in ("x", 7, 0.5, None, True, [], {}) if type(v) is not type(value)]
        parent[key] = rng.choice(others)
    return out


def test_the_draft_7_spelling_changes_prefix_items_alone() -> None:
    schema = {"items": {"type": "array", "prefixItems": [{"type": "integer"}, {"type": "string"}], "items": False}}
    tuple_items = [{"type": "integer"}, {"type": "string"}]
    assert draft7(schema) == {"items": {"type": "array", "items": tuple_items, "additionalItems": False}}


def test_both_validators_accept_the_report(document: dict[str, Any]) -> None:
    assert {"diagnostics", "sections", "summary"} <= set(document)
    assert fast_errors(document) == []
    assert reference_errors(document) == []


def test_both_validators_give_the_same_verdict_on_broken_reports(document: dict[str, Any]) -> None:
    rng = random.Random(0)
    spots = places(document)
    verdicts = {"both invalid": 0, "both valid": 0}
    disagreements = []
    for path in rng.sample(spots, min(BROKEN, len(spots))):
        case = broken(document, path, rng)
        fast, reference = bool(fast_errors(case)), bool(reference_errors(case))
        if fast != reference:
            disagreements.append(f"{'/'.join(map(str, path))}: compiled {fast}, reference {reference}")
        else:
            verdicts["both invalid" if fast else "both valid"] += 1
    assert disagreements == []
    # the breakages reach both verdicts: the agreement is not that of two validators accepting all
    assert verdicts["both invalid"] >= 30 and verdicts["both valid"] >= 10, verdicts
