"""Defects robot maintainers fixed themselves, as a recall suite: ``../shared/corpus/history``.

Each case of ``history/cases.toml`` holds a description before and after a fix taken from a
public repository's history, the links and joints the fix changed (``targets``) and the kind of
defect. A case is

- **flagged** when the version before the fix gets an error or warning on a changed element
  from a rule that can name that kind of defect (:data:`NAMING_FAMILIES`: an inertia finding
  does not name a collision box's defect);
- **cleared** when none of those rules still flags a changed element after the fix;
- **new after** when the fixed version gets an error or warning on a changed element from a rule
  that did not flag it before (each such case must be a real remaining defect, explained in
  ``docs/precision.md``).

Tests (``tests/precision/test_history.py``, a campaign) and ``benchmarks/history_recall.py``
share this module; a case added to ``cases.toml`` needs no code change.
"""

from __future__ import annotations

import json
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

MANIFEST = "cases.toml"
GATED = ("error", "warning")

# the rule families (code prefixes) whose findings can name each kind of defect
NAMING_FAMILIES: Mapping[str, tuple[str, ...]] = {
    "inertia values": ("GC5",),
    "inertia values (COM)": ("GC5",),
    "inertia missing": ("GC5", "GC105"),  # an <inertial> written outside its <link> is GC105
    "mass": ("GC5",),
    "collision size/offset": ("GC3", "GC4"),
    "collision missing": ("GC3",),
    "mesh path": ("GC2",),
    "mesh path/units": ("GC2", "GC3"),  # a mesh at the wrong scale no longer fits its collision
    "mesh geometry": ("GC2", "GC3"),
    "joint axis": ("GC1", "GC42"),
    "joint limits": ("GC1", "GC4"),
}


@dataclass(frozen=True)
class Case:
    """One table of ``cases.toml``; paths are absolute."""

    name: str
    folder: Path
    root: str
    packages: Mapping[str, str]
    args: Mapping[str, str]
    targets: tuple[str, ...]
    kind: str
    what: str

    def side(self, side: str) -> Path:
        return self.folder / side

    @property
    def families(self) -> tuple[str, ...]:
        return NAMING_FAMILIES.get(self.kind, ("GC",))


def history_dir(corpus: Path) -> Path | None:
    folder = corpus / "history"
    return folder if (folder / MANIFEST).is_file() else None


def cases(corpus: Path) -> list[Case]:
    """Every case of ``corpus/history/cases.toml``, in the file's order."""
    folder = history_dir(corpus)
    if folder is None:
        return []
    with (folder / MANIFEST).open("rb") as handle:
        tables = tomllib.load(handle)
    return [
        Case(
            name=name,
            folder=folder / name,
            root=str(t["root"]),
            packages={str(k): str(v) for k, v in (t.get("packages") or {}).items()},
            args={str(k): str(v) for k, v in (t.get("args") or {}).items()},
            targets=tuple(str(x) for x in t.get("targets", ())),
            kind=str(t.get("kind", "")),
            what=str(t.get("what", "")),
        )
        for name, t in tables.items()
    ]


def check_side(case: Case, side: str) -> dict[str, Any]:
    """The JSON report (parsed) of a default check of one side of ``case``."""
    from geomcheck.load import make_bundle
    from geomcheck.options import CheckOptions
    from geomcheck.pipeline import run_check
    from geomcheck.report import json_format

    folder = case.side(side)
    bundle = make_bundle(folder / case.root, {k: folder / v for k, v in case.packages.items()}, (), display_root=folder)
    report = run_check(bundle, CheckOptions(args=dict(case.args)))
    document: dict[str, Any] = json.loads(json_format.render(report))
    return document


def subjects(d: Mapping[str, Any]) -> set[str]:
    """The links and joints a finding is about, those it stands for (``also``) included."""
    names = {d.get("link"), d.get("joint"), *(d.get("links") or ()), *((d.get("data") or {}).get("also") or ())}
    return {n for n in names if n}


def on_targets(document: Mapping[str, Any], targets: Iterable[str]) -> list[Mapping[str, Any]]:
    """The error and warning findings of ``document`` about a changed element."""
    wanted = set(targets)
    return [d for d in document.get("diagnostics", ()) if d["severity"] in GATED and subjects(d) & wanted]


@dataclass
class Outcome:
    """What geomcheck said of one case: the codes on changed elements before and after."""

    case: Case
    before: list[Mapping[str, Any]] = field(default_factory=list)
    after: list[Mapping[str, Any]] = field(default_factory=list)

    def naming(self, findings: list[Mapping[str, Any]]) -> set[str]:
        return {d["code"] for d in findings if d["code"].startswith(self.case.families)}

    @property
    def flagged_codes(self) -> set[str]:
        return self.naming(self.before)

    @property
    def flagged(self) -> bool:
        return bool(self.flagged_codes)

    @property
    def cleared(self) -> bool:
        return self.flagged and not (self.flagged_codes & self.naming(self.after))

    @property
    def new_after(self) -> set[str]:
        return {d["code"] for d in self.after} - {d["code"] for d in self.before}


def outcome(case: Case, before: Mapping[str, Any], after: Mapping[str, Any]) -> Outcome:
    return Outcome(case, on_targets(before, case.targets), on_targets(after, case.targets))


@dataclass
class Figures:
    cases: int = 0
    flagged: int = 0
    cleared: int = 0
    new_after: int = 0

    def add(self, o: Outcome) -> None:
        self.cases += 1
        self.flagged += o.flagged
        self.cleared += o.cleared
        self.new_after += bool(o.new_after)


def figures_by_kind(outcomes: Iterable[Outcome]) -> dict[str, Figures]:
    """Figures per defect kind, and ``"all"``."""
    out: dict[str, Figures] = {"all": Figures()}
    for o in outcomes:
        out.setdefault(o.case.kind, Figures()).add(o)
        out["all"].add(o)
    return out


def table(outcomes: list[Outcome]) -> str:
    """The per-kind table, as markdown."""
    rows = [
        "| kind | cases | flagged before | cleared after | new after |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    figures = figures_by_kind(outcomes)
    for kind in [*sorted(k for k in figures if k != "all"), "all"]:
        f = figures[kind]
        label = f"**{kind}**" if kind == "all" else kind
        rows.append(f"| {label} | {f.cases} | {f.flagged} | {f.cleared} | {f.new_after} |")
    return "\n".join(rows)
