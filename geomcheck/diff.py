"""Compare two check runs of one description: new findings, fixed findings, regressions.

Findings are matched by :attr:`Diagnostic.fingerprint` (rule, subject, ``about``), so
moving, reformatting or commenting the description matches them up again. A finding
present on both sides *regresses* when its severity rose or a metric in its ``data`` got
worse by more than ``thresholds.diff.metric_relative_tolerance``; which way is worse is
what the finding's rule declares for the metric (``Rule.metrics``, :func:`metric_direction`):
a metric declared ``better="none"``, undeclared, or of a rule this version does not know is
not compared.
"""

from __future__ import annotations

import math
import os
from collections import defaultdict
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Literal

from geomcheck.cache import using_store
from geomcheck.config import Config
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.diff_cache import base_revision_key, cached_base_findings
from geomcheck.errors import InputError
from geomcheck.gitrev import exported_tree, map_into, repo_root, resolve_commit
from geomcheck.load import Bundle, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report, diagnostic_to_dict
from geomcheck.rules import find_rule

Direction = Literal["higher", "lower"]


def metric_direction(code: str, name: str) -> Direction | None:
    """Which way metric ``name`` of a finding of rule ``code`` improves, as the rule declares
    it; ``None`` when it does not (``better="none"``, not declared, or an unknown rule)."""
    rule = find_rule(code)
    metric = rule.metric(name) if rule is not None else None
    if metric is None or metric.better == "none":
        return None
    return metric.better


Value = float | tuple[float, ...]  # a metric: one number, or one per direction or component


@dataclass(frozen=True)
class MetricChange:
    """A metric of one finding before and after, in its declared unit (a number, or the
    numbers of a metric measured per direction: a tensor's moments)."""

    name: str
    before: Value
    after: Value

    def to_dict(self) -> dict[str, Any]:
        def plain(value: Value) -> float | list[float]:
            return list(value) if isinstance(value, tuple) else value

        return {"name": self.name, "before": plain(self.before), "after": plain(self.after)}


@dataclass(frozen=True)
class Regression:
    """A finding on both sides that got worse: ``severity_before`` when its severity rose,
    and the metrics that worsened."""

    diagnostic: Diagnostic
    severity_before: Severity
    metrics: tuple[MetricChange, ...]

    def describe(self) -> str:
        parts = [f"{m.name} {_num(m.before)} -> {_num(m.after)}" for m in self.metrics]
        if self.severity_before != self.diagnostic.severity:
            parts.insert(0, f"severity {self.severity_before.value} -> {self.diagnostic.severity.value}")
        return f"{self.diagnostic.code} {self.diagnostic.subject}: {', '.join(parts)}"


@dataclass(frozen=True)
class Comparison:
    new: tuple[Diagnostic, ...]
    fixed: tuple[Diagnostic, ...]
    regressions: tuple[Regression, ...]
    unchanged: int


def _num(value: Value) -> str:
    if isinstance(value, tuple):
        return "[" + ", ".join(f"{v:.6g}" for v in value) + "]"
    return f"{value:.6g}"


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _numbers(value: Any) -> tuple[float, ...] | None:
    """A metric's numbers: one for a number, each of a list of numbers (a metric measured per
    direction); ``None`` for anything else (text, an empty list, a structure)."""
    if _is_number(value):
        return (float(value),)
    if isinstance(value, list | tuple) and value and all(_is_number(v) for v in value):
        return tuple(float(v) for v in value)
    return None


def _number_worsened(direction: Direction, before: float, after: float, tolerance: float) -> bool:
    delta = (before - after) if direction == "higher" else (after - before)
    return delta > tolerance * max(abs(before), abs(after)) and delta > 1e-12


def worsened(code: str, name: str, before: Any, after: Any, tolerance: float) -> bool:
    """Whether metric ``name`` of rule ``code`` went the wrong way by more than ``tolerance``
    (relative to the larger magnitude); a metric measured per direction (a list of numbers of
    the same length on both sides) worsens when any of its numbers does. Non-numbers and
    metrics without a direction never worsen."""
    direction = metric_direction(code, name)
    old, new = _numbers(before), _numbers(after)
    if direction is None or old is None or new is None or len(old) != len(new):
        return False
    return any(_number_worsened(direction, b, a, tolerance) for b, a in zip(old, new, strict=True))


