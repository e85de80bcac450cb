"""The options are declared once (geomcheck.option_spec): the command line, the configuration
file, the service's parameters, its OpenAPI document and the docs' tables cannot drift from
the declaration, and every source refuses a value alike."""

from __future__ import annotations

import argparse
import importlib.util
import inspect
from collections.abc import Mapping
from dataclasses import fields
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from fastapi import FastAPI, Query, params

from api.checks.options import API_OPTIONS, OPTION_NAMES, RawOptions, check_options, request_config
from api.http.app import create_app
from api.http.openapi import OPTION_PARAMETERS
from api.routers.checks import REQUEST_ONLY, create_check
from api.settings import Settings
from geomcheck.cli import add_cache_option, build_parser, settings_for
from geomcheck.cli.fix import add_fix_flags
from geomcheck.config import KEYS, Config
from geomcheck.errors import UsageError
from geomcheck.option_spec import OPTIONS, SEED_MAX, Option, option, options_where, read_options
from geomcheck.options import CheckOptions
from geomcheck.pipeline import options_summary
from geomcheck.untrusted import add_untrusted_options

REPO = Path(__file__).resolve().parents[1]
MAX_SAMPLES = 200_000
# flags that steer a command rather than the check (output file, exit status, configuration lookup)
COMMAND_FLAGS = {
    "check": {"help", "paths", "output", "statistics", "exit_zero", "config", "no_config", "write_baseline", "quiet"},
    "matrix": {"help", "path", "srdf_out", "config", "no_config", "quiet"},
}


def _subparser(command: str) -> argparse.ArgumentParser:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    parser: argparse.ArgumentParser = sub.choices[command]
    return parser


def _actions(command: str) -> dict[str, argparse.Action]:
    return {a.dest: a for a in _subparser(command)._actions}


def _foreign_dests() -> set[str]:
    """Flags other modules add to ``check`` and ``matrix``: the cache, untrusted input, fixes."""
    scratch = argparse.ArgumentParser(add_help=False)
    add_cache_option(scratch)
    add_untrusted_options(scratch)
    add_fix_flags(scratch, with_fix=True)
    return {a.dest for a in scratch._actions}


def _effective(options: CheckOptions) -> dict[str, Any]:
    """What a check runs with, by option name, as a user writes it."""
    values: dict[str, Any] = dict(options_summary(options))
    values.update(
        fail_on=options.fail_on.value,
        select=tuple(options.selection.select),
        ignore=tuple(options.selection.ignore),
        srdf=options.srdf,
        env=dict(options.env),  # in the report's summary only when given (older reports stay as they were)
    )
    return values


def _default(o: Option) -> Any:
    if o.repeatable and o.kind == "selectors":
        return tuple(o.default or ())
    if o.kind == "pairs":
        return o.default or {}
    return o.default


# --- nothing exists outside the declaration -------------------------------------------------


def test_configuration_keys_are_the_declared_options() -> None:
    assert list(KEYS) == [o.key for o in OPTIONS]
    assert {name for name, _ in KEYS.values()} == {f.name for f in fields(Config)} - {"path"}
    for o in OPTIONS:
        assert KEYS[o.key] == (o.name, o.validate)
        assert getattr(Config(), o.name) in (None, (), {})  # unset: the default comes from the declaration


@pytest.mark.parametrize("command", ["check", "matrix"])
def test_flags_are_the_declared_options(command: str) -> None:
    actions = _actions(command)
    declared = {o.dest: o for o in options_where("check" if command == "check" else "matrix")}
    assert set(actions) - set(declared) - COMMAND_FLAGS[command] - _foreign_dests() == set()
    for dest, o in declared.items():
        action = actions[dest]
        assert o.flag in action.option_strings, o.key
        assert action.help == o.description()
        assert action.default is None  # unset: the file's value, then the declared default
        if o.kind == "bool":
            assert isinstance(action, argparse.BooleanOptionalAction)
            assert f"--no-{o.flag.lstrip('-')}" in action.option_strings  # type: ignore[union-attr]
        assert action.type is (int if o.kind == "int" else None)
        assert isinstance(action, argparse._AppendAction) == o.repeatable
        assert action.choices is None  # choices are checked by the option's validator, with a did-you-mean


