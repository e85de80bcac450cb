"""Baselines: accept the findings a description has today, fail only on new ones.

A baseline file (JSON, ``geomcheck.baseline/1``) lists findings by
:attr:`Diagnostic.fingerprint` (rule, subject, ``about``: not the line or the message), with
code, subject and message for the people who review it. Entries are matched as a multiset:
two identical fingerprints in the report need two entries.
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import UsageError
from geomcheck.report.model import Report

BASELINE_SCHEMA = "geomcheck.baseline/1"


@dataclass(frozen=True)
class BaselineEntry:
    fingerprint: str
    code: str
    subject: str
    message: str

    @classmethod
    def of(cls, d: Diagnostic) -> BaselineEntry:
        return cls(d.fingerprint, d.code, d.subject, d.message)


@dataclass(frozen=True)
class Baseline:
    entries: tuple[BaselineEntry, ...] = ()

    @classmethod
    def from_diagnostics(cls, diagnostics: Iterable[Diagnostic]) -> Baseline:
        """Entries of ``diagnostics`` sorted by code, subject and fingerprint: the file
        changes only when the findings do."""
        entries = sorted((BaselineEntry.of(d) for d in diagnostics), key=lambda e: (e.code, e.subject, e.fingerprint))
        return cls(tuple(entries))

    def to_json(self) -> str:
        doc = {
            "schema": BASELINE_SCHEMA,
            "findings": [
                {"fingerprint": e.fingerprint, "code": e.code, "subject": e.subject, "message": e.message}
                for e in self.entries
            ],
        }
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"

    def write(self, path: Path) -> None:
        try:
            path.write_text(self.to_json(), encoding="utf-8")
        except OSError as err:
            raise UsageError(f"cannot write baseline {_shown(path)}: {err.strerror}") from None

    @classmethod
    def load(cls, path: Path) -> Baseline:
        """The baseline in ``path``; :class:`UsageError` when it is missing or not a baseline."""
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
        except OSError as err:
            raise UsageError(f"cannot read baseline {_shown(path)}: {err.strerror}") from None
        except json.JSONDecodeError as err:
            raise UsageError(f"baseline {path} is not JSON: {err}") from None
        if not isinstance(doc, dict) or doc.get("schema") != BASELINE_SCHEMA:
            raise UsageError(f"{path} is not a geomcheck baseline (expected schema {BASELINE_SCHEMA!r})")
        try:
            return cls(tuple(_entry(item) for item in doc.get("findings", [])))
        except (KeyError, TypeError) as err:
            raise UsageError(f"baseline {path}: malformed entry ({err})") from None


def _shown(path: Path) -> str:
    """``path`` relative to the current folder when it lies inside it."""
    cwd = Path.cwd().resolve()
    resolved = path.resolve()
    return resolved.relative_to(cwd).as_posix() if resolved.is_relative_to(cwd) else str(path)


def _entry(item: Any) -> BaselineEntry:
    return BaselineEntry(
        fingerprint=str(item["fingerprint"]),
        code=str(item.get("code", "")),
        subject=str(item.get("subject", "")),
        message=str(item.get("message", "")),
    )


@dataclass(frozen=True)
class BaselineMatch:
    """``new`` findings (not in the baseline, report order), how many were ``matched``, and
    the baseline entries that no longer occur (``stale``: fixed, or their subject renamed)."""

    new: tuple[Diagnostic, ...]
    matched: int
    stale: tuple[BaselineEntry, ...]
    accepted: frozenset[str] = frozenset()  # the fingerprints the baseline matched

    def reported(self, d: Diagnostic) -> Diagnostic:
        """New finding ``d`` as the report gives it: at its own severity when it is a member of a
        group whose head the baseline accepts (a wheel added without mass to a description whose
        other massless links are accepted)."""
        if d.data.get("grouped_with") not in self.accepted:
            return d
        return d.on_its_own(" (its group is in the baseline; this part is not)")


def match(diagnostics: Iterable[Diagnostic], baseline: Baseline) -> BaselineMatch:
    remaining = Counter(e.fingerprint for e in baseline.entries)
    new: list[Diagnostic] = []
    matched = 0
    accepted: set[str] = set()
    for d in diagnostics:
        if remaining[d.fingerprint] > 0:
            remaining[d.fingerprint] -= 1
            matched += 1
            accepted.add(d.fingerprint)
        else:
            new.append(d)
    stale = []
    for e in baseline.entries:
        if remaining[e.fingerprint] > 0:
            remaining[e.fingerprint] -= 1
            stale.append(e)
    return BaselineMatch(tuple(new), matched, tuple(stale), frozenset(accepted))


def apply_baseline(reports: Sequence[Report], baseline: Baseline, label: str) -> tuple[list[Report], BaselineMatch]:
    """``reports`` (of one run, sharing one baseline) keeping only findings not in
    ``baseline``, each with a ``baseline`` section ``{file, entries, matched, stale:
    [{fingerprint, code, subject, message}]}`` about the whole run."""
    result = match((d for r in reports for d in r.diagnostics), baseline)
    new = {id(d) for d in result.new}
    section = {
        "file": label,
        "entries": len(baseline.entries),
        "matched": result.matched,
        "stale": [
            {"fingerprint": e.fingerprint, "code": e.code, "subject": e.subject, "message": e.message}
            for e in result.stale
        ],
    }
    out = [
        replace(
            r,
            diagnostics=tuple(result.reported(d) for d in r.diagnostics if id(d) in new),
            sections={**r.sections, "baseline": section},
        )
        for r in reports
    ]
    return out, result
