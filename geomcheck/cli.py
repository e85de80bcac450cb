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
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from geomcheck import progress, untrusted
from geomcheck.config import Config, discover_config, load_config, merge, parse_config
from geomcheck.errors import GeomcheckError, InputError, UsageError
from geomcheck.fix.command import add_fix_flags, add_fix_parser, cmd_fix
from geomcheck.option_spec import OPTIONS, Group, Option, options_where
from geomcheck.options import CheckOptions
from geomcheck.report import FORMATS, Report, RobotSummary, render
from geomcheck.untrusted import add_untrusted_options
from geomcheck.version import __version__

if TYPE_CHECKING:  # loading and checking are imported by the commands that run them (a fast cold start)
    from geomcheck.cache.store import Store
    from geomcheck.load import Bundle

DEFAULT_FORMAT = "full"
DEBUG_ENV = "GEOMCHECK_DEBUG"
# formats whose output for several descriptions is their outputs one after the other
LINE_FORMATS = ("full", "text", "concise", "github")


# --- arguments ---------------------------------------------------------------------------


def add_option_flags(p: argparse.ArgumentParser | argparse._ArgumentGroup, options: Sequence[Option]) -> None:
    """The flags of ``options`` (:data:`geomcheck.option_spec.OPTIONS`): help, metavar and
    action from their declaration; values are validated as configuration keys (:func:`flags_config`)."""
    for option in options:
        assert option.flag is not None
        kwargs: dict[str, Any] = {"help": option.description()}
        if option.kind == "bool":
            kwargs["action"] = argparse.BooleanOptionalAction
        elif option.repeatable:
            kwargs.update(action="append", metavar=option.metavar)
        elif option.kind == "int":
            kwargs["type"] = int
        elif option.metavar:
            kwargs["metavar"] = option.metavar
        p.add_argument(option.flag, **kwargs)


def flags_of(group: Group, command: str = "check") -> list[Option]:
    """The options of flag group ``group`` on ``command`` (``check`` or ``matrix``)."""
    return [o for o in options_where("matrix" if command == "matrix" else "check") if o.group == group]


def add_source_options(p: argparse.ArgumentParser) -> None:
    add_option_flags(p, flags_of("sources"))


def add_load_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", help="root URDF or xacro file")
    add_source_options(p)


def add_check_options(p: argparse.ArgumentParser) -> None:
    """Output, failing, selection, configuration and check options (all default to the
    configuration file, then to the built-in defaults)."""
    out = p.add_argument_group("output")
    add_option_flags(out, flags_of("output"))
    out.add_argument("-o", "--output", metavar="FILE", help="write the report to FILE")
    out.add_argument("--statistics", action="store_true", help="print the number of findings per rule instead")
    gate = p.add_argument_group("exit status")
    add_option_flags(gate, flags_of("exit status"))
    gate.add_argument("--exit-zero", action="store_true", help="exit 0 even when findings fail")
    sel = p.add_argument_group("rule selection (codes, prefixes such as GC3, family names such as fit, or ALL)")
    add_option_flags(sel, flags_of("rule selection"))
    add_config_options(p.add_argument_group("configuration"))
    add_option_flags(p.add_argument_group("checks"), flags_of("checks"))


def add_config_options(p: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
    p.add_argument("--config", metavar="FILE", help="use this geomcheck.toml or pyproject.toml")
    p.add_argument("--no-config", action="store_true", help="ignore configuration files")


def add_cache_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--no-cache",
        action="store_true",
        help="neither read nor write the cache (GEOMCHECK_CACHE_DIR, default $XDG_CACHE_HOME/geomcheck)",
    )


def cache_store(ns: argparse.Namespace) -> Store | None:
    """The cache store for this command: none for commands that compute nothing or with ``--no-cache``."""
    if getattr(ns, "no_cache", True):
        return None
    from geomcheck.cache import open_store

    return open_store()


def add_check_arguments(p: argparse.ArgumentParser) -> None:
    """One description and every check option (``ns.path``)."""
    add_load_arguments(p)
    add_check_options(p)


def flags_config(ns: argparse.Namespace) -> Config:
    """The flags that were given, validated as configuration keys (by each option's own validator)."""
    flagged = [o for o in OPTIONS if o.flag is not None]
    data: dict[str, Any] = {}
    for option in flagged:
        value = getattr(ns, option.dest, None)  # subcommands define subsets of the flags
        if value is not None:
            data[option.key] = option.from_text(value if option.repeatable else [value], str(option.flag))
    flags = {o.key: str(o.flag) for o in flagged}
    return parse_config(data, Path.cwd(), "command line", label=lambda k: flags[k])


