"""geomcheck against urdfdom's and libsdformat's own test suites: the agreement per suite and
every case that does not agree (tests/load/conformance/, docs/conformance.md).

    python scripts/conformance.py            # the figures and the disagreements
    python scripts/conformance.py --all      # every case and geomcheck's answer
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from tests.load.conformance.harness import agreement, run_case  # noqa: E402
from tests.load.conformance.sdformat_cases import CASES as SDFORMAT  # noqa: E402
from tests.load.conformance.urdfdom_cases import CASES as URDFDOM  # noqa: E402


def say(text: str) -> None:
    sys.stdout.write(text + "\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="list every case, not only the disagreements")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        for name, cases in (("urdfdom", URDFDOM), ("libsdformat (one model per file)", SDFORMAT)):
            found = [run_case(case, Path(folder) / name / str(i)) for i, case in enumerate(cases)]
            agreed, total = agreement(found)
            say(f"{name}: {agreed} of {total} cases agree ({agreed / total:.1%})")
            for o in found:
                if args.all or not o.agrees:
                    mark = "agrees" if o.agrees else "DISAGREES"
                    detail = "; ".join([*o.said[:1], *o.wrong_facts[:2]])
                    say(f"  {mark}: {o.case.id}: reference {o.case.verdict}, geomcheck {o.verdict}  {detail}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