def test_request_options_are_the_declared_options() -> None:
    assert tuple(o.name for o in OPTIONS if o.api) == OPTION_NAMES
    assert [o.name for o in API_OPTIONS] == list(OPTION_NAMES)
    signature = inspect.signature(create_check).parameters
    queried = [n for n, p in signature.items() if isinstance(p.default, params.Query)]
    assert queried == list(REQUEST_ONLY)  # FastAPI parses these
    assert [p["name"] for p in OPTION_PARAMETERS] == list(OPTION_NAMES)  # the rest are declared to OpenAPI
    assert set(options_summary(CheckOptions())) <= {o.name for o in OPTIONS}


def test_openapi_parameters_and_form_fields_follow_the_declaration() -> None:
    document = create_app(Settings(data_dir=Path("/nonexistent-geomcheck-data"))).openapi()
    post = document["paths"]["/v1/checks"]["post"]
    parameters = {p["name"]: p for p in post["parameters"]}
    form = post["requestBody"]["content"]["multipart/form-data"]["schema"]["properties"]
    assert set(parameters) == {*REQUEST_ONLY, *OPTION_NAMES}
    assert set(form) == {"description", "files", "root", "options", *OPTION_NAMES}
    for o in API_OPTIONS:
        parameter = parameters[o.name]
        assert parameter["in"] == "query" and parameter["description"] == o.description()
        schema = next((s for s in parameter["schema"].get("anyOf", []) if s.get("type") != "null"), parameter["schema"])
        field = form[o.name]
        if o.kind != "file":
            assert field["description"] == o.description()
        for declared in (schema, field) if o.kind != "file" else (schema,):
            assert declared.get("minimum") == o.minimum
            assert declared.get("maximum") == o.maximum
            assert declared.get("enum", []) == list(o.choice_values())
            expected = {"bool": "boolean", "int": "integer"}.get(o.kind, "array" if o.repeatable else "string")
            assert declared["type"] == expected, o.name


def _fastapi_query(option: Option) -> inspect.Parameter:
    """What FastAPI would be given to parse ``option`` itself: its type, bounds and description."""
    annotation: Any
    if option.repeatable:
        annotation, default = list[str], Query([], description=option.description())
    elif option.kind == "bool":
        annotation, default = bool | None, Query(None, description=option.description())
    elif option.kind == "int":
        annotation = int | None
        default = Query(None, ge=option.minimum, le=option.maximum, description=option.description())
    else:
        annotation, default = str | None, Query(None, description=option.description())
    return inspect.Parameter(option.name, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=annotation)


def test_option_parameters_are_what_fastapi_writes_for_the_declared_types() -> None:
    def endpoint(**options: Any) -> None:
        return None

    endpoint.__signature__ = inspect.Signature([_fastapi_query(o) for o in API_OPTIONS])  # type: ignore[attr-defined]
    app = FastAPI()
    app.post("/probe")(endpoint)
    generated = app.openapi()["paths"]["/probe"]["post"]["parameters"]
    assert generated == OPTION_PARAMETERS
    assert len(generated) == len(OPTION_NAMES) == len(API_OPTIONS)
    assert {p["name"] for p in generated} >= {"env", "view_3d"}


# --- the same defaults everywhere -------------------------------------------------------------


def test_defaults_are_the_declared_ones_from_every_source(tmp_path: Path) -> None:
    (tmp_path / "r.urdf").write_text('<robot name="r"><link name="a"/></robot>')
    ns = build_parser().parse_args(["check", "--no-config", str(tmp_path / "r.urdf")])
    sources = {
        "library": CheckOptions(),
        "configuration": Config().to_options(),
        "empty file": read_options({}, tmp_path, "file").to_options(),
        "command line": settings_for(ns, ns.paths[0]).to_options(),
        "request": check_options(request_config(RawOptions(), MAX_SAMPLES, tmp_path), MAX_SAMPLES),
    }
    checked = [o for o in OPTIONS if o.name in _effective(CheckOptions())]
    # every request option (extend-select is folded into select, checked there)
    assert {o.name for o in checked} == {o.name for o in OPTIONS if o.api} - {"extend_select"}
    for source, options in sources.items():
        effective = _effective(options)
        for o in checked:
            assert effective[o.name] == _default(o), (source, o.name)
    assert option("output-format").default == "full" and Config().output_format is None
    from geomcheck.cli import DEFAULT_FORMAT

    assert option("output-format").default == DEFAULT_FORMAT


# --- one validation: a value is refused alike wherever it comes from -------------------------


def _refusal_everywhere(o: Option, file_value: Any, text: str) -> list[str]:
    """The error of ``o`` set to a bad value in a file, as a flag and in a request."""
    messages = []
    with pytest.raises(UsageError) as err:
        read_options({o.key: file_value}, Path.cwd(), "file")
    messages.append(str(err.value))
    for where, places, make in (
        ("flag", "check", lambda: _flag_config(o, text)),
        ("request", "api", lambda: _request_config(o, text)),
    ):
        if places in o.where:
            with pytest.raises(UsageError) as err:
                make()
            messages.append(f"{where}: {err.value}")
    return messages


