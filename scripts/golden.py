"""Golden reports: the JSON report of every corpus robot and of the bundled example, as hashes.

For each robot the report is computed with the default options (sweep on), normalised (the
``created`` timestamp and the tool version replaced by fixed values, every number to 6
significant digits: the documented tolerance, so that another CPU's or BLAS kernel's last
digits never change a hash) and recorded in
``tests/golden/reports.json`` as hashes only, never corpus text: the sha256 of the whole
normalised report, of each part of it (robot summary, options, skipped checks, each report
section) and, per finding, its code, fingerprint and the sha256 of its normalised entry (one string). A
refactoring that must not change behaviour keeps every hash; when one changes,
``tests/test_golden.py`` says which robot, which findings appeared, disappeared or changed
(code, subject and message of the new ones) and which parts differ.

    python scripts/golden.py            # compare with tests/golden/reports.json
    python scripts/golden.py --update   # rewrite it
    python scripts/golden.py --robot erd_panda --out /tmp/reports   # also write the normalised reports

The corpus robots are those of ``robots.toml`` (``scripts/corpus_robots.py``), keyed by table
name and checked with their packages, arguments and SRDF; the corpus is ``$GEOMCHECK_CORPUS`` or
``../shared/corpus`` beside the repository. Without it only the bundled example is computed
(and only its entry is compared or updated).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
import corpus_robots

REPO = corpus_robots.REPO
GOLDEN = REPO / "tests" / "golden" / "reports.json"
EXAMPLE = "examples/pr2_base/robots/pr2_base.urdf.xacro"
FIXED_CREATED = "2026-01-01T00:00:00Z"
FIXED_VERSION = "0"


@dataclass(frozen=True)
class Robot:
    """One golden robot: ``key`` names it in the golden file (a path relative to the corpus,
    or to the repository for the example)."""

    key: str
    root_file: Path
    display_root: Path
    packages: dict[str, Path] = field(default_factory=dict)
    search: tuple[Path, ...] = ()
    args: dict[str, str] = field(default_factory=dict)
    srdf: Path | None = None


def corpus_dir() -> Path | None:
    return corpus_robots.corpus_dir()


def robots(corpus: Path | None) -> list[Robot]:
    """The bundled example, then (with a corpus) every robot of robots.toml geomcheck loads,
    keyed by its table's name and checked with its packages, arguments and SRDF."""
    out = [Robot(EXAMPLE, REPO / EXAMPLE, REPO)]
    if corpus is None:
        return out
    for robot in corpus_robots.checked_robots(corpus):
        out.append(
            Robot(
                robot.name,
                robot.root,
                corpus,
                packages=dict(robot.packages),
                args=dict(robot.args),
                srdf=robot.srdf,
            )
        )
    return out


CORPUS_PLACEHOLDER = "$GEOMCHECK_CORPUS"


def corpus_spellings(corpus: Path | None) -> list[str]:
    """The ways the corpus folder can be written on this machine (as given and resolved),
    longest first."""
    if corpus is None:
        return []
    return sorted({str(corpus), str(corpus.resolve())}, key=len, reverse=True)


def normalised(document: dict[str, Any], corpus: Path | None = None) -> dict[str, Any]:
    """A copy of a JSON report with its timestamp and tool version fixed and the corpus
    folder (``corpus``, by default the one this machine has) written as
    ``$GEOMCHECK_CORPUS``: a ``file://$(find pkg)/...`` mesh filename expands to an absolute
    path, which must not tie the golden hashes to where the corpus lies."""
    text = json.dumps(document)
    for spelling in corpus_spellings(corpus or corpus_dir()):
        text = text.replace(json.dumps(spelling)[1:-1], CORPUS_PLACEHOLDER)
    document = json.loads(text)
    document["created"] = FIXED_CREATED
    document["tool"]["version"] = FIXED_VERSION
    return document


def normalised_report(robot: Robot) -> dict[str, Any]:
    """The JSON report of ``robot`` (default options, sweep on) with timestamp and version fixed."""
    return normalised(
        corpus_robots.check_document(
            robot.root_file, robot.packages, robot.display_root, robot.args, robot.srdf, robot.search
        )
    )


HASHED_DIGITS = 6  # numbers are hashed to this many significant digits: the golden tolerance