def _value(value: Any) -> Value:
    return float(value) if _is_number(value) else tuple(float(v) for v in value)


def metric_changes(
    code: str, before: Mapping[str, Any], after: Mapping[str, Any], tolerance: float
) -> tuple[MetricChange, ...]:
    """Metrics of rule ``code`` in both ``data`` maps that worsened, sorted by name."""
    return tuple(
        MetricChange(name, _value(before[name]), _value(after[name]))
        for name in sorted(set(before) & set(after))
        if worsened(code, name, before[name], after[name], tolerance)
    )


def _by_fingerprint(diagnostics: Iterable[Diagnostic]) -> dict[str, list[Diagnostic]]:
    out: dict[str, list[Diagnostic]] = defaultdict(list)
    for d in sorted(diagnostics, key=lambda d: (d.fingerprint, d.message)):
        out[d.fingerprint].append(d)
    return out


def compare(base: Sequence[Diagnostic], head: Sequence[Diagnostic], tolerance: float = 0.01) -> Comparison:
    """``head`` against ``base``; each side's findings keep their report order."""
    before, after = _by_fingerprint(base), _by_fingerprint(head)
    new_ids: set[int] = set()
    fixed_ids: set[int] = set()
    regressions: list[Regression] = []
    unchanged = 0
    for fp in sorted(set(before) | set(after)):
        olds, news = before.get(fp, []), after.get(fp, [])
        for old, cur in zip(olds, news, strict=False):
            metrics = metric_changes(cur.code, old.data, cur.data, tolerance)
            if metrics or cur.severity.rank > old.severity.rank:
                regressions.append(Regression(cur, old.severity, metrics))
            else:
                unchanged += 1
        new_ids.update(id(d) for d in news[len(olds) :])
        fixed_ids.update(id(d) for d in olds[len(news) :])
    return Comparison(
        new=tuple(d for d in head if id(d) in new_ids),
        fixed=tuple(d for d in base if id(d) in fixed_ids),
        regressions=tuple(sorted(regressions, key=lambda r: r.diagnostic.sort_key())),
        unchanged=unchanged,
    )


def regressed_diagnostic(regression: Regression, base_label: str) -> Diagnostic:
    """The finding of ``regression`` as the gate reports it: its message says what got worse
    since ``base_label``, so every output format (annotations, SARIF, JUnit) names the reason."""
    d = regression.diagnostic
    _, _, what = regression.describe().partition(": ")
    return replace(d, message=f"{d.message} (regressed since {base_label}: {what})")


def diff_report(
    base: Sequence[Diagnostic] | None,
    head: Report,
    base_label: str,
    tolerance: float = 0.01,
    base_note: str | None = None,
    gate_regressions: bool = True,
) -> Report:
    """``head`` with its new findings as diagnostics, then (``gate_regressions``) its
    regressed ones, and a ``diff`` section ``{base, base_exists, base_note, new, fixed:
    [diagnostic], regressions: [{diagnostic, severity_before, metrics: [{name, before,
    after}]}], unchanged, gated}``. A regressed finding is a diagnostic like a new one, so it
    fails the gate when its severity reaches ``fail_on`` (a warning raised to an error, or an
    error whose numbers got worse) and every format shows why. ``base`` is ``None`` when the
    description does not exist there (every finding is new)."""
    result = compare(base or (), head.diagnostics, tolerance)
    regressed = tuple(regressed_diagnostic(r, base_label) for r in result.regressions) if gate_regressions else ()
    section = {
        "base": base_label,
        "base_exists": base is not None,
        "base_note": base_note,
        "new": len(result.new),
        "fixed": [diagnostic_to_dict(d) for d in result.fixed],
        "regressions": [
            {
                "diagnostic": diagnostic_to_dict(r.diagnostic),
                "severity_before": r.severity_before.value,
                "metrics": [m.to_dict() for m in r.metrics],
            }
            for r in result.regressions
        ],
        "unchanged": result.unchanged,
        "gated": gate_regressions,
    }
    # a member of a group whose head the base has, itself new: reported apart, at its own severity
    known = {d.fingerprint for d in base or ()}
    new = tuple(
        d.on_its_own(f" (its group is in {base_label}; this part is not)") if d.data.get("grouped_with") in known else d
        for d in result.new
    )
    return replace(head, diagnostics=new + regressed, sections={**head.sections, "diff": section})


# --- the two sides -----------------------------------------------------------------------

