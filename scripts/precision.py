"""The precision ledger: every error and warning finding on the corpus, classified by hand.

Each robot of ``robots.toml`` (``scripts/corpus_robots.py``) is checked with the default
options (its packages, xacro arguments and SRDF as listed), and each of its error and warning
findings is matched with an entry of ``tests/precision/ledger/*.toml``::

    [[finding]]
    robot = "unitree_h1"                      # the robots.toml table
    code = "GC301"
    subject = "left_elbow_link collision[0]"  # link, joint or "a, b", then the finding's `about`
    verdict = "real"                          # real | dismissable | wrong
    reason = "one line, written after opening the mesh and the numbers"

An entry may carry ``count = N`` when N findings share code and subject. ``tests/precision``
fails when a finding has no entry, or when an entry classified real has no finding any more;
``docs/precision.md`` holds the summary rendered between its markers.

    python scripts/precision.py                    # check the corpus, compare with the ledger
    python scripts/precision.py --reports DIR      # use JSON reports already written (NAME.json)
    python scripts/precision.py --stubs            # print entries to fill for unclassified findings
    python scripts/precision.py --write-docs       # rewrite the summary in docs/precision.md
"""

from __future__ import annotations

import argparse
import json
import sys
import tomllib
from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from corpus_robots import REPO, CorpusRobot, check_document, checked_robots, corpus_dir

LEDGER = REPO / "tests" / "precision" / "ledger"
DOCS = REPO / "docs" / "precision.md"
START = "<!-- ledger summary: scripts/precision.py --write-docs -->"
END = "<!-- end of ledger summary -->"
VERDICTS = ("real", "dismissable", "wrong")
GATED = ("error", "warning")  # the severities the ledger classifies


@dataclass(frozen=True)
class Entry:
    """One classified finding (or ``count`` findings of one code and subject)."""

    robot: str
    code: str
    subject: str
    verdict: str
    reason: str
    count: int = 1

    @property
    def key(self) -> tuple[str, str, str]:
        return (self.robot, self.code, self.subject)


@dataclass(frozen=True)
class Finding:
    """An error or warning of a report; ``also``, the subjects a grouped finding stands for
    too (one macro line written alike for several links)."""

    robot: str
    code: str
    severity: str
    subject: str
    message: str
    also: tuple[str, ...] = ()

    @property
    def key(self) -> tuple[str, str, str]:
        return (self.robot, self.code, self.subject)


@dataclass
class RobotReview:
    """The findings of one robot matched with the ledger."""

    robot: str
    findings: list[Finding] = field(default_factory=list)
    matched: list[tuple[Finding, Entry]] = field(default_factory=list)
    unclassified: list[Finding] = field(default_factory=list)
    vanished: list[Entry] = field(default_factory=list)  # entries with no finding left

    def count(self, verdict: str) -> int:
        return sum(1 for _, e in self.matched if e.verdict == verdict)

    def severity(self, severity: str) -> int:
        return sum(1 for f in self.findings if f.severity == severity)

    @property
    def vanished_real(self) -> list[Entry]:
        return [e for e in self.vanished if e.verdict == "real"]


def subject(d: Mapping[str, Any]) -> str:
    """The subject of a JSON finding: its link, joint or pair, then what part of it (``about``)."""
    who = d.get("link") or d.get("joint") or ", ".join(d.get("links") or ()) or "-"
    return who + (f" {d['about']}" if d.get("about") else "")


def gated_findings(robot: str, document: Mapping[str, Any]) -> list[Finding]:
    """The error and warning findings of one JSON report, in its order."""
    return [
        Finding(
            robot,
            d["code"],
            d["severity"],
            subject(d),
            d["message"],
            tuple(f"{name} {d['about']}" if d.get("about") else name for name in d.get("data", {}).get("also", ())),
        )
        for d in document["diagnostics"]
        if d["severity"] in GATED
    ]


def load_ledger(folder: Path = LEDGER) -> list[Entry]:
    """Every entry of the ledger files, checked for shape."""
    entries: list[Entry] = []
    for path in sorted(folder.glob("*.toml")):
        with path.open("rb") as handle:
            for raw in tomllib.load(handle).get("finding", []):
                entry = Entry(**raw)
                if entry.verdict not in VERDICTS:
                    raise ValueError(f"{path.name}: verdict {entry.verdict!r} of {entry.key}; valid: {VERDICTS}")
                if not entry.reason.strip():
                    raise ValueError(f"{path.name}: {entry.key} has no reason")
                entries.append(entry)
    return entries


def review(robot: str, document: Mapping[str, Any], entries: Iterable[Entry]) -> RobotReview:
    """Match ``robot``'s findings with its entries (an entry answers for ``count`` findings)."""
    result = RobotReview(robot, gated_findings(robot, document))
    available: dict[tuple[str, str, str], list[Entry]] = {}
    for entry in entries:
        if entry.robot == robot:
            available.setdefault(entry.key, []).extend([entry] * entry.count)
    for finding in result.findings:
        pool = available.get(finding.key)
        if pool:
            result.matched.append((finding, pool.pop(0)))
        else:
            result.unclassified.append(finding)
        for other in finding.also:  # the entries of the subjects it stands for are answered by it
            absorbed = available.get((robot, finding.code, other))
            if absorbed:
                absorbed.pop(0)
    seen: set[int] = set()
    for pool in available.values():
        for entry in pool:
            if id(entry) not in seen:
                seen.add(id(entry))
                result.vanished.append(entry)
    return result


