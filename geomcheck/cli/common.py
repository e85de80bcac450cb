"""What the commands share at run time: the settings of a description (configuration file and
flags), the output format, the bundle, writing the output and the exit status.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import geomcheck.progress as progress
import geomcheck.untrusted as untrusted
from geomcheck.config import Config, discover_config, load_config, merge
from geomcheck.errors import InputError, UsageError
from geomcheck.options import CheckOptions
from geomcheck.report import DRAWN_FORMATS, FORMATS, Report, RobotSummary, render
from geomcheck.version import __version__

if TYPE_CHECKING:  # loading and checking are imported by the commands that run them (a fast cold start)
    from geomcheck.load import Bundle
from geomcheck.cli.args import DEFAULT_FORMAT, flags_config


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
    if untrusted.in_child() and not _operators_config(ns):  # the repository's configuration narrows; flags grant
        granted = (Path.cwd(), *flags.packages.values(), *flags.search)
        file_config = untrusted.narrow_file_config(file_config, granted)
    return merge(file_config, flags)


def _operators_config(ns: argparse.Namespace) -> bool:
    """Whether ``--config`` names a file outside the checked folder: the operator's, not the repository's."""
    return bool(getattr(ns, "config", None)) and not Path(ns.config).resolve().is_relative_to(Path.cwd().resolve())


def output_format(ns: argparse.Namespace, settings: Config) -> str:
    fmt = settings.output_format or DEFAULT_FORMAT
    if fmt not in FORMATS:
        raise UsageError.bad_choice("output format", fmt, sorted(FORMATS))
    return fmt


def drawn_for(options: CheckOptions, fmt: str, ns: argparse.Namespace) -> CheckOptions:
    """``options`` that draw the views and the 3D scene only when the output shows or carries
    them (``fmt`` in :data:`DRAWN_FORMATS`, not ``--statistics`` nor ``--write-baseline``)."""
    shown = fmt in DRAWN_FORMATS and not getattr(ns, "statistics", False) and not getattr(ns, "write_baseline", None)
    return replace(options, drawings=shown)


def options_from_args(ns: argparse.Namespace) -> CheckOptions:
    """Options for ``ns.path`` (or the first of ``ns.paths``): configuration file and flags."""
    path = getattr(ns, "path", None) or ns.paths[0]
    settings = settings_for(ns, path)
    return settings.to_options()


def bundle_for(path: str | Path, settings: Config, display_root: Path | None = None) -> Bundle:
    from geomcheck.load import make_bundle

    return make_bundle(path, dict(settings.packages), settings.search, display_root=display_root, env=settings.env)


def checked(bundle: Bundle, options: CheckOptions) -> Report:
    """The report of ``bundle``: loaded and checked (the pipeline, imported only then: a check
    read back from the whole check's cache never imports it)."""
    from geomcheck.pipeline import run_check

    return run_check(bundle, options)


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