BaseSide = tuple[tuple[Diagnostic, ...] | None, str, str | None]  # findings, label, note


def check_side(bundle: Bundle, options: CheckOptions, label: str) -> BaseSide:
    """Findings of the base side; a description that does not load there has only the
    finding that says why (or none), and a note."""
    try:
        return run_check(bundle, options).diagnostics, label, None
    except InputError as err:
        found = (err.diagnostic,) if err.diagnostic is not None else ()
        return found, label, f"the description does not load at {label}: {err}"


def corresponding_roots(old: Path, new: Path) -> tuple[Path, Path]:
    """The folders of ``old`` and ``new`` below which both paths are alike (the longest
    common tail of their components, the file name included)."""
    a, b = old.resolve().parts, new.resolve().parts
    same = 0
    while same < min(len(a), len(b)) - 1 and a[-1 - same] == b[-1 - same]:
        same += 1
    return Path(*a[: len(a) - same]), Path(*b[: len(b) - same])


def translate_about(
    diagnostics: Sequence[Diagnostic], old_root: str, new_root: str, exists: Callable[[str], bool]
) -> tuple[Diagnostic, ...]:
    """Findings whose ``about`` is the display path of a file under ``old_root`` (``exists``
    says whether that relative path is a file there) renamed to the same file under
    ``new_root``, so per-file findings of two copies match up."""

    def prefix(root: str) -> str:
        return "" if root in ("", ".") else root.rstrip("/") + "/"

    old, new = prefix(old_root), prefix(new_root)
    out = []
    for d in diagnostics:
        rest = d.about[len(old) :]
        if d.about.startswith(old) and rest and exists(rest):
            d = replace(d, about=new + rest)
        out.append(d)
    return tuple(out)


def check_other(old: Path, new: Path, settings: Config, options: CheckOptions) -> BaseSide:
    """``geomcheck diff OLD NEW``: the OLD side, with the same settings as NEW; files of the
    OLD tree named in findings are read as the corresponding files of the NEW tree."""
    bundle = make_bundle(old, dict(settings.packages), settings.search, env=settings.env)
    found, label, note = check_side(bundle, options, bundle.display(bundle.root_file))
    if found:
        old_root, new_root = corresponding_roots(old, new)
        found = translate_about(
            found, bundle.display(old_root), bundle.display(new_root), lambda rest: (old_root / rest).is_file()
        )
    return found, label, note


def check_base_revision(rev: str, head_path: Path, settings: Config, options: CheckOptions) -> BaseSide:
    """``geomcheck diff --base REV PATH``: PATH as it is in commit REV of its repository.

    Packages, search folders and the SRDF inside the repository are taken from REV too
    (those outside it are the same for both sides); paths are displayed as for the work
    tree, so both sides name files alike.
    """
    root = repo_root(head_path)
    commit = resolve_commit(root, rev)
    label = f"{rev} ({commit[:12]})" if not commit.startswith(rev) else rev
    key = base_revision_key(root, label, commit, head_path, settings.packages, settings.search, options)
    found, note = cached_base_findings(
        key, lambda: check_exported_revision(root, commit, head_path, settings, options, label)
    )
    return found, label, note


def check_exported_revision(
    root: Path, commit: str, head_path: Path, settings: Config, options: CheckOptions, label: str
) -> tuple[tuple[Diagnostic, ...] | None, str | None]:
    """Findings and note of ``head_path`` as it is in ``commit`` (``None``: no such file there).

    The stage caches stay off: the exported tree's temporary paths are in their keys, so its
    entries could never be found again."""
    with using_store(None), exported_tree(root, commit) as tree:
        base_path = map_into(head_path, root, tree)
        if not base_path.is_file():
            return None, None
        packages = {n: map_into(Path(d), root, tree) for n, d in settings.packages.items()}
        search = [map_into(Path(d), root, tree) for d in settings.search]
        srdf = map_into(options.srdf, root, tree) if options.srdf else None
        display = Path(os.path.normpath(tree / os.path.relpath(Path.cwd().resolve(), root)))
        bundle = make_bundle(
            base_path,
            {n: d for n, d in packages.items() if d.is_dir()},
            [d for d in search if d.is_dir()],
            display_root=display,
            env=settings.env,
        )
        base_options = replace(options, srdf=srdf if srdf and srdf.is_file() else None)
        found, _, note = check_side(bundle, base_options, label)
        return found, note
