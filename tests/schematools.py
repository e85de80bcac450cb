"""docs/report-schema.json as the tests validate against it: every JSON report a test produces
is validated (tests/conftest.py), and the corpus's reports reach 2.5 MB, so the suite compiles
the schema once (fastjsonschema, about 25 times faster than jsonschema's interpreter) and asks
jsonschema, the reference implementation of the schema's draft, only for the words of a failure.

fastjsonschema reads drafts 4 to 7; the published schema is draft 2020-12. The one keyword it
uses that draft 7 spells otherwise is ``prefixItems`` (draft 7: ``items`` as a list, and the
2020-12 ``items`` after it becomes ``additionalItems``): :func:`draft7` rewrites exactly that, and
tests/report/test_schema_validators.py holds both validators to the same verdicts.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

REPORT_SCHEMA = Path(__file__).resolve().parents[1] / "docs" / "report-schema.json"
DRAFT7 = "http://json-schema.org/draft-07/schema#"


def schema() -> dict[str, Any]:
    loaded: dict[str, Any] = json.loads(REPORT_SCHEMA.read_text(encoding="utf-8"))
    return loaded


def draft7(node: Any) -> Any:
    """``node`` (a 2020-12 schema) with ``prefixItems`` spelt as draft 7 spells it."""
    if isinstance(node, list):
        return [draft7(v) for v in node]
    if not isinstance(node, dict):
        return node
    out = {k: draft7(v) for k, v in node.items()}
    if "prefixItems" in out:
        tuple_items = out.pop("prefixItems")
        if "items" in out:
            out["additionalItems"] = out.pop("items")
        out["items"] = tuple_items
    if out.get("$schema"):
        out["$schema"] = DRAFT7
    return out


@functools.cache
def fast_validator() -> Callable[[Any], Any]:
    """The compiled validator: raises ``fastjsonschema.JsonSchemaValueException`` on a document
    that does not match."""
    import fastjsonschema

    return fastjsonschema.compile(draft7(schema()))


def reference_errors(document: object) -> list[str]:
    """What jsonschema (draft 2020-12, the schema's own draft) finds wrong in ``document``, as
    ``path: message`` lines in path order."""
    import jsonschema

    validator = jsonschema.Draft202012Validator(schema())
    errors = sorted(validator.iter_errors(document), key=lambda e: list(e.absolute_path))
    return [f"{e.json_path}: {e.message[:200]}" for e in errors]


def fast_errors(document: object) -> list[str]:
    """What the compiled validator finds wrong in ``document`` (its first error, or nothing)."""
    import fastjsonschema

    try:
        fast_validator()(document)
    except fastjsonschema.JsonSchemaValueException as err:
        return [f"{err.name}: {err.message[:200]}"]
    return []


def report_errors(document: object) -> list[str]:
    """Why ``document`` does not match the schema (empty when it does): the compiled validator
    decides, the reference names the errors."""
    found = fast_errors(document)
    if not found:
        return []
    return reference_errors(document) or [f"{found[0]} (the reference validator accepts it: the two disagree)"]
