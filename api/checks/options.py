"""Check options from a request: query parameters, form fields and an ``options`` JSON object.

The options are those of :data:`geomcheck.option_spec.OPTIONS` that apply to the API, under
their snake_case names (``args``, ``srdf`` as a path in the upload, ``samples``, ``seed``,
``pose``, ``select``...): names, kinds, bounds and help come from that declaration.
Repeatable options (``args``, ``pose``, the rule selection) collect every source and take
comma-separated selectors; a single-valued option given twice with different values is a
usage error. The values are read by :func:`geomcheck.option_spec.read_options`, by each
option's one validator, exactly as command-line flags and configuration keys are.
"""

from __future__ import annotations

import difflib
import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from geomcheck.errors import UsageError
from geomcheck.option_spec import Config, Option, from_texts, options_where, read_options
from geomcheck.option_spec import check_options as spec_check_options
from geomcheck.options import CheckOptions
from geomcheck.thresholds import Thresholds

API_OPTIONS: tuple[Option, ...] = options_where("api")
OPTION_NAMES = tuple(o.name for o in API_OPTIONS)
REPEATABLE = tuple(o.name for o in API_OPTIONS if o.repeatable)
SINGLE = tuple(o.name for o in API_OPTIONS if not o.repeatable)
MAX_VALUES = 256  # values of one repeatable option [count]
MAX_VALUE_LENGTH = 4096  # one option value [characters]
MAX_JSON_DEPTH = 8  # nesting of the options JSON object [levels]
MAX_JSON_LENGTH = MAX_VALUES * MAX_VALUE_LENGTH  # the options JSON text [characters]
REQUEST_ONLY = ("root", "wait", "cache", "verify_fixes")  # parameters of the request itself, not check options
VALID_NAMES = (*OPTION_NAMES, *REQUEST_ONLY)


def unknown_option(name: str, source: str) -> str:
    """The message for an unknown option ``name``, with the closest valid name when one is near."""
    near = difflib.get_close_matches(name, VALID_NAMES, n=1, cutoff=0.6)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    return f"unknown option {name!r} in {source}{hint}"


@dataclass
class RawOptions:
    """Option values as strings, by name, gathered from every source of one request."""

    values: dict[str, list[str]] = field(default_factory=dict)

    def add(self, name: str, value: str, source: str) -> None:
        if name not in OPTION_NAMES:
            raise UsageError(f"{unknown_option(name, source)}; valid names: {', '.join(VALID_NAMES)}")
        if len(value) > MAX_VALUE_LENGTH:
            raise UsageError(f"option {name} is longer than {MAX_VALUE_LENGTH} characters")
        current = self.values.setdefault(name, [])
        if name in SINGLE and current and current[0] != value:
            raise UsageError(f"option {name} given twice with different values ({current[0]!r}, {value!r})")
        if name in SINGLE and current:
            return
        if len(current) >= MAX_VALUES:
            raise UsageError(f"option {name} given more than {MAX_VALUES} times")
        current.append(value)

    def add_pairs(self, pairs: Iterable[tuple[str, str]], source: str) -> None:
        """Add every pair; every problem is reported at once (one :class:`UsageError`)."""
        problems: list[str] = []
        unknown = False
        for name, value in pairs:
            if name not in OPTION_NAMES:
                problems.append(unknown_option(name, source))
                unknown = True
                continue
            try:
                self.add(name, value, source)
            except UsageError as err:
                problems.append(str(err))
        if problems:
            valid = f"; valid names: {', '.join(VALID_NAMES)}" if unknown else ""
            raise UsageError("; ".join(dict.fromkeys(problems)) + valid)

    def add_json(self, text: str) -> None:
        """Options from the JSON object ``text`` (``{"samples": 500, "args": {"k": "v"}, ...}``)."""
        if len(text) > MAX_JSON_LENGTH:
            raise UsageError(f"options field is longer than {MAX_JSON_LENGTH} characters")
        depth = json_depth(text)
        if depth > MAX_JSON_DEPTH:  # before parsing: json.loads recurses once per level
            raise UsageError(f"options field nests {depth} levels deep; at most {MAX_JSON_DEPTH} are allowed")
        try:
            data = json.loads(text)
        except ValueError as err:
            raise UsageError(f"options field is not valid JSON: {err}") from None
        if not isinstance(data, dict):
            raise UsageError("options field must be a JSON object")
        self.add_pairs(
            ((name, item) for name, value in data.items() for item in _json_values(name, value)), "options JSON"
        )

    def one(self, name: str) -> str | None:
        values = self.values.get(name)
        return values[0] if values else None


