"""One check, as it runs inside its sandboxed process: configuration, bundle, pipeline, JSON report.

A configuration file inside the upload (``geomcheck.toml``, or ``pyproject.toml`` with
``[tool.geomcheck]``, found from the root file's folder up to the upload root and never
above it) applies as it does for the CLI, with the request's options on top; paths it
names must stay inside the upload. ``baseline`` and ``output-format`` are CLI matters and
are not applied.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from pathlib import Path

import geomcheck.progress as progress
from api.checks.options import check_options
from api.checks.sandbox import deliver
from geomcheck.cache import open_store, using_store
from geomcheck.cache.store import CACHE_DIR_ENV
from geomcheck.config import Config, find_config, load_config, merge
from geomcheck.errors import SandboxViolation, UsageError
from geomcheck.fix.offer import verified_fixes
from geomcheck.load import make_bundle
from geomcheck.patch.section import FIXES_SECTION
from geomcheck.pipeline import load_and_check
from geomcheck.report import Report, render


@dataclass(frozen=True)
class CheckJob:
    """What a check process needs: the root file, the upload root report paths are relative
    to, the folder packages are discovered under, and the request's options."""

    check_id: str
    root_file: Path
    display_root: Path
    search_root: Path
    config: Config
    client: str = ""  # the client (token name) submitting it, who owns the check
    verify_fixes: bool = True  # verify the offered fixes once the report is out (False: offer the plan as it is)


FIXES_VERIFYING = "verifying"  # the report is out; its fixes are being verified
FIXES_VERIFIED = "verified"  # the report offers the verified patches
FIXES_UNVERIFIED = "unverified"  # verification was turned off: the report offers the planned patches
FIXES_FAILED = "failed"  # verification did not finish (a limit, a lost worker): the planned patches stay


@dataclass(frozen=True)
class CheckResult:
    """What a check process sends back: the JSON report (the CLI's bytes) and the figures stored
    beside it; ``fixes`` is the state of its offered fixes (None: it offers none)."""

    report_json: str
    robot: str
    source: str
    verdict: str
    summary: dict[str, int]
    has_matrix: bool
    fixes: str | None = None


def upload_config(job: CheckJob) -> Config:
    """The upload's own configuration (defaults when it has none), confined to the upload."""
    found = find_config(job.root_file, within=job.display_root)
    if found is None:
        return Config()
    shown = found.relative_to(job.display_root).as_posix()
    try:
        config = load_config(found)
    except UsageError as err:
        raise UsageError(str(err).replace(str(found), shown)) from None
    area = job.search_root.resolve()
    named = [
        *((f"packages.{k}", p) for k, p in config.packages.items()),
        *(("search", p) for p in config.search),
        *((("srdf", config.srdf),) if config.srdf is not None else ()),
    ]
    for key, path in named:
        if not path.resolve().is_relative_to(area):
            raise SandboxViolation(f"{shown}: {key} points outside the upload")
    return replace(config, baseline=None, output_format=None)


def redact_paths(text: str, job: CheckJob) -> str:
    """``text`` with the server's folders taken out: paths relative to the upload root, the rest ``<upload>``."""
    text = text.replace(f"{job.display_root}/", "").replace(str(job.display_root), ".")
    return text.replace(str(job.search_root.parent), "<upload>")


def run_job(job: CheckJob) -> CheckResult:
    """Check the upload of ``job`` in a confined bundle (nothing outside the upload is readable).

    Messages of failures name files relative to the upload root, never the server's folders.
    """
    # the service hands a stage-cache folder to its check processes only when configured
    store = open_store() if os.environ.get(CACHE_DIR_ENV) else None
    try:
        with using_store(store):
            return _check(job)
    except Exception as err:
        if err.args and isinstance(err.args[0], str):
            err.args = (redact_paths(err.args[0], job), *err.args[1:])
        raise


def _check(job: CheckJob) -> CheckResult:
    config = merge(upload_config(job), job.config)
    bundle = make_bundle(
        job.root_file,
        dict(config.packages),
        [job.search_root, *config.search],
        display_root=job.display_root,
        confined=True,
        uploaded=True,
        env=config.env,
    )
    options = check_options(config)
    loaded, report = load_and_check(bundle, options)
    planned = report.sections.get(FIXES_SECTION)
    if not isinstance(planned, dict):
        return _result(report, None)
    # the report goes out as soon as it exists, offering the planned patches (its fixes
    # section says they are not verified); the verification, as `geomcheck fix` does it, follows
    unverified = replace(report, sections={**report.sections, FIXES_SECTION: {**planned, "verified": False}})
    if not job.verify_fixes:
        return _result(unverified, FIXES_UNVERIFIED)
    deliver(_result(unverified, FIXES_VERIFYING))
    with progress.phase("fixes"):
        fixes = verified_fixes(loaded, report, options)
    assert fixes is not None
    return _result(replace(report, sections={**report.sections, FIXES_SECTION: fixes}), FIXES_VERIFIED)


def _result(report: Report, fixes: str | None) -> CheckResult:
    return CheckResult(
        report_json=render(report, "json"),
        robot=report.robot.name,
        source=report.robot.source,
        verdict="fail" if report.failed else "pass",
        summary=report.counts,
        has_matrix="matrix" in report.sections,
        fixes=fixes,
    )
