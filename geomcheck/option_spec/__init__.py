"""Every check option declared once, the one validation of each, and the one path from any
surface's values to what a check runs with.

An :class:`Option` names a configuration key (kebab-case), its kind, its built-in default,
unit, one-line help, valid range or choices, and where it applies: the configuration file
(always), the flags of ``geomcheck check`` (with ``diff`` and ``fix``), of ``geomcheck
matrix``, and the request options of the service. Everything else is derived from
:data:`OPTIONS`: the keys and validators of :mod:`geomcheck.config`, the flags of
:mod:`geomcheck.cli`, the option names, parsing, query parameters and form fields of the
API (:mod:`api.checks.options`, :mod:`api.http.openapi`) and the tables of ``docs/ci.md`` and
``docs/api.md`` (``scripts/options_docs.py``).

Values arrive as TOML values (the file), argparse values or strings (flags, requests):
:meth:`Option.from_text` turns strings into the values a file would hold, and
:meth:`Option.validate` is then the one check every source goes through, so a bound or a
choice is the same everywhere (``seed`` within 0..2^32-1, ``pose`` values finite).

:mod:`~geomcheck.option_spec.declaration` holds :data:`OPTIONS`,
:mod:`~geomcheck.option_spec.validation` the validators, and
:mod:`~geomcheck.option_spec.settings` the path every surface takes: :func:`read_options`
into a :class:`Config` over the configuration file (:func:`merge`), then
:func:`check_options` into the run's :class:`geomcheck.options.CheckOptions`.
"""

from __future__ import annotations

from geomcheck.option_spec.declaration import (
    BY_KEY,
    BY_NAME,
    OPTIONS,
    REPEATABLE_KINDS,
    SEED_MAX,
    SELECTOR_TEXT,
    VALIDATORS,
    Group,
    Kind,
    Option,
    Validator,
    Where,
    option,
    options_where,
)
from geomcheck.option_spec.settings import Config, check_options, from_texts, merge, read_options
from geomcheck.option_spec.validation import (
    FAMILY_PREFIX,
    did_you_mean,
    edit_distance,
    finite_number,
    integer_in,
    parse_assignment,
    parse_bool,
    parse_float,
    parse_int,
    resolve_selector,
)
from geomcheck.options import BACKENDS, SEMANTICS

__all__ = [
    "BACKENDS",
    "BY_KEY",
    "BY_NAME",
    "FAMILY_PREFIX",
    "OPTIONS",
    "REPEATABLE_KINDS",
    "SEED_MAX",
    "SELECTOR_TEXT",
    "SEMANTICS",
    "VALIDATORS",
    "Config",
    "Group",
    "Kind",
    "Option",
    "Validator",
    "Where",
    "check_options",
    "did_you_mean",
    "edit_distance",
    "finite_number",
    "from_texts",
    "integer_in",
    "merge",
    "option",
    "options_where",
    "parse_assignment",
    "parse_bool",
    "parse_float",
    "parse_int",
    "read_options",
    "resolve_selector",
]
