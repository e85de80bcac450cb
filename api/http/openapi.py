"""The OpenAPI document: the request body of ``POST /v1/checks`` and the corrections
:func:`install_openapi` applies to what FastAPI generates.

The endpoint reads its body itself (raw XML, a multipart form or an archive, streamed under
the size limits), so FastAPI cannot infer it; this declares all three forms. The options'
query parameters, form fields and enums are written from their declaration
(:data:`geomcheck.option_spec.OPTIONS`).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from fastapi import FastAPI
from fastapi.openapi.utils import get_openapi

from api.checks.options import API_OPTIONS
from api.uploads.archives import TAR_TYPES, TGZ_TYPES, ZIP_TYPES
from geomcheck.option_spec import Option

_BINARY = {"type": "string", "format": "binary"}
_EXAMPLE_URDF = """<robot name="two_links">
  <link name="base_link"><collision><geometry><box size="0.6 0.6 0.2"/></geometry></collision></link>
  <link name="arm"><collision><geometry><cylinder radius="0.05" length="0.5"/></geometry></collision></link>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="arm"/>
    <origin xyz="0 0 0.35"/><axis xyz="0 0 1"/><limit lower="-1.57" upper="1.57" effort="10" velocity="1"/></joint>
</robot>
"""


def option_schema(option: Option) -> dict[str, Any]:
    """The JSON Schema of a request option's value (a form field, a query parameter's type)."""
    if option.repeatable:
        return {"type": "array", "items": {"type": "string"}}
    if option.kind == "bool":
        return {"type": "boolean"}
    if option.kind == "int":
        bounds = {"minimum": option.minimum, "maximum": option.maximum}
        return {"type": "integer", **{k: v for k, v in bounds.items() if v is not None}}
    if option.choice_values():
        return {"type": "string", "enum": list(option.choice_values())}
    return {"type": "string"}


def option_parameter(option: Option) -> dict[str, Any]:
    """The OpenAPI query parameter of ``option``, as FastAPI would write it for the declared type.

    The endpoint reads its options from the query string itself (:class:`api.checks.options.RawOptions`,
    the same validation as the CLI and the form fields), so FastAPI does not parse them on
    every request; they are declared to the OpenAPI document only."""
    description = option.description()
    title = option.name.replace("_", " ").title()
    schema: dict[str, Any]
    if option.repeatable:
        schema = {"type": "array", "items": {"type": "string"}, "default": []}
    else:
        kind = {"bool": "boolean", "int": "integer"}.get(option.kind, "string")
        bounds = {"minimum": option.minimum, "maximum": option.maximum} if option.kind == "int" else {}
        value = {"type": kind, **{k: v for k, v in bounds.items() if v is not None}}
        schema = {"anyOf": [value, {"type": "null"}]}
    return {
        "name": option.name,
        "in": "query",
        "required": False,
        "schema": {**schema, "description": description, "title": title},
        "description": description,
    }


# the query parameters of the options, after the endpoint's own (root, wait, cache)
OPTION_PARAMETERS: list[dict[str, Any]] = [option_parameter(o) for o in API_OPTIONS]


# the form fields of the options (srdf, a file part or a path, is declared with the files)
_OPTION_FIELDS: dict[str, Any] = {
    o.name: {**option_schema(o), "description": o.description()} for o in API_OPTIONS if o.kind != "file"
}

CHECK_REQUEST_BODY: dict[str, Any] = {
    "required": True,
    "description": (
        "One of three forms. (1) A URDF or xacro document (`application/xml` or `text/xml`); the files it "
        "references are absent, so mesh rules report them missing. (2) A multipart form: `description` "
        "(the root file) and any number of `files`, each part's filename being its path in the package tree "
        "(`pr2_description/meshes/base_v0/base.stl`), plus option fields. (3) An archive of the package tree "
        "(zip, gzip'd tar or tar) with `?root=` naming the root file. Options may also be given as query "
        "parameters. Report paths are relative to the upload root (the archive's or form's top level; a "
        "top level that is itself a package is placed in a folder named after it)."
    ),
    "content": {
        "application/xml": {"schema": {"type": "string"}, "example": _EXAMPLE_URDF},
        "text/xml": {"schema": {"type": "string"}},
        "multipart/form-data": {
            "schema": {
                "type": "object",
                "properties": {
                    "description": {**_BINARY, "description": "the root URDF/xacro; its filename is its path"},
                    "files": {
                        "type": "array",
                        "items": _BINARY,
                        "description": "meshes, includes and manifests; each filename is its path in the tree",
                    },
                    "root": {"type": "string", "description": "root file path, when it is one of `files`"},
                    "srdf": {"description": "an SRDF file part, or as a text field its path in the upload"},
                    "options": {
                        "type": "string",
                        "description": 'JSON object of options: {"samples": 500, "args": {"NAME": "VALUE"}}',
                    },
                    **_OPTION_FIELDS,
                },
            },
        },
        **{t: {"schema": _BINARY} for t in sorted(ZIP_TYPES | TGZ_TYPES | TAR_TYPES)},
    },
}


# --- the published document ---------------------------------------------------------------

REPORT_SCHEMA_FILE = Path(__file__).resolve().parents[2] / "docs" / "report-schema.json"
REPORT_COMPONENT = "ReportOut"
_CHOICES = {
    **{o.name: list(o.choice_values()) for o in API_OPTIONS if o.choice_values()},
    "status": ["queued", "running", "succeeded", "failed", "cancelled"],
}
_ERROR_OUT = {"$ref": "#/components/schemas/ErrorOut"}
_INVALID_PARAMETER = {
    "description": "invalid parameter (a query or path value of the wrong type, range or choice)",
    "content": {"application/json": {"schema": _ERROR_OUT}},
}
_UNAUTHORIZED = {
    "description": "missing or invalid bearer token",
    "content": {"application/json": {"schema": _ERROR_OUT}},
}


def report_components() -> dict[str, Any]:
    """docs/report-schema.json as OpenAPI 3.1 components: the report as ``ReportOut`` and its
    definitions as ``Report_<name>`` (references rewritten to point at them)."""
    if not REPORT_SCHEMA_FILE.is_file():  # an installed package without the docs: the model's own schema stays
        return {}
    text = REPORT_SCHEMA_FILE.read_text(encoding="utf-8").replace('"#/$defs/', '"#/components/schemas/Report_')
    schema = json.loads(text)
    definitions = schema.pop("$defs", {})
    for key in ("$schema", "$id"):  # an $id would move the base of every reference inside
        schema.pop(key, None)
    schema["description"] = f"{schema.get('description', '')} Published as docs/report-schema.json."
    return {REPORT_COMPONENT: schema, **{f"Report_{name}": value for name, value in definitions.items()}}


def accurate(document: dict[str, Any], tokens: bool) -> dict[str, Any]:
    """The generated OpenAPI ``document`` made to say what the service does.

    FastAPI documents its own validation error (422 ``HTTPValidationError``), but the service
    answers bad parameters with 400 and ``{"detail"}``; 401 is what every ``/v1`` operation
    answers without a valid token when tokens are configured, and no operation asks for a
    token when none is (the scheme stays defined, used by no operation); choices of string
    parameters are enums; the report is the published JSON Schema of ``geomcheck.report/1``.
    """
    schemas = document.setdefault("components", {}).setdefault("schemas", {})
    for operations in document.get("paths", {}).values():
        for operation in operations.values():
            responses = operation.setdefault("responses", {})
            default = responses.get("422", {}).get("content", {}).get("application/json", {}).get("schema", {})
            if default.get("$ref", "").endswith("/HTTPValidationError"):
                del responses["422"]
                responses.setdefault("400", _INVALID_PARAMETER)
            elif operation.get("parameters"):
                responses.setdefault("400", _INVALID_PARAMETER)
            if "security" in operation:
                if tokens:
                    responses.setdefault("401", _UNAUTHORIZED)
                else:
                    del operation["security"]
            for parameter in operation.get("parameters", []):
                choices = _CHOICES.get(parameter.get("name", ""))
                if choices is not None and parameter.get("in") == "query":
                    parameter["schema"] = {"anyOf": [{"type": "string", "enum": choices}, {"type": "null"}]}
    add_links(document)
    schemas.pop("HTTPValidationError", None)
    schemas.pop("ValidationError", None)
    schemas.update(report_components())
    return document


CHECK_PATH = "/v1/checks/{check_id}"


def add_links(document: dict[str, Any]) -> None:
    """OpenAPI links from the check a POST answers to every operation on it (read, download,
    delete), so clients and stateful testers can follow a check from its submission."""
    paths = document.get("paths", {})
    submit = paths.get("/v1/checks", {}).get("post")
    if submit is None:
        return
    links: dict[str, Any] = {}
    for path, operations in sorted(paths.items()):
        if not path.startswith(CHECK_PATH):
            continue
        for method, operation in sorted(operations.items()):
            if "operationId" not in operation:
                continue
            name = f"{method}{path.removeprefix(CHECK_PATH).replace('/', '_').replace('.', '_') or '_check'}"
            links[name] = {"operationId": operation["operationId"], "parameters": {"check_id": "$response.body#/id"}}
    for status in ("201", "202"):
        if status in submit.get("responses", {}):
            submit["responses"][status]["links"] = links


def install_openapi(app: FastAPI) -> None:
    """Serve :func:`accurate`'s document at ``/openapi.json`` (built once per app)."""

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None:
            document = get_openapi(
                title=app.title,
                version=app.version,
                description=app.description,
                routes=app.routes,
                license_info=app.license_info,
            )
            app.openapi_schema = accurate(document, bool(app.state.settings.tokens))
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]
