"""From option values to what a check runs with: the one path every surface takes.

Each surface gathers values by configuration key: a configuration file as TOML holds them,
the command line's flags and the service's request fields as strings (:func:`from_texts`
reads those as a file would hold them), the library's keywords as Python values.
:func:`read_options` validates them, each by its option's one validator, into a
:class:`Config`, which :func:`merge` puts over the configuration file that applies; a
:class:`Config` becomes the :class:`geomcheck.options.CheckOptions` of a run by
:func:`check_options`, from the declaration: an unset option takes its declared default.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from geomcheck.diagnostics import Severity
from geomcheck.errors import UsageError
from geomcheck.option_spec.declaration import BY_KEY, OPTIONS, Option
from geomcheck.option_spec.validation import did_you_mean
from geomcheck.options import CheckOptions, Selection
from geomcheck.thresholds import Thresholds


@dataclass(frozen=True)
class Config:
    """Settings from one source (a file, the command line, a request, the library's keywords);
    ``None`` or empty means "not set". One field per option of :data:`OPTIONS` (its ``name``),
    and the file it came from (``path``).

    ``thresholds`` holds the overrides ``{family: {field: value}}`` (units as in
    :mod:`geomcheck.thresholds`), already validated.
    """

    path: Path | None = None
    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()
    extend_select: tuple[str, ...] = ()
    severity: Mapping[str, Severity] = field(default_factory=dict)
    thresholds: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    per_link_ignores: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    per_joint_ignores: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    packages: Mapping[str, Path] = field(default_factory=dict)
    search: tuple[Path, ...] = ()
    args: Mapping[str, str] = field(default_factory=dict)
    env: Mapping[str, str] = field(default_factory=dict)
    srdf: Path | None = None
    pose: Mapping[str, float] = field(default_factory=dict)
    pose_name: str | None = None
    matrix: bool | None = None
    sweep: bool | None = None
    view_3d: bool | None = None
    samples: int | None = None
    seed: int | None = None
    backend: str | None = None
    semantics: str | None = None
    fail_on: Severity | None = None
    output_format: str | None = None
    baseline: Path | None = None

    def selection(self) -> Selection:
        """The rule selection: ``select`` (``ALL`` when unset) plus ``extend-select``, minus ``ignore``."""
        select = (*(self.select if self.select is not None else ("ALL",)), *self.extend_select)
        return Selection(
            select=select,
            ignore=self.ignore,
            severity=dict(self.severity),
            per_link_ignore=dict(self.per_link_ignores),
            per_joint_ignore=dict(self.per_joint_ignores),
        )

    def to_options(self) -> CheckOptions:
        """The :class:`CheckOptions` these settings ask for (:func:`check_options`)."""
        return check_options(self)


assert {f.name for f in fields(Config)} == {"path", *(o.name for o in OPTIONS)}, "one Config field per option"


def merge(base: Config, top: Config) -> Config:
    """``top`` (the command line, a request, keywords) over ``base`` (a file).

    Scalars of ``top`` win when set; maps are merged key by key; ``search``, ``ignore`` and
    ``extend-select`` add up. A ``select`` in ``top`` replaces both ``select`` and
    ``ignore`` of ``base``, as in ruff: asking for rules on the command line gets them.
    """
    values: dict[str, Any] = {}
    for f in fields(Config):
        low, high = getattr(base, f.name), getattr(top, f.name)
        if isinstance(low, Mapping):
            if f.name == "thresholds":
                merged = {fam: {**low.get(fam, {}), **high.get(fam, {})} for fam in sorted({*low, *high})}
                values[f.name] = merged
            else:
                values[f.name] = {**low, **high}
        elif f.name in ("search", "extend_select"):
            values[f.name] = (*low, *high)
        elif f.name == "ignore":
            values[f.name] = high if top.select is not None else (*low, *high)
        else:
            values[f.name] = high if high is not None else low
    values["path"] = base.path
    return Config(**values)


def _as_written(key: str) -> str:
    return key


def from_texts(texts: Mapping[str, Sequence[Any]], label: Callable[[Option], str]) -> dict[str, Any]:
    """Values given as strings (flags, request fields; argparse may have typed them), by
    configuration key, as a configuration file would hold them (:meth:`Option.from_text`);
    ``label`` names an option in errors as the user wrote it."""
    return {key: BY_KEY[key].from_text(values, label(BY_KEY[key])) for key, values in texts.items()}


def read_options(
    values: Mapping[str, Any],
    base_dir: Path,
    where: str,
    path: Path | None = None,
    label: Callable[[str], str] = _as_written,
) -> Config:
    """The one path from any surface's option values to a :class:`Config`: ``values`` by
    configuration key (kebab-case) as a file holds them, each validated by its option's one
    validator, unknown keys refused with a did-you-mean. A surface then :func:`merge` s the
    result over the configuration file that applies.

    ``where`` names the source in error messages (the file, ``command line``, ``request``),
    ``label`` turns a key into the name the user wrote (``--select`` on the command line),
    ``base_dir`` anchors relative paths, ``path`` is the file the values came from.
    """
    checked: dict[str, Any] = {}
    for key, value in values.items():
        if key not in BY_KEY:
            hint = did_you_mean(key, BY_KEY)
            raise UsageError(f"{where}: unknown configuration key {key!r}{hint}; valid keys: {', '.join(BY_KEY)}")
        option = BY_KEY[key]
        try:
            checked[option.name] = option.validate(value, label(key), base_dir)
        except UsageError as err:
            raise UsageError(f"{where}: {err}") from None
    return replace(Config(path=path), **checked)


# the fields of CheckOptions that are not one option's value: built from several, or the run's own (the
# output decides the drawings)
_BUILT = ("thresholds", "selection", "workers", "drawings")
_RUN_FIELDS = tuple(f.name for f in fields(CheckOptions) if f.name not in _BUILT)
_RUN_OPTIONS = tuple(BY_KEY[name.replace("_", "-")] for name in _RUN_FIELDS)


def _default(option: Option) -> Any:
    """The value of an unset option in a run: its declared default, validated as a file's value;
    ``None`` when it has none or when the thresholds hold it."""
    if option.default is None or option.default_in_thresholds:
        return None
    return option.validate(option.default, option.key, Path("."))


def check_options(config: Config) -> CheckOptions:
    """The :class:`CheckOptions` ``config`` asks for: every option that is a field of a run
    takes the configured value, else its declared default; the thresholds and the rule
    selection are built from their options."""
    values: dict[str, Any] = {}
    for option in _RUN_OPTIONS:
        value = getattr(config, option.name)
        if value is None:
            value = _default(option)
        values[option.name] = dict(value) if isinstance(value, Mapping) else value
    return CheckOptions(
        **values, thresholds=Thresholds().with_overrides(config.thresholds), selection=config.selection()
    )


__all__ = ["Config", "check_options", "from_texts", "merge", "read_options"]
