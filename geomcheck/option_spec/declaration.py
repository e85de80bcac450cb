"""Every check option declared once (:data:`OPTIONS`), with the one validator of each."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from geomcheck.diagnostics import Severity
from geomcheck.option_spec.validation import (
    _choice,
    _expect,
    _path,
    _scalar_text,
    _selector,
    _selectors,
    _severity,
    _table,
    _thresholds,
    finite_number,
    integer_in,
    parse_assignment,
    parse_bool,
    parse_float,
    parse_int,
)
from geomcheck.options import BACKENDS, SEMANTICS
from geomcheck.thresholds import Thresholds

SEED_MAX = 2**32 - 1  # the largest sampling seed: one unsigned 32-bit word, the bound the service always had

Kind = Literal["bool", "int", "choice", "text", "file", "path", "folders", "pairs", "selectors", "table"]
Where = Literal["check", "matrix", "config", "api"]
# flag groups of ``geomcheck check`` (None: the parser's own, beside the paths)
Group = Literal["sources", "output", "exit status", "rule selection", "checks", "baseline"]
REPEATABLE_KINDS = ("folders", "pairs", "selectors")

Validator = Callable[[Any, str, Path], Any]


@dataclass(frozen=True)
class Option:
    """One option. ``key`` is its configuration key; ``name`` (snake_case) is its
    :class:`geomcheck.config.Config` field and its name in the service's requests.

    ``default`` is the built-in value as a user would write it (``None``: none); ``minimum``
    and ``maximum`` bound an integer; ``choices`` lists a choice's values (a callable when
    they are known only once their module is imported). ``flag`` is the command-line flag of
    ``check``, ``diff`` and ``fix`` (``None``: file only) in flag group ``group``;
    ``matrix`` puts it on ``geomcheck matrix`` too; ``api`` makes it a request option.
    ``values`` says what a ``pairs`` option maps names to: ``text``, ``number`` or ``folder``.
    ``type_text`` overrides the derived type in the docs; ``flag_note`` says how a flag
    meets the file's value when it does not simply win. ``default_in_thresholds``: the
    check's own default is that of :mod:`geomcheck.thresholds` (``samples``, ``seed``).
    """

    key: str
    kind: Kind
    help: str
    default: Any = None
    unit: str = ""
    minimum: int | None = None
    maximum: int | None = None
    choices: tuple[str, ...] | Callable[[], tuple[str, ...]] = ()
    flag: str | None = None
    metavar: str | None = None
    group: Group | None = None
    matrix: bool = False
    api: bool = False
    values: Literal["text", "number", "folder"] = "text"
    type_text: str = ""
    flag_note: str = ""
    api_note: str = ""
    default_in_thresholds: bool = False  # unset, the check takes the value of its thresholds, not ``default``

    @property
    def name(self) -> str:
        return self.key.replace("-", "_")

    @property
    def dest(self) -> str:
        """The argparse attribute of the flag."""
        return (self.flag or "").lstrip("-").replace("-", "_")

    @property
    def where(self) -> frozenset[Where]:
        places: set[Where] = {"config"}
        if self.flag is not None:
            places.add("check")
        if self.matrix:
            places.add("matrix")
        if self.api:
            places.add("api")
        return frozenset(places)

    @property
    def repeatable(self) -> bool:
        return self.kind in REPEATABLE_KINDS

    def choice_values(self) -> tuple[str, ...]:
        return self.choices() if callable(self.choices) else self.choices

    def default_text(self) -> str:
        """The default as the docs and help show it (``""`` when there is none to show)."""
        if isinstance(self.default, bool):
            return "true" if self.default else "false"
        if isinstance(self.default, list | tuple):
            return ",".join(str(v) for v in self.default)
        return "" if self.default is None or self.default == {} else str(self.default)

    def description(self) -> str:
        """The one-line help with its unit, choices, bounds and default: the flag's help, the
        API parameter's description and the docs' wording."""
        notes = []
        if self.choice_values():
            notes.append(f"one of {', '.join(self.choice_values())}")
        if self.kind == "int":
            notes.append(f"at least {self.minimum}" if self.maximum is None else f"{self.minimum} to {self.maximum}")
        if self.default_text():
            notes.append(f"default {self.default_text()}")
        if self.repeatable:
            notes.append("repeatable")
        unit = f" [{self.unit}]" if self.unit else ""
        syntax = f" {self.metavar}" if self.kind == "pairs" and self.metavar else ""
        return f"{self.help}{syntax}{unit}" + (f" ({'; '.join(notes)})" if notes else "")

    def validate(self, value: Any, what: str, base: Path) -> Any:
        """The checked value of the option as :class:`geomcheck.config.Config` holds it;
        ``what`` names it in errors (the key, or the flag), ``base`` anchors relative paths.
        The one validation of the option, whatever the source."""
        return VALIDATORS[self.key](value, what, base)

    def from_text(self, values: Sequence[Any], what: str) -> Any:
        """Flag or request values (strings, or what argparse already typed) as a file would
        hold them, for :meth:`validate`; a single-valued option takes the first."""
        if self.kind == "selectors":
            return [s.strip() for v in values for s in str(v).split(",") if s.strip()]
        if self.kind == "folders":
            return [str(v) for v in values]
        if self.kind == "pairs":
            pairs = [parse_assignment(v, what) for v in values]
            if self.values == "number":
                return {k: parse_float(v, f"{what} {k}") for k, v in pairs}
            return dict(pairs)
        value = values[0]
        if self.kind == "bool" and isinstance(value, str):
            return parse_bool(value, what)
        if self.kind == "int" and isinstance(value, str):
            return parse_int(value, what)
        if self.kind == "choice" and isinstance(value, str):
            return value.strip()
        return value


def _output_formats() -> tuple[str, ...]:
    from geomcheck.report import FORMATS  # the report package is heavy and imports the options

    return tuple(sorted(FORMATS))


def _severities() -> tuple[str, ...]:
    return tuple(s.value for s in Severity)


_SAMPLING = Thresholds().self_collision
SELECTOR_TEXT = "codes, prefixes (GC3), family names (fit), rule names or ALL"

OPTIONS: tuple[Option, ...] = (
    Option("packages", "pairs", "ROS package location", flag="--package", metavar="NAME=DIR",
           group="sources", matrix=True, values="folder", flag_note="merged name by name"),
    Option("search", "folders", "folder to discover ROS packages in", flag="--search", metavar="DIR",
           group="sources", matrix=True, flag_note="adds"),
    Option("args", "pairs", "xacro argument", flag="--arg", metavar="NAME=VALUE",
           group="sources", matrix=True, api=True, flag_note="merged name by name"),
    Option("env", "pairs", "value of an environment variable the description reads ($(env NAME), $(optenv NAME)); "
           "untrusted runs and the service never read their own environment: $(optenv) takes its default there",
           flag="--env", metavar="NAME=VALUE", group="sources", matrix=True, api=True, flag_note="merged name by name"),
    Option("srdf", "file", "SRDF to audit and to read named poses from (in the service: its path in the upload); "
           "a xacro SRDF (NAME.srdf.xacro) is expanded with the description's packages and args",
           flag="--srdf", metavar="FILE",
           group="checks", matrix=True, api=True,
           api_note="in a form also an `srdf` file part"),
    Option("samples", "int", "random configurations of the collision matrix", default=_SAMPLING.samples,
           minimum=1, flag="--samples", group="checks", matrix=True, api=True, default_in_thresholds=True,
           api_note="at most the service's `GEOMCHECK_MAX_SAMPLES`"),
    Option("seed", "int", "collision-matrix sampling seed", default=_SAMPLING.seed, minimum=0, maximum=SEED_MAX,
           flag="--seed", group="checks", matrix=True, api=True, default_in_thresholds=True),
    Option("backend", "choice", "collision backend", default="coal", choices=BACKENDS, flag="--backend",
           group="checks", matrix=True, api=True),
    Option("semantics", "choice", "which link pairs exist: moveit, every two links with collision geometry; "
           "pinocchio, not two links joined only by fixed joints (one body, as in Pinocchio)",
           default="moveit", choices=SEMANTICS, flag="--semantics", group="checks", matrix=True, api=True),
    Option("fail-on", "choice", "lowest severity that fails", default="error", choices=_severities,
           flag="--fail-on", group="exit status", api=True),
    Option("matrix", "bool", "also compute the collision matrix (slow)", default=False, flag="--matrix",
           group="checks", api=True),
    Option("sweep", "bool", "sweep continuous joints", default=True, flag="--sweep", group="checks", api=True),
    Option("pose", "pairs", "default-pose joint value", unit="rad or m", flag="--pose",
           metavar="JOINT=VALUE", group="checks", matrix=True, api=True, values="number",
           flag_note="merged joint by joint"),
    Option("pose-name", "text", "SRDF group_state to use as the default pose", flag="--pose-name", metavar="NAME",
           group="checks", matrix=True, api=True),
    Option("select", "selectors", f"only these rules: {SELECTOR_TEXT}", default=("ALL",), flag="--select",
           metavar="CODES", group="rule selection", api=True, flag_note="replaces the file's `select` and `ignore`"),
    Option("ignore", "selectors", "not these rules", flag="--ignore", metavar="CODES", group="rule selection",
           api=True, flag_note="adds"),
    Option("extend-select", "selectors", "these rules in addition to select", flag="--extend-select",
           metavar="CODES", group="rule selection", api=True, flag_note="adds"),
    Option("severity", "table", "severity overrides; the longest matching selector wins",
           type_text="table selector → `error`/`warning`/`info`"),
    Option("per-link-ignores", "table", "rules not reported for a link (or for a pair with the link)",
           type_text="table link → selectors"),
    Option("per-joint-ignores", "table", "rules not reported for a joint", type_text="table joint → selectors"),
    Option("thresholds", "table", "thresholds of the checks by family (below)",
           type_text="table family → table field → number"),
    Option("output-format", "choice", "output format", default="full", choices=_output_formats, flag="--format",
           group="output"),
    Option("baseline", "path", "baseline to report against (its findings are not reported)", flag="--baseline",
           metavar="FILE", group="baseline"),
    Option("view-3d", "bool", "the interactive 3D view in the HTML report (robot, collision geometry, findings; "
           "adds the robot's meshes, decimated, to the report)", default=True, flag="--view-3d", group="output",
           api=True),
)  # fmt: skip

BY_KEY = {o.key: o for o in OPTIONS}
BY_NAME = {o.name: o for o in OPTIONS}


def option(key: str) -> Option:
    """The option with configuration key (or snake_case name) ``key``."""
    return BY_KEY.get(key) or BY_NAME[key]


def _pairs_of(kind: Literal["text", "number", "folder"]) -> Validator:
    def validate(value: Any, what: str, base: Path) -> dict[str, Any]:
        table = _table(value, what)
        if kind == "number":
            return {k: finite_number(x, f"{what} {k}") for k, x in table.items()}
        if kind == "folder":
            return {k: _path(d, f"{what}.{k}", base, "dir") for k, d in table.items()}
        return {k: _scalar_text(s, f"{what}.{k}") for k, s in table.items()}

    return validate


def _by_selector(value: Any, what: str, base: Path) -> dict[str, tuple[str, ...]]:
    return {k: _selectors(s, f"{what}.{k}") for k, s in _table(value, what).items()}


def _integer(key: str) -> Validator:
    spec = BY_KEY[key]
    assert spec.minimum is not None
    lo, hi = spec.minimum, spec.maximum
    return lambda v, w, b: integer_in(v, w, lo, hi)


def _choice_of(key: str) -> Validator:
    spec = BY_KEY[key]
    return lambda v, w, b: _choice(v, w, spec.choice_values())


# configuration key -> the option's one validator (value as in a file, name for errors, base folder)
VALIDATORS: dict[str, Validator] = {
    "packages": _pairs_of("folder"),
    "search": lambda v, w, b: tuple(_path(d, w, b, "dir") for d in _expect(v, list, w, "a list of folders")),
    "args": _pairs_of("text"),
    "env": _pairs_of("text"),
    "srdf": lambda v, w, b: _path(v, w, b, "file"),
    "samples": _integer("samples"),
    "seed": _integer("seed"),
    "backend": _choice_of("backend"),
    "semantics": _choice_of("semantics"),
    "fail-on": lambda v, w, b: _severity(v, w),
    "matrix": lambda v, w, b: _expect(v, bool, w, "true or false"),
    "sweep": lambda v, w, b: _expect(v, bool, w, "true or false"),
    "pose": _pairs_of("number"),
    "pose-name": lambda v, w, b: _expect(v, str, w, "a string"),
    "select": lambda v, w, b: _selectors(v, w),
    "ignore": lambda v, w, b: _selectors(v, w),
    "extend-select": lambda v, w, b: _selectors(v, w),
    "severity": lambda v, w, b: {_selector(k, w): _severity(s, f"{w}.{k}") for k, s in _table(v, w).items()},
    "per-link-ignores": _by_selector,
    "per-joint-ignores": _by_selector,
    "thresholds": lambda v, w, b: _thresholds(v, w),
    "output-format": _choice_of("output-format"),
    "baseline": lambda v, w, b: b / _expect(v, str, w, "a path"),
    "view-3d": lambda v, w, b: _expect(v, bool, w, "true or false"),
}
assert set(VALIDATORS) == set(BY_KEY), "every option has exactly one validator"


def options_where(place: Where) -> tuple[Option, ...]:
    """The options that apply to ``place``, in declaration order."""
    return tuple(o for o in OPTIONS if place in o.where)
