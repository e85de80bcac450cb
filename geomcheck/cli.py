"""The ``geomcheck`` command line.

Exit status: 0 no finding at or above the failing severity, 1 there are, 2 usage or input
error (one line on stderr, never a traceback).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from geomcheck import __version__
from geomcheck.diagnostics import Severity
from geomcheck.errors import GeomcheckError, UsageError
from geomcheck.load import make_bundle
from geomcheck.options import BACKENDS, CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report import FORMATS, render


def parse_assignment(text: str, what: str) -> tuple[str, str]:
    """``NAME=VALUE`` split; :class:`UsageError` otherwise."""
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise UsageError(f"{what} must be NAME=VALUE, got {text!r}")
    return name.strip(), value


def parse_float(text: str, what: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise UsageError(f"{what} must be a number, got {text!r}") from None


def add_load_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", help="root URDF or xacro file")
    p.add_argument("--package", action="append", default=[], metavar="NAME=DIR", help="ROS package location")
    p.add_argument("--search", action="append", default=[], metavar="DIR", help="discover packages under DIR")
    p.add_argument("--arg", action="append", default=[], metavar="NAME=VALUE", help="xacro argument")


def add_check_arguments(p: argparse.ArgumentParser) -> None:
    add_load_arguments(p)
    p.add_argument("--format", default="text", help=f"output format ({', '.join(sorted(FORMATS))})")
    p.add_argument("-o", "--output", metavar="FILE", help="write the report to FILE")
    p.add_argument("--fail-on", default="error", help="lowest severity that fails (error, warning, info)")
    p.add_argument("--srdf", metavar="FILE", help="SRDF to audit (and to read named poses from)")
    p.add_argument("--pose", action="append", default=[], metavar="JOINT=VALUE", help="default-pose joint value")
    p.add_argument("--pose-name", metavar="NAME", help="SRDF group_state to use as the default pose")
    p.add_argument("--backend", default="coal", help=f"collision backend ({', '.join(BACKENDS)})")
    p.add_argument("--matrix", action="store_true", help="also compute the collision matrix")
    p.add_argument("--no-sweep", action="store_true", help="skip the continuous-joint sweep")
    p.add_argument("--samples", type=int, help="matrix samples (default 10000)")
    p.add_argument("--seed", type=int, help="matrix sampling seed (default 0)")


def options_from_args(ns: argparse.Namespace) -> CheckOptions:
    if ns.backend not in BACKENDS:
        raise UsageError.bad_choice("backend", ns.backend, BACKENDS)
    if ns.format not in FORMATS:
        raise UsageError.bad_choice("output format", ns.format, sorted(FORMATS))
    pose = {}
    for item in ns.pose:
        name, value = parse_assignment(item, "--pose")
        pose[name] = parse_float(value, f"--pose {name}")
    return CheckOptions(
        args=dict(parse_assignment(a, "--arg") for a in ns.arg),
        srdf=Path(ns.srdf) if ns.srdf else None,
        pose=pose,
        pose_name=ns.pose_name,
        backend=ns.backend,
        matrix=ns.matrix,
        sweep=not ns.no_sweep,
        samples=ns.samples,
        seed=ns.seed,
        fail_on=Severity.parse(ns.fail_on),
        progress=sys.stderr.isatty() and ns.format in ("text",) and ns.output is None,
    )


def write_output(text: str, output: str | None) -> None:
    if output:
        Path(output).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)


def cmd_check(ns: argparse.Namespace) -> int:
    options = options_from_args(ns)
    bundle = make_bundle(ns.path, dict(parse_assignment(p, "--package") for p in ns.package), ns.search)
    report = run_check(bundle, options)
    write_output(render(report, ns.format), ns.output)
    return 1 if report.failed else 0


def cmd_rules(ns: argparse.Namespace) -> int:
    from geomcheck.rules import all_rules

    rows = [(r.code, r.name, r.severity.value, r.summary) for r in all_rules()]
    width = max((len(r[1]) for r in rows), default=4)
    lines = [f"{code}  {name:<{width}}  {sev:<7}  {summary}" for code, name, sev, summary in rows]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def cmd_rule(ns: argparse.Namespace) -> int:
    from geomcheck.rules import get_rule

    r = get_rule(ns.code)
    sys.stdout.write(
        f"{r.code} {r.name} ({r.severity.value})\n\n{r.summary}\n\n"
        f"What it does\n{r.what}\n\nWhy it matters\n{r.why}\n\nExample\n{r.example}\n\nFix\n{r.fix}\n"
    )
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="geomcheck", description="Collision and geometry verification for URDF and xacro."
    )
    parser.add_argument("--version", action="version", version=f"geomcheck {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    check = sub.add_parser("check", help="check a robot description")
    add_check_arguments(check)
    check.set_defaults(func=cmd_check)
    rules = sub.add_parser("rules", help="list the rules")
    rules.set_defaults(func=cmd_rules)
    rule = sub.add_parser("rule", help="show one rule's documentation")
    rule.add_argument("code")
    rule.set_defaults(func=cmd_rule)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        ns = parser.parse_args(argv)
    except SystemExit as exc:  # argparse exits 2 on usage errors, 0 on --help
        return int(exc.code or 0)
    try:
        return int(ns.func(ns))
    except GeomcheckError as err:
        sys.stderr.write(f"geomcheck: error: {err}\n")
        return err.exit_code
    except KeyboardInterrupt:
        sys.stderr.write("geomcheck: interrupted\n")
        return 130


if __name__ == "__main__":
    sys.exit(main())