def settings_for(ns: argparse.Namespace, path: str | Path) -> Config:
    """The configuration that applies to the description ``path`` with the flags on top."""
    if getattr(ns, "no_config", False):
        file_config = Config()
    elif getattr(ns, "config", None):
        config_path = Path(ns.config)
        if not config_path.is_file():
            raise UsageError(f"--config: no such file: {config_path}")
        file_config = load_config(config_path)
    else:
        file_config = discover_config(Path(path))
    flags = flags_config(ns)
    operators = getattr(ns, "config", None) and not Path(ns.config).resolve().is_relative_to(Path.cwd().resolve())
    if untrusted.in_child() and not operators:  # the repository's configuration narrows; flags grant
        granted = (Path.cwd(), *flags.packages.values(), *flags.search)
        file_config = untrusted.narrow_file_config(file_config, granted)
    return merge(file_config, flags)


def output_format(ns: argparse.Namespace, settings: Config) -> str:
    fmt = settings.output_format or DEFAULT_FORMAT
    if fmt not in FORMATS:
        raise UsageError.bad_choice("output format", fmt, sorted(FORMATS))
    return fmt


def wants_progress(ns: argparse.Namespace, fmt: str) -> bool:
    return sys.stderr.isatty() and fmt in LINE_FORMATS and getattr(ns, "output", None) is None


def options_from_args(ns: argparse.Namespace) -> CheckOptions:
    """Options for ``ns.path`` (or the first of ``ns.paths``): configuration file and flags."""
    path = getattr(ns, "path", None) or ns.paths[0]
    settings = settings_for(ns, path)
    return settings.to_options(progress=wants_progress(ns, output_format(ns, settings)))


def bundle_for(path: str | Path, settings: Config, display_root: Path | None = None) -> Bundle:
    from geomcheck.load import make_bundle

    return make_bundle(path, dict(settings.packages), settings.search, display_root=display_root)


def display_path(path: Path) -> str:
    """``path`` relative to the current folder when it lies inside it, posix separators."""
    resolved = path.resolve()
    cwd = Path.cwd().resolve()
    return resolved.relative_to(cwd).as_posix() if resolved.is_relative_to(cwd) else resolved.as_posix()


def write_output(text: str, output: str | None) -> None:
    progress.clear_display()
    if output:
        try:
            Path(output).write_text(text, encoding="utf-8")
        except OSError as err:
            raise UsageError(f"cannot write {output}: {err.strerror}") from None
    else:
        sys.stdout.write(text)


def render_reports(reports: Sequence[Report], fmt: str, statistics: bool) -> str:
    from geomcheck.report import statistics as stats

    if statistics:
        merged = replace(reports[0], diagnostics=tuple(d for r in reports for d in r.diagnostics))
        return stats.render_json(merged) if fmt == "json" else stats.render_text(merged)
    return "".join(render(r, fmt) for r in reports)


@contextmanager
def annotated_input_errors(fmt: str, output: str | None) -> Iterator[None]:
    """With ``--format github`` on stdout, an unreadable description (exit 2) is also an
    annotation on the file and line that broke it."""
    try:
        yield
    except InputError as err:
        if fmt == "github" and output is None and err.diagnostic is not None:
            from geomcheck.report.github import annotation

            source = err.diagnostic.location.file if err.diagnostic.location else ""
            empty = Report(RobotSummary("", source, 0, 0), (), __version__, "")
            sys.stdout.write(annotation(err.diagnostic, empty) + "\n")
        raise


def exit_status(failed: bool, ns: argparse.Namespace) -> int:
    return 1 if failed and not ns.exit_zero else 0


# --- commands ----------------------------------------------------------------------------


def cmd_check(ns: argparse.Namespace) -> int:
    from geomcheck.baseline import Baseline, apply_baseline
    from geomcheck.pipeline import run_check

    if ns.fix or ns.diff:
        return cmd_fix(ns)

    runs = [(path, settings_for(ns, path)) for path in ns.paths]
    fmt = output_format(ns, runs[0][1])
    if len(runs) > 1 and fmt not in LINE_FORMATS and not ns.statistics:
        raise UsageError(f"--format {fmt} takes one description; run geomcheck once per description")
    progress = wants_progress(ns, fmt)
    with annotated_input_errors(fmt, ns.output):
        reports = [run_check(bundle_for(p, s), s.to_options(progress=progress)) for p, s in runs]
    if ns.write_baseline:
        baseline = Baseline.from_diagnostics(d for r in reports for d in r.diagnostics)
        baseline.write(Path(ns.write_baseline))
        sys.stderr.write(f"geomcheck: wrote {len(baseline.entries)} findings to baseline {ns.write_baseline}\n")
        return 0
    baseline_files = {s.baseline for _, s in runs if s.baseline is not None}
    if len(baseline_files) > 1:
        raise UsageError("the descriptions' configurations name different baselines; pass --baseline FILE")
    if baseline_files:
        baseline_file = baseline_files.pop()
        label = display_path(baseline_file)
        reports, result = apply_baseline(reports, Baseline.load(baseline_file), label)
        if result.stale:
            sys.stderr.write(
                f"geomcheck: {len(result.stale)} baseline entries no longer occur; "
                f"update it with --write-baseline {label}\n"
            )
    write_output(render_reports(reports, fmt, ns.statistics), ns.output)
    return exit_status(any(r.failed for r in reports), ns)


