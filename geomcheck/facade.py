"""geomcheck as a Python library: check, diff and fix a description from a script, a notebook
or a test suite, with the options of the command line and of ``geomcheck.toml``.

    import geomcheck

    report = geomcheck.check("my_robot_description/robots/robot.urdf.xacro", search=["src"], matrix=True)
    for finding in report.diagnostics:
        print(finding.code, finding.subject, finding.message)
    assert not report.failed

Options are the configuration keys of ``geomcheck.toml`` with ``_`` for ``-`` (``fail_on``,
``extend_select``, ``per_link_ignores``...), validated as a configuration file's are (a bad
name or value raises :class:`geomcheck.errors.UsageError` naming the valid ones). The
``geomcheck.toml`` or ``[tool.geomcheck]`` beside the description applies unless
``use_config=False``; the options given here win over it, as command-line flags do.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from geomcheck.config import discover_config
from geomcheck.load import Bundle, make_bundle
from geomcheck.option_spec import Config, merge, read_options
from geomcheck.report.model import Report

PathLike = str | os.PathLike[str]


def settings(path: PathLike, use_config: bool = True, **options: Any) -> Config:
    """The configuration a check of ``path`` runs with: the description's configuration file
    (unless ``use_config`` is false) under ``options`` (configuration keys, ``_`` for ``-``)."""
    data = {key.replace("_", "-"): value for key, value in options.items() if value is not None}
    given = read_options(data, Path.cwd(), "geomcheck.check() options", label=lambda key: key.replace("-", "_"))
    found = discover_config(Path(path)) if use_config else Config()
    return merge(found, given)


def _bundle(path: PathLike, config: Config) -> Bundle:
    return make_bundle(path, dict(config.packages), config.search, env=config.env)


def check(
    path: PathLike,
    *,
    packages: Mapping[str, PathLike] | None = None,
    search: Iterable[PathLike] = (),
    use_config: bool = True,
    **options: Any,
) -> Report:
    """Check the description at ``path`` (URDF or xacro) and return its :class:`Report`.

    ``packages`` maps ROS package names to folders, ``search`` lists folders to find packages
    in; ``options`` are configuration keys (``args={"use_gripper": "true"}``, ``srdf=...``,
    ``matrix=True``, ``select=["GC3"]``, ``fail_on="warning"``...). Raises
    :class:`geomcheck.errors.InputError` when the description cannot be read.
    """
    from geomcheck.pipeline import run_check

    config = _with_packages(settings(path, use_config, **options), packages, search)
    return run_check(_bundle(path, config), config.to_options())


def diff(
    old: PathLike,
    new: PathLike,
    *,
    packages: Mapping[str, PathLike] | None = None,
    search: Iterable[PathLike] = (),
    use_config: bool = True,
    **options: Any,
) -> Report:
    """``new`` against ``old`` (two copies of a description): the report of ``new`` whose
    diagnostics are its new and regressed findings, with the ``diff`` section."""
    from geomcheck.diff import check_other, diff_report
    from geomcheck.pipeline import run_check

    config = _with_packages(settings(new, use_config, **options), packages, search)
    check_options = config.to_options()
    head = run_check(_bundle(new, config), check_options)
    base, label, note = check_other(Path(old), Path(new), config, check_options)
    tolerance = check_options.thresholds.diff.metric_relative_tolerance
    return diff_report(base, head, label, tolerance, base_note=note)


def fix(
    path: PathLike,
    *,
    unsafe: bool = False,
    write: bool = False,
    packages: Mapping[str, PathLike] | None = None,
    search: Iterable[PathLike] = (),
    use_config: bool = True,
    **options: Any,
) -> str:
    """The verified fixes of ``path``'s findings as a unified diff (``""`` when nothing is
    fixable), exactly as ``geomcheck fix --diff`` computes them; ``write`` also applies them
    (files inside the description's folder only). ``unsafe`` includes the fitted primitives
    and inertias."""
    from geomcheck.fix.run import fix_bundle
    from geomcheck.fix.verify import verify
    from geomcheck.patch.apply import write_sources

    config = _with_packages(settings(path, use_config, **options), packages, search)
    check_options = config.to_options()
    bundle = _bundle(path, config)
    verified = verify(fix_bundle(bundle, check_options, unsafe=unsafe), check_options)
    if write:
        write_sources(bundle, verified.original, verified.final)
    return verified.diff


def _with_packages(config: Config, packages: Mapping[str, PathLike] | None, search: Iterable[PathLike]) -> Config:
    extra = {name: Path(folder) for name, folder in (packages or {}).items()}
    return replace(
        config,
        packages={**config.packages, **extra},
        search=(*config.search, *(Path(s) for s in search)),
    )


__all__ = ["check", "diff", "fix", "settings"]
