"""``geomcheck render``, ``rules`` and ``rule``: saved reports and the rules' documentation."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from geomcheck.cli.args import DEFAULT_FORMAT
from geomcheck.cli.common import exit_status, render_reports, write_output
from geomcheck.errors import UsageError
from geomcheck.report import FORMATS, Report


def add_render_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    again = sub.add_parser("render", help="render a saved JSON report in another format")
    again.add_argument("report", metavar="REPORT.json", help="output of check or diff --format json")
    again.add_argument("--format", help=f"output format: {', '.join(sorted(FORMATS))} (default {DEFAULT_FORMAT})")
    again.add_argument("-o", "--output", metavar="FILE", help="write to FILE")
    again.add_argument("--statistics", action="store_true", help="print the number of findings per rule instead")
    again.add_argument("--exit-zero", action="store_true", help="exit 0 even when the report fails")
    again.set_defaults(func=cmd_render)


def add_rules_parsers(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """``rules`` (the list) and ``rule`` (one rule's documentation)."""
    rules = sub.add_parser("rules", help="list the rules")
    rules.add_argument("--format", choices=("table", "markdown", "json"), default="table")
    rules.add_argument("-o", "--output", metavar="FILE", help="write to FILE (docs/rules.md)")
    rules.set_defaults(func=cmd_rules)
    rule = sub.add_parser("rule", help="show one rule's documentation")
    rule.add_argument("code")
    rule.set_defaults(func=cmd_rule)


def cmd_render(ns: argparse.Namespace) -> int:
    """A saved JSON report (of check or diff) in another format, without checking again."""
    import json

    fmt = ns.format or DEFAULT_FORMAT
    if fmt not in FORMATS:
        raise UsageError.bad_choice("output format", fmt, sorted(FORMATS))
    try:
        report = Report.from_dict(json.loads(Path(ns.report).read_text(encoding="utf-8")))
    except OSError as err:
        raise UsageError(f"cannot read report {ns.report}: {err.strerror}") from None
    except (ValueError, KeyError, TypeError) as err:
        raise UsageError(f"{ns.report} is not a geomcheck JSON report ({err})") from None
    write_output(render_reports([report], fmt, ns.statistics), ns.output)
    return exit_status(report.failed, ns)


def cmd_rules(ns: argparse.Namespace) -> int:
    import json

    from geomcheck.report.rules_markdown import render as render_markdown
    from geomcheck.rules import all_rules

    rules = all_rules()
    if ns.format == "markdown":
        text = render_markdown(rules)
    elif ns.format == "json":
        fields = ("code", "name", "severity", "summary", "what", "why", "example", "fix")
        metric = ("name", "unit", "better", "description", "optional")
        text = (
            json.dumps(
                [
                    {
                        **{f: str(getattr(r, f)) for f in fields},
                        "metrics": [{f: getattr(m, f) for f in metric} for m in r.metrics],
                    }
                    for r in rules
                ],
                indent=2,
            )
            + "\n"
        )
    else:
        width = max((len(r.name) for r in rules), default=4)
        text = "".join(f"{r.code}  {r.name:<{width}}  {r.severity.value:<7}  {r.summary}\n" for r in rules)
    write_output(text, ns.output)
    return 0


def cmd_rule(ns: argparse.Namespace) -> int:
    from geomcheck.fixes.derive import rule_fix_note
    from geomcheck.report.rules_markdown import metrics_text
    from geomcheck.rules import get_rule

    r = get_rule(ns.code)
    automatic = rule_fix_note(r.code)
    metrics = metrics_text(r)
    sys.stdout.write(
        f"{r.code} {r.name} ({r.severity.value})\n\n{r.summary}\n\n"
        f"What it does\n{r.what}\n\nWhy it matters\n{r.why}\n\n"
        + (f"Severity\n{r.severity_reason}\n\n" if r.severity_reason else "")
        + f"Example\n{r.example}\n\nFix\n{r.fix}\n"
        + (f"\nAutomatic fix\n{automatic}\n" if automatic else "")
        + (f"\n{metrics}" if metrics else "")
    )
    return 0