def canonical(value: object) -> object:
    """``value`` with every float to :data:`HASHED_DIGITS` significant digits: the last digits a
    BLAS kernel or CPU produces (an eigen solver, a summation order) do not change a hash, a
    change of meaning does."""
    if isinstance(value, float):
        return float(f"{value:.{HASHED_DIGITS}g}") + 0.0
    if isinstance(value, dict):
        return {k: canonical(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [canonical(v) for v in value]
    return value


def digest(value: object) -> str:
    text = json.dumps(canonical(value), sort_keys=True, ensure_ascii=True, allow_nan=False, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def summary(document: dict[str, Any]) -> dict[str, Any]:
    """Hashes of a normalised report: whole, per part, per finding (code, fingerprint, sha256)."""
    parts = {
        name: digest(document.get(name))
        for name in ("schema", "robot", "options", "fail_on", "verdict", "summary", "skipped")
    }
    parts.update({f"sections.{name}": digest(value) for name, value in sorted(document["sections"].items())})
    findings = sorted(f"{d['code']} {d['fingerprint']} {digest(d)}" for d in document["diagnostics"])
    return {"sha256": digest(document), "parts": parts, "findings": findings}


def subject(d: dict[str, Any]) -> str:
    who = d.get("link") or d.get("joint") or ", ".join(d.get("links") or ()) or "-"
    return who + (f" {d['about']}" if d.get("about") else "")


def differences(key: str, golden: dict[str, Any], document: dict[str, Any]) -> list[str]:
    """What differs between the golden hashes of ``key`` and a freshly computed report, in
    words: findings that appeared (code, subject, message), disappeared (code, fingerprint)
    or changed, then the parts whose hash differs. Empty when the report is identical."""
    now = summary(document)
    if now["sha256"] == golden["sha256"]:
        return []
    lines = [f"{key}: the normalised report differs from the golden one"]
    by_fingerprint = {d["fingerprint"]: d for d in document["diagnostics"]}
    before = {(code, fp): h for code, fp, h in map(str.split, golden["findings"])}
    after = {(code, fp): h for code, fp, h in map(str.split, now["findings"])}
    for code, fp in sorted(after.keys() - before.keys()):
        d = by_fingerprint[fp]
        lines.append(f"  + {code} {subject(d)}: {d['message']} (fingerprint {fp[:12]})")
    for code, fp in sorted(before.keys() - after.keys()):
        lines.append(f"  - {code} fingerprint {fp[:12]} (no longer reported)")
    for code, fp in sorted(before.keys() & after.keys()):
        if before[code, fp] != after[code, fp]:
            d = by_fingerprint[fp]
            lines.append(f"  ~ {code} {subject(d)}: {d['message']} (fingerprint {fp[:12]}: entry changed)")
    for name in sorted(golden["parts"].keys() | now["parts"].keys()):
        if golden["parts"].get(name) != now["parts"].get(name):
            lines.append(f"  part {name} differs")
    if len(lines) == 1:
        lines.append("  (same findings and parts: the order of the findings changed)")
    return lines


def load_golden(path: Path = GOLDEN) -> dict[str, Any]:
    if not path.is_file():
        return {}
    data: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))["robots"]
    return data


def write_golden(entries: dict[str, Any], path: Path = GOLDEN) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    document = {
        "about": "sha256 of normalised JSON reports (default options, sweep on); scripts/golden.py --update",
        "robots": dict(sorted(entries.items())),
    }
    path.write_text(json.dumps(document, indent=1, sort_keys=False) + "\n", encoding="utf-8")


def computed(selected: list[Robot]) -> Iterator[tuple[Robot, dict[str, Any], float]]:
    for robot in selected:
        start = time.perf_counter()
        document = normalised_report(robot)
        yield robot, document, time.perf_counter() - start


def say(text: str) -> None:
    sys.stdout.write(text + "\n")
    sys.stdout.flush()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--update", action="store_true", help="rewrite tests/golden/reports.json")
    parser.add_argument(
        "--robot", action="append", default=[], help="only this robot (robots.toml table name, or the example's path)"
    )
    parser.add_argument("--out", type=Path, help="also write each normalised report to this folder")
    args = parser.parse_args(argv)
    selected = [r for r in robots(corpus_dir()) if not args.robot or r.key in args.robot]
    golden = load_golden()
    entries = {} if args.update and not args.robot else dict(golden)  # a full update drops robots gone
    failed = False
    for robot, document, seconds in computed(selected):
        if args.out is not None:
            target = args.out / (robot.key.replace("/", "__") + ".json")
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
        entries[robot.key] = summary(document)
        if args.update:
            status = "recorded"
        elif robot.key not in golden:
            status, failed = "not in the golden file", True
        else:
            lines = differences(robot.key, golden[robot.key], document)
            status = "identical" if not lines else "\n".join(lines)
            failed = failed or bool(lines)
        say(f"{robot.key} ({seconds:.1f} s): {status}")
    if args.update:
        write_golden(entries)
        say(f"wrote {GOLDEN.relative_to(REPO)} ({len(entries)} robots)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