def _flag_config(o: Option, text: str) -> Config:
    ns = build_parser().parse_args(["check", "--no-config", str(o.flag), text, "r.urdf"])
    return settings_for(ns, ns.paths[0])


def _request_config(o: Option, text: str) -> Config:
    raw = RawOptions()
    raw.add(o.name, text, "query")
    return request_config(raw, MAX_SAMPLES, Path.cwd())


@pytest.mark.parametrize("o", [o for o in OPTIONS if o.kind == "int"], ids=lambda o: o.key)
def test_integer_bounds_are_one_rule(o: Option, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert o.minimum is not None
    for bad in (o.minimum - 1, *(() if o.maximum is None else (o.maximum + 1,))):
        messages = _refusal_everywhere(o, bad, str(bad))
        assert len(messages) == 3
        assert all("must be " in m and f"got {bad}" in m for m in messages), messages
    good = o.maximum if o.maximum is not None else o.minimum
    assert getattr(read_options({o.key: good}, tmp_path, "file"), o.name) == good
    assert getattr(_request_config(o, str(good)), o.name) == good


def test_seed_range_is_the_same_in_file_flag_and_request(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    messages = _refusal_everywhere(option("seed"), SEED_MAX + 1, str(SEED_MAX + 1))
    assert messages == [
        "file: seed must be between 0 and 4294967295, got 4294967296",
        "flag: command line: --seed must be between 0 and 4294967295, got 4294967296",
        "request: request: seed must be between 0 and 4294967295, got 4294967296",
    ]
    assert _refusal_everywhere(option("seed"), -1, "-1")[1] == (
        "flag: command line: --seed must be between 0 and 4294967295, got -1"
    )


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_pose_values_must_be_finite_everywhere(value: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    messages = _refusal_everywhere(option("pose"), {"elbow": float(value)}, f"elbow={value}")
    assert messages == [
        f"file: pose elbow must be finite, got {float(value)!r}",
        f"flag: command line: --pose elbow must be finite, got {float(value)!r}",
        f"request: request: pose elbow must be finite, got {float(value)!r}",
    ]
    assert read_options({"pose": {"elbow": 0.5}}, tmp_path, "file").pose == {"elbow": 0.5}


@pytest.mark.parametrize("o", [o for o in OPTIONS if o.choice_values()], ids=lambda o: o.key)
def test_choices_are_one_rule(o: Option, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    messages = _refusal_everywhere(o, "bogus", "bogus")
    assert len(messages) == 1 + ("check" in o.where) + ("api" in o.where)
    for message in messages:
        assert f"invalid value 'bogus'; valid choices: {', '.join(sorted(o.choice_values()))}" in message
    first = o.choice_values()[0]
    assert getattr(read_options({o.key: first}, tmp_path, "file"), o.name) == first
    if o.api:
        assert getattr(_request_config(o, f" {first} "), o.name) == first


# --- the docs --------------------------------------------------------------------------------


def _docs_script() -> ModuleType:
    spec = importlib.util.spec_from_file_location("options_docs", REPO / "scripts" / "options_docs.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_docs_tables_are_the_generated_ones() -> None:
    script = _docs_script()
    for name, (path, make) in script.TABLES.items():
        text = path.read_text(encoding="utf-8")
        assert script.updated(text, name, make()) == text, f"{path.name}: run python scripts/options_docs.py"
    config_rows = script.config_table().splitlines()[2:]
    assert [row.split(" | ")[0] for row in config_rows] == [f"| `{o.key}`" for o in OPTIONS]
    api_rows = script.api_table().splitlines()[2:]
    assert [row.split(" | ")[0] for row in api_rows] == [f"| `{n}`" for n in (*REQUEST_ONLY, *OPTION_NAMES)]


def test_descriptions_say_bounds_choices_and_defaults() -> None:
    described: Mapping[str, str] = {o.key: o.description() for o in OPTIONS}
    assert described["seed"] == "collision-matrix sampling seed (0 to 4294967295; default 0)"
    assert described["backend"] == "collision backend (one of coal, fcl; default coal)"
    assert described["pose"] == "default-pose joint value JOINT=VALUE [rad or m] (repeatable)"
    assert described["samples"].endswith("(at least 1; default 10000)")
