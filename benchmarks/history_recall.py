"""Recall on defects robot maintainers fixed themselves (``../shared/corpus/history``).

For every case of ``history/cases.toml`` (``scripts/history_cases.py``), checks the description
before and after the fix with the default options and prints, per case and per defect kind:

- **flagged**: the version before gets an error or warning on an element the fix changed, from a
  rule that can name that kind of defect;
- **cleared**: those rules no longer flag the changed elements after the fix;
- **new after**: the fixed version gets an error or warning on a changed element from a rule
  that did not flag it before.

    python benchmarks/history_recall.py [--case NAME ...] [--json FILE] [--jobs N]

The corpus is ``$GEOMCHECK_CORPUS`` or ``../shared/corpus``. The figures go in docs/precision.md.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
from corpus_robots import corpus_dir  # noqa: E402
from history_cases import Case, Outcome, cases, check_side, outcome, table  # noqa: E402


def check_case(case: Case) -> tuple[str, dict[str, Any], dict[str, Any]]:
    return case.name, check_side(case, "before"), check_side(case, "after")


def describe(o: Outcome) -> str:
    state = "FLAGGED" if o.flagged else "missed"
    if o.flagged:
        state += ", cleared" if o.cleared else ", still flagged after"
    codes = ", ".join(sorted(o.flagged_codes)) or "-"
    new = f"; new after: {', '.join(sorted(o.new_after))}" if o.new_after else ""
    return f"{o.case.name:42s} {o.case.kind:24s} {state:30s} {codes}{new}"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", action="append", default=[], help="only this case (repeatable)")
    parser.add_argument("--json", type=Path, help="also write each side's report here, one JSON object")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="checks in parallel")
    args = parser.parse_args(argv)
    corpus = corpus_dir()
    if corpus is None:
        sys.stderr.write("no corpus: set GEOMCHECK_CORPUS to ../shared/corpus\n")
        return 2
    chosen = [c for c in cases(corpus) if not args.case or c.name in args.case]
    if not chosen:
        sys.stderr.write("no history cases (../shared/corpus/history/cases.toml)\n")
        return 2
    load = os.getloadavg()
    print(f"# {len(chosen)} cases, load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    start = time.perf_counter()
    with ProcessPoolExecutor(max(1, args.jobs)) as pool:
        reports = {name: (before, after) for name, before, after in pool.map(check_case, chosen)}
    outcomes = [outcome(c, *reports[c.name]) for c in chosen]
    for o in outcomes:
        print(describe(o))
    print()
    print(table(outcomes))
    flagged = sum(o.flagged for o in outcomes)
    cleared = sum(o.cleared for o in outcomes)
    print()
    print(
        f"flagged {flagged}/{len(outcomes)} ({flagged / len(outcomes):.0%}), cleared "
        f"{cleared}/{flagged} ({cleared / max(flagged, 1):.0%}) in {time.perf_counter() - start:.0f} s"
    )
    if args.json is not None:
        args.json.write_text(json.dumps({k: {"before": b, "after": a} for k, (b, a) in reports.items()}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
