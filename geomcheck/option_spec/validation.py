"""The one validation of each kind of option value, and strings (flags, request fields) read
as the values a configuration file holds. Every bound and choice is checked here, whatever the
value's source."""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from geomcheck.diagnostics import Severity
from geomcheck.errors import UsageError
from geomcheck.rules import FAMILIES, all_rules, matches
from geomcheck.thresholds import Thresholds

FAMILY_PREFIX = {name: prefix for prefix, name in FAMILIES.items()}  # "fit" -> "GC3"


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


def integer_in(value: Any, what: str, lo: int, hi: int | None) -> int:
    """``value`` as an integer within ``lo..hi`` (``hi`` None: no upper bound)."""
    number = _expect(value, int, what, "an integer")
    if hi is None and number < lo:
        _raise(f"{what} must be at least {lo}, got {number}")
    if hi is not None and not lo <= number <= hi:
        _raise(f"{what} must be between {lo} and {hi}, got {number}")
    return int(number)


def finite_number(value: Any, what: str) -> float:
    """``value`` as a finite float: NaN and infinities are refused wherever they come from."""
    number = float(_expect(value, (int, float), what, "a number"))
    if not math.isfinite(number):
        _raise(f"{what} must be finite, got {value!r}")
    return number


# --- strings (flags, request options) to the values a file holds ----------------------------

_TRUE = ("1", "true", "yes", "on")
_FALSE = ("0", "false", "no", "off")


def parse_assignment(text: str, what: str) -> tuple[str, str]:
    """``NAME=VALUE`` split; :class:`UsageError` otherwise."""
    name, sep, value = str(text).partition("=")
    if not sep or not name.strip():
        raise UsageError(f"{what} must be NAME=VALUE, got {text!r}")
    return name.strip(), value


def parse_bool(text: str, what: str) -> bool:
    lowered = text.strip().lower()
    if lowered in _TRUE:
        return True
    if lowered in _FALSE:
        return False
    raise UsageError.bad_choice(what, text, ("true", "false"))


def parse_int(text: str, what: str) -> int:
    try:
        return int(text.strip())
    except ValueError:
        raise UsageError(f"{what} must be an integer, got {text!r}") from None


def parse_float(text: str, what: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise UsageError(f"{what} must be a number, got {text!r}") from None