def report_document(robot: CorpusRobot) -> dict[str, Any]:
    """The JSON report of a default check of ``robot`` (its packages, arguments and SRDF)."""
    return check_document(robot.root, robot.packages, robot.corpus, robot.args, robot.srdf)


def summary_markdown(reviews: list[RobotReview]) -> str:
    """The per-robot table and the per-finding tables, between the docs' markers."""
    rows = [
        "| robot | errors | warnings | real | dismissable | wrong | unclassified |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    totals: Counter[str] = Counter()
    for r in reviews:
        figures = {
            "errors": r.severity("error"),
            "warnings": r.severity("warning"),
            **{v: r.count(v) for v in VERDICTS},
            "unclassified": len(r.unclassified),
        }
        totals.update(figures)
        rows.append(f"| {r.robot} | " + " | ".join(str(v) for v in figures.values()) + " |")
    rows.append(
        "| **all** | "
        + " | ".join(f"**{totals[k]}**" for k in ("errors", "warnings", *VERDICTS, "unclassified"))
        + " |"
    )
    classified = sum(totals[v] for v in VERDICTS)
    share = f"{100 * totals['real'] / classified:.1f}%" if classified else "-"
    lines = [START, "", *rows, "", f"Real: **{share}** of {classified} classified findings.", ""]
    for r in reviews:
        if not r.findings:
            continue
        lines += [
            f"### {r.robot}",
            "",
            "| rule | severity | subject | verdict | reason |",
            "| --- | --- | --- | --- | --- |",
        ]
        for finding, entry in sorted(r.matched, key=lambda m: (m[0].code, m[0].subject)):
            reason = entry.reason.replace("|", "\\|")
            lines.append(f"| {finding.code} | {finding.severity} | {finding.subject} | {entry.verdict} | {reason} |")
        for finding in r.unclassified:
            lines.append(f"| {finding.code} | {finding.severity} | {finding.subject} | **unclassified** | |")
        lines.append("")
    lines.append(END)
    return "\n".join(lines)


def with_summary(text: str, summary: str) -> str:
    """``text`` (docs/precision.md) with the part between the markers replaced."""
    head, _, rest = text.partition(START)
    _, _, tail = rest.partition(END)
    return head + summary + tail


def stubs(reviews: Iterable[RobotReview]) -> str:
    """TOML entries to fill (verdict and reason) for every unclassified finding."""
    out = []
    for r in reviews:
        for f in r.unclassified:
            out.append(
                f'[[finding]]\nrobot = "{f.robot}"\ncode = "{f.code}"\nsubject = {json.dumps(f.subject)}\n'
                f'verdict = ""\nreason = ""  # {f.severity}: {f.message[:200]}\n'
            )
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", action="append", default=[], help="only this robots.toml table (repeatable)")
    parser.add_argument("--reports", type=Path, help="read NAME.json reports from this folder instead of checking")
    parser.add_argument("--stubs", action="store_true", help="print ledger entries for unclassified findings")
    parser.add_argument("--write-docs", action="store_true", help="rewrite the summary in docs/precision.md")
    args = parser.parse_args(argv)
    corpus = corpus_dir()
    if corpus is None:
        sys.stderr.write("no corpus: set GEOMCHECK_CORPUS to ../shared/corpus\n")
        return 2
    entries = load_ledger()
    reviews = []
    for robot in checked_robots(corpus):
        if args.robot and robot.name not in args.robot:
            continue
        if args.reports is not None:
            document = json.loads((args.reports / f"{robot.name}.json").read_text(encoding="utf-8"))
        else:
            document = report_document(robot)
        reviews.append(review(robot.name, document, entries))
    if args.stubs:
        sys.stdout.write(stubs(reviews) + "\n")
        return 0
    summary = summary_markdown(reviews)
    if args.write_docs:
        DOCS.write_text(with_summary(DOCS.read_text(encoding="utf-8"), summary), encoding="utf-8")
    failed = False
    for r in reviews:
        for f in r.unclassified:
            failed = True
            sys.stdout.write(f"unclassified: {f.robot} {f.code} {f.subject} ({f.severity}): {f.message[:160]}\n")
        for e in r.vanished_real:
            failed = True
            sys.stdout.write(f"real finding gone: {e.robot} {e.code} {e.subject}\n")
        for e in r.vanished:
            if e.verdict != "real":
                sys.stdout.write(f"stale ({e.verdict}): {e.robot} {e.code} {e.subject}\n")
    real = sum(r.count("real") for r in reviews)
    classified = sum(r.count(v) for r in reviews for v in VERDICTS)
    sys.stdout.write(f"{real} real of {classified} classified; wrong {sum(r.count('wrong') for r in reviews)}\n")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
