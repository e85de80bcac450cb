"""Configuration: ``[tool.geomcheck]`` in a pyproject.toml, or the same keys at the top level
of a geomcheck.toml.

The file is found from the description's folder upwards (``geomcheck.toml`` wins over
``pyproject.toml`` in one folder; a pyproject.toml without ``[tool.geomcheck]`` is passed
over); the search stops at the root of the git work tree or of the file system. Relative
paths in a file are relative to the file's folder. Command-line flags are parsed into a
:class:`Config` by the same code and :func:`merge`d on top: flags win.

Every key and rule code is checked: an unknown one is a :class:`UsageError` naming it.
"""

from __future__ import annotations

import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from geomcheck.diagnostics import Severity
from geomcheck.errors import UsageError
from geomcheck.option_spec import OPTIONS, did_you_mean, edit_distance, option, resolve_selector
from geomcheck.options import CheckOptions, Selection
from geomcheck.thresholds import Thresholds

CONFIG_FILES = ("geomcheck.toml", "pyproject.toml")
__all__ = [  # did_you_mean, edit_distance and resolve_selector live with the options' validation
    "CONFIG_FILES",
    "KEYS",
    "Config",
    "did_you_mean",
    "discover_config",
    "edit_distance",
    "find_config",
    "load_config",
    "merge",
    "parse_config",
    "read_toml",
    "resolve_selector",
]


@dataclass(frozen=True)
class Config:
    """Settings from one file or from the command line; ``None`` or empty means "not set".

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
        """The :class:`CheckOptions` these settings ask for, defaults where unset."""
        return CheckOptions(
            args=dict(self.args),
            env=dict(self.env),
            srdf=self.srdf,
            pose=dict(self.pose),
            pose_name=self.pose_name,
            backend=self.backend or option("backend").default,
            semantics=self.semantics or option("semantics").default,
            matrix=self.matrix if self.matrix is not None else option("matrix").default,
            sweep=self.sweep if self.sweep is not None else option("sweep").default,
            view_3d=self.view_3d if self.view_3d is not None else option("view-3d").default,
            samples=self.samples,
            seed=self.seed,
            fail_on=self.fail_on or Severity(option("fail-on").default),
            thresholds=Thresholds().with_overrides(self.thresholds),
            selection=self.selection(),
        )


def merge(base: Config, top: Config) -> Config:
    """``top`` (the command line) over ``base`` (a file).

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


# --- reading -----------------------------------------------------------------------------


def find_config(start: Path, within: Path | None = None) -> Path | None:
    """The configuration file that applies to ``start`` (a file or folder), or ``None``.

    The search goes upwards and stops at a git root, and never leaves ``within`` when given
    (an uploaded bundle's own configuration must not come from outside it)."""
    folder = start if start.is_dir() else start.parent
    for directory in (folder.resolve(), *folder.resolve().parents):
        if within is not None and not directory.is_relative_to(within.resolve()):
            return None
        own = directory / "geomcheck.toml"
        if own.is_file():
            return own
        project = directory / "pyproject.toml"
        if project.is_file() and "geomcheck" in read_toml(project).get("tool", {}):
            return project
        if (directory / ".git").exists():
            return None
    return None


def read_toml(path: Path) -> dict[str, Any]:
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise UsageError(f"cannot read configuration {path}: {err.strerror}") from None
    except tomllib.TOMLDecodeError as err:
        raise UsageError(f"{path}: invalid TOML: {err}") from None


def load_config(path: Path) -> Config:
    """Settings of the file ``path``: its ``[tool.geomcheck]`` table for a pyproject.toml,
    its top level otherwise."""
    data = read_toml(path)
    if path.name == "pyproject.toml":
        data = data.get("tool", {}).get("geomcheck", {})
    return parse_config(data, base_dir=path.parent.resolve(), where=str(path), path=path.resolve())


def discover_config(description: Path) -> Config:
    """Settings of the file that applies to ``description``; defaults when there is none."""
    found = find_config(description)
    return load_config(found) if found else Config()


# --- validation --------------------------------------------------------------------------

Parser = Callable[[Any, str, Path], Any]

# key as written in a file -> (Config field, the option's validator): every option of
# geomcheck.option_spec, nothing else
KEYS: dict[str, tuple[str, Parser]] = {o.key: (o.name, o.validate) for o in OPTIONS}


def _raise(message: str) -> Any:
    raise UsageError(message)


def parse_config(
    data: Mapping[str, Any],
    base_dir: Path,
    where: str,
    path: Path | None = None,
    label: Callable[[str], str] = lambda key: key,
) -> Config:
    """Validate ``data`` (file keys, kebab-case) into a :class:`Config`.

    ``where`` names the source in error messages (the file, or ``command line``) and
    ``label`` turns a key into the name the user wrote (``--select`` on the command line).
    """
    values: dict[str, Any] = {}
    for key, value in data.items():
        if key not in KEYS:
            _raise(
                f"{where}: unknown configuration key {key!r}{did_you_mean(key, KEYS)}; valid keys: {', '.join(KEYS)}"
            )
        name, parse = KEYS[key]
        try:
            values[name] = parse(value, label(key), base_dir)
        except UsageError as err:
            raise UsageError(f"{where}: {err}") from None
    return replace(Config(path=path), **values)