def json_depth(text: str) -> int:
    """Deepest nesting of brackets and braces in the JSON ``text`` (outside strings), in one pass."""
    depth = deepest = 0
    in_string = escaped = False
    for char in text:
        if in_string:
            if escaped:
                escaped = False
            elif char == "\\":
                escaped = True
            elif char == '"':
                in_string = False
        elif char == '"':
            in_string = True
        elif char in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "]}":
            depth -= 1
    return deepest


def _json_values(name: str, value: Any) -> list[str]:
    if name in REPEATABLE and isinstance(value, Mapping):
        return [f"{k}={_scalar(name, v)}" for k, v in value.items()]
    if name in REPEATABLE and isinstance(value, list):
        return [_scalar(name, v) for v in value]
    return [_scalar(name, value)]


def _scalar(name: str, value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float | str):
        return str(value)
    raise UsageError(f"option {name} must be a string, number or boolean in the options JSON")


def config_data(raw: RawOptions, max_samples: int) -> dict[str, Any]:
    """The raw values as configuration keys (kebab-case, typed) for :func:`geomcheck.option_spec.read_options`.

    ``srdf`` is left out: it names a file of the upload, which :mod:`api.uploads.body` locates.
    ``samples`` is held to the service's ``max_samples`` as well."""
    texts = {o.key: raw.values[o.name] for o in API_OPTIONS if raw.values.get(o.name) and o.kind != "file"}
    data = from_texts(texts, lambda option: option.name)
    samples = data.get("samples")
    if isinstance(samples, int) and not 1 <= samples <= max_samples:
        raise UsageError(f"samples must be between 1 and {max_samples}, got {samples}")
    return data


def request_config(raw: RawOptions, max_samples: int, base_dir: Path, srdf: Path | None = None) -> Config:
    """The options of a request as a :class:`Config`, validated by the library's own parser
    (unknown rule codes get a did-you-mean); ``srdf`` is the SRDF already located in the upload."""
    config = read_options(config_data(raw, max_samples), base_dir, "request")
    return replace(config, srdf=srdf)


MAX_COUNT_FACTOR = 10  # an uploaded configuration may raise a count threshold to this many times its default [ratio]


def check_options(config: Config, max_samples: int | None = None) -> CheckOptions:
    """:class:`CheckOptions` of ``config`` for the service: one process per check, no progress bars.

    ``config`` may come from a configuration file inside the upload: it is held to the API's
    limits as the request's own options are (``samples`` up to ``max_samples``, by default the
    service's ``max_samples`` setting; count thresholds such as ``surface_samples`` up to
    :data:`MAX_COUNT_FACTOR` times their default), a :class:`UsageError` naming the key otherwise.
    """
    if max_samples is None:
        from api.settings import Settings

        max_samples = Settings().max_samples
    if config.samples is not None and config.samples > max_samples:
        raise UsageError(f"samples must be between 1 and {max_samples}, got {config.samples}")
    defaults = Thresholds()
    for family, values in config.thresholds.items():
        for name, value in values.items():
            default = getattr(getattr(defaults, family, None), name, None)
            if isinstance(default, int) and not isinstance(default, bool) and value > default * MAX_COUNT_FACTOR:
                most = default * MAX_COUNT_FACTOR
                raise UsageError(f"thresholds.{family}.{name} must be at most {most} in the service, got {value}")
    return replace(spec_check_options(config), workers=1)