def cmd_diff(ns: argparse.Namespace) -> int:
    from geomcheck.diff import check_base_revision, check_other, diff_report
    from geomcheck.pipeline import run_check

    if ns.base is not None and len(ns.paths) != 1:
        raise UsageError("diff --base REV takes one description: geomcheck diff --base REV PATH")
    if ns.base is None and len(ns.paths) != 2:
        raise UsageError("diff takes --base REV PATH, or two descriptions: geomcheck diff OLD NEW")
    head_path = ns.paths[-1]
    settings = settings_for(ns, head_path)
    fmt = output_format(ns, settings)
    options = settings.to_options(progress=wants_progress(ns, fmt))
    with annotated_input_errors(fmt, ns.output):
        head = run_check(bundle_for(head_path, settings), options)
    if ns.base is not None:
        base, label, note = check_base_revision(ns.base, Path(head_path), settings, options)
    else:
        base, label, note = check_other(Path(ns.paths[0]), Path(head_path), settings, options)
    tolerance = options.thresholds.diff.metric_relative_tolerance
    report = diff_report(base, head, label, tolerance, base_note=note, gate_regressions=ns.fail_on_regression)
    write_output(render_reports([report], fmt, ns.statistics), ns.output)
    return exit_status(report.failed, ns)


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
    from geomcheck.fix.derive import rule_fix_note
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


def cmd_matrix(ns: argparse.Namespace) -> int:
    """The collision matrix as a MoveIt SRDF ``<disable_collisions>`` list (file or stdout)."""
    from geomcheck.checks.matrix import load_and_compute
    from geomcheck.report.srdf import render_srdf

    settings = settings_for(ns, ns.path)
    options = replace(settings.to_options(progress=sys.stderr.isatty()), matrix=True, sweep=False)
    loaded, matrix = load_and_compute(bundle_for(ns.path, settings), options)
    write_output(render_srdf(matrix, loaded.robot.name), ns.srdf_out)
    if ns.srdf_out:
        counts = matrix.counts()
        tally = ", ".join(f"{counts[c]} {c}" for c in ("adjacent", "default", "always", "never", "enabled"))
        sys.stdout.write(
            f"{loaded.robot.name}: {len(matrix.pairs)} pairs of {len(matrix.links)} links: {tally} "
            f"({counts['certified']} never pairs certified); {matrix.samples} samples, seed {matrix.seed}, "
            f"backend {matrix.backend}, {matrix.stats.seconds:.1f} s; wrote {ns.srdf_out}\n"
        )
    return 0


def cmd_serve(ns: argparse.Namespace) -> int:
    from api.server import serve  # the one sanctioned import of the service: the library never needs it

    serve(ns.host, ns.port, ns.database)
    return 0


def cmd_worker(ns: argparse.Namespace) -> int:
    if ns.ping:
        from api.distributed.health import local_worker_answers
        from api.settings import Settings

        return 0 if local_worker_answers(Settings()) else 1
    from api.distributed.worker import run_worker  # the service's Celery worker (distributed mode)

    if ns.concurrency < 1:
        raise UsageError(f"--concurrency must be at least 1, got {ns.concurrency}")
    run_worker(ns.concurrency, beat=ns.beat)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="geomcheck", description="Collision and geometry verification for URDF and xacro."
    )
    parser.add_argument("--version", action="version", version=f"geomcheck {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)

    check = sub.add_parser("check", help="check robot descriptions")
    check.add_argument("paths", nargs="+", metavar="PATH", help="root URDF or xacro file(s)")
    add_source_options(check)
    add_check_options(check)
    base = check.add_argument_group("baseline")
    add_option_flags(base, flags_of("baseline"))
    base.add_argument("--write-baseline", metavar="FILE", help="record the current findings in FILE and exit 0")
    add_cache_option(check)
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


def progress_bar(ns: argparse.Namespace) -> progress.TerminalBar | None:
    """A stage bar on stderr when it is a terminal, for the long commands, whatever the output
    (``-o``, JSON) and also while fixing; ``None`` otherwise (CI logs, pipes)."""
    func = getattr(ns, "func", None)
    if not sys.stderr.isatty() or getattr(func, "__name__", "") not in PROGRESS_COMMANDS:
        return None
    return progress.TerminalBar(sys.stderr)


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
    bar = progress_bar(ns)
    try:
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


if __name__ == "__main__":
    sys.exit(main())
