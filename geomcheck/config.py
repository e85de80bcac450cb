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

import difflib
import tomllib
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from geomcheck.diagnostics import Severity
from geomcheck.errors import UsageError
from geomcheck.options import BACKENDS, SEMANTICS, CheckOptions, Selection
from geomcheck.rules import FAMILIES, all_rules, matches
from geomcheck.thresholds import Thresholds

CONFIG_FILES = ("geomcheck.toml", "pyproject.toml")
FAMILY_PREFIX = {name: prefix for prefix, name in FAMILIES.items()}  # "fit" -> "GC3"


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
    srdf: Path | None = None
    pose: Mapping[str, float] = field(default_factory=dict)
    pose_name: str | None = None
    matrix: bool | None = None
    sweep: bool | None = None
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

    def to_options(self, progress: bool = False) -> CheckOptions:
        """The :class:`CheckOptions` these settings ask for, defaults where unset."""
        return CheckOptions(
            args=dict(self.args),
            srdf=self.srdf,
            pose=dict(self.pose),
            pose_name=self.pose_name,
            backend=self.backend or "coal",
            semantics=self.semantics or "moveit",
            matrix=bool(self.matrix),
            sweep=self.sweep is not False,
            samples=self.samples,
            seed=self.seed,
            fail_on=self.fail_on or Severity.ERROR,
            thresholds=Thresholds().with_overrides(self.thresholds),
            selection=self.selection(),
            progress=progress,
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


def edit_distance(a: str, b: str) -> int:
    """Levenshtein distance (insertions, deletions, substitutions)."""
    row = list(range(len(b) + 1))
    for i, ca in enumerate(a, 1):
        prev, row[0] = row[0], i
        for j, cb in enumerate(b, 1):
            prev, row[j] = row[j], min(row[j] + 1, row[j - 1] + 1, prev + (ca != cb))
    return row[-1]


def did_you_mean(value: str, choices: Iterable[str]) -> str:
    """``; did you mean 'x'?`` for the closest choice (fewest edits, then most similar), or ``""``."""
    options = sorted(set(choices))
    if not options:
        return ""
    best = min(options, key=lambda c: (edit_distance(value, c), -difflib.SequenceMatcher(None, value, c).ratio()))
    if edit_distance(value, best) <= max(2, len(value) // 3):
        return f"; did you mean {best!r}?"
    return ""


def resolve_selector(selector: str) -> str:
    """A rule code, a code prefix (``GC3``, ``GC30``), a family name (``fit``) or ``ALL``,
    as the upper-case prefix it selects; :class:`UsageError` with a did-you-mean otherwise."""
    text = str(selector).strip()
    if text.lower() in FAMILY_PREFIX:
        return FAMILY_PREFIX[text.lower()]
    if text.upper() in FAMILIES:  # a family is valid before any of its rules is registered
        return text.upper()
    codes = [r.code for r in all_rules()]
    if text.upper() == "ALL" or (text and any(matches(c, text) for c in codes)):
        return text.upper()
    names = {r.name: r.code for r in all_rules()}
    if text in names:
        return names[text]
    hint = did_you_mean(text.upper(), [*codes, *FAMILIES]) or did_you_mean(text, [*names, *FAMILY_PREFIX])
    return _raise(f"unknown rule code or family {text!r}{hint} (see `geomcheck rules`)")


def _raise(message: str) -> Any:
    raise UsageError(message)


def _expect(value: Any, kind: type | tuple[type, ...], what: str, described: str) -> Any:
    if isinstance(value, bool) and bool not in (kind if isinstance(kind, tuple) else (kind,)):
        return _raise(f"{what} must be {described}, got {value!r}")
    if not isinstance(value, kind):
        return _raise(f"{what} must be {described}, got {value!r}")
    return value


def _selectors(value: Any, what: str) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [v for v in value.split(",") if v.strip()]
    items = _expect(value, list, what, "a list of rule codes")
    return tuple(_selector(_expect(v, str, what, "a list of rule codes"), what) for v in items)


def _selector(value: str, what: str) -> str:
    try:
        return resolve_selector(value)
    except UsageError as err:
        return _raise(f"{what}: {err}")


def _table(value: Any, what: str) -> dict[str, Any]:
    return dict(_expect(value, dict, what, "a table"))


def _path(value: Any, what: str, base: Path, kind: str) -> Path:
    path = base / _expect(value, str, what, "a path")
    if kind == "dir" and not path.is_dir():
        _raise(f"{what}: not a directory: {path}")
    if kind == "file" and not path.is_file():
        _raise(f"{what}: no such file: {path}")
    return path


def _choice(value: Any, what: str, choices: Iterable[str]) -> str:
    options = sorted(choices)
    text = _expect(value, str, what, f"one of {', '.join(options)}")
    if text not in options:
        _raise(f"{what}: invalid value {text!r}{did_you_mean(text, options)}; valid choices: {', '.join(options)}")
    return text


def _severity(value: Any, what: str) -> Severity:
    return Severity(_choice(str(value).lower() if isinstance(value, str) else value, what, [s.value for s in Severity]))


def _thresholds(value: Any, what: str) -> dict[str, dict[str, float]]:
    out = {
        fam.replace("-", "_"): {k.replace("-", "_"): v for k, v in _table(vals, f"{what}.{fam}").items()}
        for fam, vals in _table(value, what).items()
    }
    try:
        Thresholds().with_overrides(out)
    except UsageError as err:
        _raise(f"{what}: {err}")
    return out


def _scalar_text(value: Any, what: str) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(_expect(value, (str, int, float), what, "a string"))


def _output_formats() -> list[str]:
    from geomcheck.report import FORMATS

    return sorted(FORMATS)


Parser = Callable[[Any, str, Path], Any]

# key as written in a file -> (Config field, parser of the value)
KEYS: dict[str, tuple[str, Parser]] = {
    "select": ("select", lambda v, w, b: _selectors(v, w)),
    "ignore": ("ignore", lambda v, w, b: _selectors(v, w)),
    "extend-select": ("extend_select", lambda v, w, b: _selectors(v, w)),
    "severity": (
        "severity",
        lambda v, w, b: {_selector(k, w): _severity(s, f"{w}.{k}") for k, s in _table(v, w).items()},
    ),
    "thresholds": ("thresholds", lambda v, w, b: _thresholds(v, w)),
    "per-link-ignores": (
        "per_link_ignores",
        lambda v, w, b: {k: _selectors(s, f"{w}.{k}") for k, s in _table(v, w).items()},
    ),
    "per-joint-ignores": (
        "per_joint_ignores",
        lambda v, w, b: {k: _selectors(s, f"{w}.{k}") for k, s in _table(v, w).items()},
    ),
    "packages": ("packages", lambda v, w, b: {k: _path(d, f"{w}.{k}", b, "dir") for k, d in _table(v, w).items()}),
    "search": (
        "search",
        lambda v, w, b: tuple(_path(d, w, b, "dir") for d in _expect(v, list, w, "a list of folders")),
    ),
    "args": ("args", lambda v, w, b: {k: _scalar_text(s, f"{w}.{k}") for k, s in _table(v, w).items()}),
    "srdf": ("srdf", lambda v, w, b: _path(v, w, b, "file")),
    "pose": (
        "pose",
        lambda v, w, b: {k: float(_expect(x, (int, float), f"{w}.{k}", "a number")) for k, x in _table(v, w).items()},
    ),
    "pose-name": ("pose_name", lambda v, w, b: _expect(v, str, w, "a string")),
    "matrix": ("matrix", lambda v, w, b: _expect(v, bool, w, "true or false")),
    "sweep": ("sweep", lambda v, w, b: _expect(v, bool, w, "true or false")),
    "samples": ("samples", lambda v, w, b: _positive(_expect(v, int, w, "an integer"), w)),
    "seed": ("seed", lambda v, w, b: _expect(v, int, w, "an integer")),
    "backend": ("backend", lambda v, w, b: _choice(v, w, BACKENDS)),
    "semantics": ("semantics", lambda v, w, b: _choice(v, w, SEMANTICS)),
    "fail-on": ("fail_on", lambda v, w, b: _severity(v, w)),
    "output-format": ("output_format", lambda v, w, b: _choice(v, w, _output_formats())),
    "baseline": ("baseline", lambda v, w, b: b / _expect(v, str, w, "a path")),
}


def _positive(value: int, what: str) -> int:
    if value < 1:
        _raise(f"{what} must be at least 1, got {value}")
    return value


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
