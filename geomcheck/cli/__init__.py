"""The ``geomcheck`` command line.

Exit status: 0 no finding at or above the failing severity (or ``--exit-zero``), 1 there
are, 2 usage, configuration or input error, or an internal error (one line on stderr; the
traceback of an internal error with ``GEOMCHECK_DEBUG=1``).
Settings come from the configuration file found from the description upwards
(:mod:`geomcheck.config`), with the flags on top.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

import geomcheck.progress as progress
import geomcheck.untrusted as untrusted
from geomcheck.cli.args import (
    DEFAULT_FORMAT,
    add_cache_option,
    add_check_options,
    add_config_options,
    add_load_arguments,
    add_option_flags,
    add_quiet_option,
    add_source_options,
    cache_store,
    flags_of,
)
from geomcheck.cli.check import cmd_check
from geomcheck.cli.common import settings_for
from geomcheck.cli.diff import cmd_diff
from geomcheck.cli.fix import add_fix_flags, add_fix_parser
from geomcheck.cli.matrix import cmd_matrix
from geomcheck.cli.report import cmd_render, cmd_rule, cmd_rules
from geomcheck.cli.service import cmd_serve, cmd_worker
from geomcheck.errors import GeomcheckError, UsageError
from geomcheck.report import FORMATS
from geomcheck.untrusted import add_untrusted_options
from geomcheck.version import __version__

__all__ = ["DEFAULT_FORMAT", "add_cache_option", "build_parser", "main", "settings_for"]

DEBUG_ENV = "GEOMCHECK_DEBUG"


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="geomcheck",
        description="Collision and geometry verification for robot descriptions: URDF and xacro, MJCF, SDFormat.",
    )
    parser.add_argument("--version", action="version", version=f"geomcheck {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)

    check = sub.add_parser("check", help="check robot descriptions")
    check.add_argument("paths", nargs="+", metavar="PATH", help="root URDF, xacro, MJCF or SDFormat file(s)")
    add_source_options(check)
    add_check_options(check)
    base = check.add_argument_group("baseline")
    add_option_flags(base, flags_of("baseline"))
    base.add_argument("--write-baseline", metavar="FILE", help="record the current findings in FILE and exit 0")
    add_cache_option(check)
    add_quiet_option(check)
    add_untrusted_options(check)
    add_fix_flags(check, with_fix=True)
    check.set_defaults(func=cmd_check)
    add_fix_parser(sub)

    diff = sub.add_parser(
        "diff",
        help="report what a change did: new, fixed and regressed findings",
        description="geomcheck diff --base REV PATH compares PATH at git revision REV with the working tree; "
        "geomcheck diff OLD NEW compares two descriptions. Exit 1 when a new finding fails.",
    )
    diff.add_argument("paths", nargs="+", metavar="PATH", help="PATH with --base, else OLD NEW")
    diff.add_argument("--base", metavar="REV", help="git revision to compare the working tree with")
    diff.add_argument(
        "--fail-on-regression",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="report a kept finding that got worse (severity rose, or a metric past the tolerance) like a new "
        "one, so it fails at --fail-on (default: on)",
    )
    add_source_options(diff)
    add_check_options(diff)
    add_cache_option(diff)
    add_quiet_option(diff)
    add_untrusted_options(diff)
    diff.set_defaults(func=cmd_diff)

    again = sub.add_parser("render", help="render a saved JSON report in another format")
    again.add_argument("report", metavar="REPORT.json", help="output of check or diff --format json")
    again.add_argument("--format", help=f"output format: {', '.join(sorted(FORMATS))} (default {DEFAULT_FORMAT})")
    again.add_argument("-o", "--output", metavar="FILE", help="write to FILE")
    again.add_argument("--statistics", action="store_true", help="print the number of findings per rule instead")
    again.add_argument("--exit-zero", action="store_true", help="exit 0 even when the report fails")
    again.set_defaults(func=cmd_render)

    matrix = sub.add_parser(
        "matrix",
        help="compute the collision matrix and write it as a MoveIt SRDF",
        description="Classify every pair of links with collision geometry as MoveIt's Setup Assistant does "
        "(Adjacent, Default, Always, Never), with certified-never pairs and a witness search, and write the "
        "<disable_collisions> list (to stdout without --srdf-out).",
    )
    add_load_arguments(matrix)
    matrix.add_argument("--srdf-out", metavar="FILE", help="write the SRDF to FILE and a summary to stdout")
    add_option_flags(matrix, flags_of("checks", "matrix"))
    add_config_options(matrix)
    add_cache_option(matrix)
    add_quiet_option(matrix)
    add_untrusted_options(matrix)
    matrix.set_defaults(func=cmd_matrix)

    rules = sub.add_parser("rules", help="list the rules")
    rules.add_argument("--format", choices=("table", "markdown", "json"), default="table")
    rules.add_argument("-o", "--output", metavar="FILE", help="write to FILE (docs/rules.md)")
    rules.set_defaults(func=cmd_rules)
    rule = sub.add_parser("rule", help="show one rule's documentation")
    rule.add_argument("code")
    rule.set_defaults(func=cmd_rule)
    serve = sub.add_parser("serve", help="run the HTTP service (settings: GEOMCHECK_* environment variables)")
    serve.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    serve.add_argument("--port", type=int, default=8000, help="port to listen on (default 8000)")
    serve.add_argument("--database", metavar="URL", help="database URL (default: SQLite in GEOMCHECK_DATA_DIR)")
    serve.set_defaults(func=cmd_serve)

    worker = sub.add_parser(
        "worker",
        help="run checks for the HTTP service's distributed mode (GEOMCHECK_BROKER_URL, GEOMCHECK_DATABASE_URL)",
    )
    worker.add_argument("--concurrency", type=int, default=os.cpu_count() or 1, help="checks at once (default: cores)")
    worker.add_argument("--beat", action="store_true", help="also schedule the periodic retention (one per deployment)")
    worker.add_argument(
        "--ping",
        action="store_true",
        help="exit 0 when a worker on this host answers through the broker, else 1 (a container health check)",
    )
    worker.set_defaults(func=cmd_worker)
    return parser


def show_debug_log(enabled: bool) -> None:
    """Whether geomcheck's debug log lines (corrupt cache entries, evictions) go to stderr."""
    import logging

    class StderrLines(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            sys.stderr.write(f"geomcheck: debug: {record.getMessage()}\n")  # the stderr of the moment

    logger = logging.getLogger("geomcheck")
    for handler in [h for h in logger.handlers if type(h).__name__ == "StderrLines"]:
        logger.removeHandler(handler)
    if enabled:
        logger.addHandler(StderrLines())
    logger.setLevel(logging.DEBUG if enabled else logging.NOTSET)


PROGRESS_COMMANDS = ("cmd_check", "cmd_diff", "cmd_fix", "cmd_matrix")  # the commands that take long


def progress_bar(ns: argparse.Namespace) -> progress.TerminalBar | progress.StageLines | None:
    """How the long commands show their stages on stderr, whatever the output (``-o``, JSON)
    and also while fixing: a bar on a terminal; elsewhere (a CI log, a pipe) one line per stage
    once the run takes more than a few seconds; ``None`` with ``--quiet`` and for the others."""
    func = getattr(ns, "func", None)
    if getattr(func, "__name__", "") not in PROGRESS_COMMANDS or getattr(ns, "quiet", False):
        return None
    if sys.stderr.isatty():
        return progress.TerminalBar(sys.stderr)
    after = os.environ.get(progress.LINES_AFTER_ENV, "").strip()
    try:
        after_s = float(after) if after else progress.LINES_AFTER_S
    except ValueError:
        raise UsageError(f"{progress.LINES_AFTER_ENV} must be a number of seconds, got {after!r}") from None
    return progress.StageLines(sys.stderr, after_s)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        ns = parser.parse_args(argv)
    except SystemExit as exc:  # argparse exits 2 on usage errors, 0 on --help
        return int(exc.code or 0)
    if hasattr(ns, "untrusted") and not untrusted.in_child():
        try:
            if untrusted.untrusted_requested(ns.untrusted, os.environ):
                limits = untrusted.limits_from(ns)
                return untrusted.run_untrusted(sys.argv[1:] if argv is None else argv, limits, ns.allow_env)
        except GeomcheckError as err:
            sys.stderr.write(f"geomcheck: error: {err}\n")
            return err.exit_code
    show_debug_log(bool(os.environ.get(DEBUG_ENV)))
    bar: progress.TerminalBar | progress.StageLines | None = None
    try:
        bar = progress_bar(ns)
        if untrusted.in_child():  # inside the handlers: its imports may already meet the memory limit
            untrusted.confine_this_process()
        with progress.listening(bar):
            store = cache_store(ns)
            if store is None:
                return int(ns.func(ns))
            from geomcheck.cache import using_store

            with using_store(store):
                return int(ns.func(ns))
    except GeomcheckError as err:
        if bar is not None:
            bar.clear()
        sys.stderr.write(f"geomcheck: error: {err}\n")
        return err.exit_code
    except KeyboardInterrupt:
        sys.stderr.write("geomcheck: interrupted\n")
        return 130
    except MemoryError as err:
        hint = f" ({err})" if str(err) else ""
        sys.stderr.write(f"geomcheck: error: {untrusted.memory_message()}{hint}\n")
        return 2
    except Exception as err:  # a bug: one line and exit 2 in CI logs; the traceback on request
        if untrusted.in_child() and untrusted.out_of_memory(err):
            sys.stderr.write(f"geomcheck: error: {untrusted.memory_message()}\n")
            return 2
        if os.environ.get(DEBUG_ENV):
            raise
        sys.stderr.write(
            f"geomcheck: internal error: {type(err).__name__}: {err} (set {DEBUG_ENV}=1 for the traceback)\n"
        )
        return 2
    finally:
        if bar is not None:
            bar.clear()
        if isinstance(bar, progress.StageLines):
            bar.close()


if __name__ == "__main__":
    sys.exit(main())
