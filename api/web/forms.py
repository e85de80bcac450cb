"""The check-option form of the web page, generated from the API's own option definitions.

The fields are the request options ``api.checks.options`` accepts (:data:`api.checks.options.OPTION_NAMES`),
typed and described by the service's OpenAPI document (query parameters and multipart
fields of ``POST /v1/checks``), with the defaults a request without options gets
(:func:`api.checks.options.request_config`). Nothing here lists options a second time.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from api.checks.options import OPTION_NAMES, RawOptions, check_options, request_config
from geomcheck.pipeline import options_summary

Kind = Literal["boolean", "integer", "choice", "list", "text"]
CHECK_PATH = "/v1/checks"
# shown folded under "More options": rule selection, poses and SRDF are for people who know them
ADVANCED = frozenset({"srdf", "pose", "pose_name", "select", "ignore", "extend_select"})


@dataclass(frozen=True)
class OptionField:
    """One form field: the request option ``name``, how it is entered, and its default as text
    (``""`` when the option has none)."""

    name: str
    label: str
    kind: Kind
    description: str
    default: str
    choices: tuple[str, ...] = ()
    minimum: int | None = None
    advanced: bool = False


def _shown(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return ""
    if isinstance(value, Mapping):
        return "\n".join(f"{k}={v}" for k, v in value.items())
    if isinstance(value, list | tuple):
        return ",".join(str(v) for v in value)
    return str(value)


def option_defaults(max_samples: int) -> dict[str, str]:
    """What a request that names no option gets, by option name, as the form shows it."""
    options = check_options(request_config(RawOptions(), max_samples, Path(".")))
    values: dict[str, object] = dict(options_summary(options))
    values["fail_on"] = options.fail_on.value
    values["select"] = list(options.selection.select)
    values["ignore"] = list(options.selection.ignore)
    values["extend_select"] = []
    return {name: _shown(values.get(name)) for name in OPTION_NAMES}


def _resolved(openapi: Mapping[str, Any], schema: Mapping[str, Any]) -> dict[str, Any]:
    """``schema`` with a local ``$ref`` (``#/components/schemas/...``) replaced by what it names."""
    ref = schema.get("$ref")
    if not isinstance(ref, str) or not ref.startswith("#/"):
        return dict(schema)
    target: Any = openapi
    for part in ref[2:].split("/"):
        target = target.get(part, {}) if isinstance(target, Mapping) else {}
    return {**target, **{k: v for k, v in schema.items() if k != "$ref"}}


def _schema(openapi: Mapping[str, Any], parameter: Mapping[str, Any]) -> dict[str, Any]:
    """The schema of ``parameter`` without its ``null`` alternative."""
    schema = _resolved(openapi, parameter.get("schema", {}))
    for alternative in schema.pop("anyOf", []):
        if alternative.get("type") != "null":
            schema.update(_resolved(openapi, alternative))
    return schema


def _kind(schema: Mapping[str, Any]) -> Kind:
    if schema.get("enum"):
        return "choice"
    kind = schema.get("type")
    if kind == "boolean":
        return "boolean"
    if kind == "integer":
        return "integer"
    if kind == "array":
        return "list"
    return "text"


def option_fields(openapi: Mapping[str, Any], defaults: Mapping[str, str]) -> tuple[OptionField, ...]:
    """The form fields of every request option, in the order ``POST /v1/checks`` declares them."""
    operation = openapi["paths"][CHECK_PATH]["post"]
    body = operation.get("requestBody", {}).get("content", {}).get("multipart/form-data", {})
    form = _resolved(openapi, body.get("schema", {})).get("properties", {})
    fields = []
    for parameter in operation["parameters"]:
        name = parameter["name"]
        if name not in OPTION_NAMES:
            continue
        schema = {**_schema(openapi, parameter), **_resolved(openapi, form.get(name, {}))}
        kind = _kind(schema)
        fields.append(
            OptionField(
                name=name,
                label=name.replace("_", " "),
                kind=kind,
                description=parameter.get("description") or schema.get("description", ""),
                default=defaults.get(name, ""),
                choices=tuple(str(c) for c in schema.get("enum", ())),
                minimum=schema.get("minimum") if kind == "integer" else None,
                advanced=name in ADVANCED,
            )
        )
    return tuple(fields)
