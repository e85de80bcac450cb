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
from geomcheck.cli.args import DEFAULT_FORMAT, add_cache_option, cache_store
from geomcheck.cli.check import add_check_parser
from geomcheck.cli.common import settings_for
from geomcheck.cli.diff import add_diff_parser
from geomcheck.cli.fix import add_fix_parser
from geomcheck.cli.matrix import add_matrix_parser
from geomcheck.cli.report import add_render_parser, add_rules_parsers
from geomcheck.cli.service import add_service_parsers
from geomcheck.errors import GeomcheckError, UsageError
from geomcheck.version import __version__

__all__ = ["DEFAULT_FORMAT", "add_cache_option", "build_parser", "main", "settings_for"]

DEBUG_ENV = "GEOMCHECK_DEBUG"

# each command module adds its own subcommands, in the order the help lists them
COMMANDS = (
    add_check_parser,
    add_fix_parser,
    add_diff_parser,
    add_render_parser,
    add_matrix_parser,
    add_rules_parsers,
    add_service_parsers,
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="geomcheck",
        description="Collision and geometry verification for robot descriptions: URDF and xacro, MJCF, SDFormat.",
    )
    parser.add_argument("--version", action="version", version=f"geomcheck {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for add_commands in COMMANDS:
        add_commands(sub)
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
            return failure_status(err)
    show_debug_log(bool(os.environ.get(DEBUG_ENV)))
    bar: progress.TerminalBar | progress.StageLines | None = None
    try:
        bar = progress_bar(ns)
        return run_command(ns, bar)
    except GeomcheckError as err:
        if bar is not None:
            bar.clear()
        return failure_status(err)
    except (KeyboardInterrupt, Exception) as err:
        return failure_status(err)
    finally:
        if bar is not None:
            bar.clear()
        if isinstance(bar, progress.StageLines):
            bar.close()


def run_command(ns: argparse.Namespace, bar: progress.TerminalBar | progress.StageLines | None) -> int:
    """The command's exit status, its stages shown on ``bar``, with the cache it uses."""
    if untrusted.in_child():  # inside the handlers: its imports may already meet the memory limit
        untrusted.confine_this_process()
    with progress.listening(bar):
        store = cache_store(ns)
        if store is None:
            return int(ns.func(ns))
        from geomcheck.cache import using_store

        with using_store(store):
            return int(ns.func(ns))


def failure_status(err: BaseException) -> int:
    """The exit status of a command that raised ``err``, its one line written to stderr; a bug's
    traceback is raised again with ``GEOMCHECK_DEBUG`` set."""
    if isinstance(err, GeomcheckError):
        sys.stderr.write(f"geomcheck: error: {err}\n")
        return err.exit_code
    if isinstance(err, KeyboardInterrupt):
        sys.stderr.write("geomcheck: interrupted\n")
        return 130
    if isinstance(err, MemoryError):
        hint = f" ({err})" if str(err) else ""
        sys.stderr.write(f"geomcheck: error: {untrusted.memory_message()}{hint}\n")
        return 2
    if untrusted.in_child() and untrusted.out_of_memory(err):  # a bug: one line and exit 2 in CI logs
        sys.stderr.write(f"geomcheck: error: {untrusted.memory_message()}\n")
        return 2
    if os.environ.get(DEBUG_ENV):
        raise err
    sys.stderr.write(f"geomcheck: internal error: {type(err).__name__}: {err} (set {DEBUG_ENV}=1 for the traceback)\n")
    return 2


if __name__ == "__main__":
    sys.exit(main())
