"""The service's result cache: a POST whose result is already known is answered at once.

Two keys find a stored check (both live in the database, so every replica and both modes
share them):

* the **request key**, over the request's body bytes (XML documents and archives; a
  multipart body carries a random boundary and has none), its media type, its ``root``
  and options, the service's limits that shape options and the code's versions. It is known
  as soon as the body has arrived, before anything is unpacked: a CI gate re-posting the
  same archive is answered from it.
* the **result key** (:func:`api.results.key.result_key`), over the canonical
  upload (every file's relative path and sha256, a ``geomcheck.toml`` inside included),
  the root file, the effective options and thresholds and the versions: the same
  description sent as another archive or as a form finds the same report.

``fail_on`` is applied after the lookup: the report is re-rendered when the asked
``fail_on`` differs from the stored one, and when the stored report is another client's (its
``created`` time is then this check's: :func:`restamp`). Rule selection stays in the key: it decides which
analyses run (``select=GC1`` loads no mesh), so a narrower selection's report is not a
filter of a stored one. ``cache=false`` (query parameter or form field) forces a fresh run.
"""

from __future__ import annotations

import functools
import hashlib
import json
from dataclasses import replace
from pathlib import Path

from api.checks.job import CheckJob, upload_config
from api.checks.options import RawOptions
from api.results.key import result_key, result_versions, upload_digests
from api.settings import Settings
from api.store import CacheKeys
from geomcheck.cache.keys import digest_key
from geomcheck.config import Config
from geomcheck.diagnostics import Severity
from geomcheck.errors import GeomcheckError
from geomcheck.report import Report, render
from geomcheck.report.model import report_timestamp

FORMAT = 1
# modules of the service that shape a report besides the library: the upload's configuration,
# the request's options, the layout of the upload
REPORT_MODULES = ("checks/job.py", "checks/options.py", "uploads/layout.py", "results/cache.py")


@functools.cache
def service_versions() -> dict[str, str]:
    """:func:`result_versions` and a digest of the service modules that shape a report."""
    folder = Path(__file__).resolve().parents[1]  # api/
    h = hashlib.sha256()
    for name in REPORT_MODULES:
        h.update(name.encode() + b"\0" + (folder / name).read_bytes())
    return {**result_versions(), "api": h.hexdigest()[:16]}


def request_key(
    media: str, body_sha256: str, root: str | None, raw: RawOptions, settings: Settings, verify_fixes: bool = True
) -> str:
    """The key of a request whose body (``body_sha256``) is the whole upload."""
    # repeated values keep their order: of two pairs naming one argument the later wins
    options = {name: list(values) for name, values in sorted(raw.values.items()) if name != "fail_on"}
    if not verify_fixes:  # a report offering the planned patches answers only requests that asked for that
        options["verify_fixes"] = ["false"]
    return digest_key(
        "request", FORMAT, media, body_sha256, root or "", options, settings.max_samples, service_versions()
    )


def fail_on_value(config: Config) -> str | None:
    """The ``fail_on`` a request named (its options or form fields), None when it named none."""
    return config.fail_on.value if config.fail_on is not None else None


def upload_keys(job: CheckJob, request_key_: str | None) -> CacheKeys:
    """Both keys of an arranged upload, and the fail_on a request naming none gets from it.

    A configuration file in the upload that cannot be read gives no result key (the check
    runs and reports why)."""
    asked = fail_on_value(job.config)
    try:
        own = upload_config(job).fail_on
    except GeomcheckError:
        return CacheKeys(request_key=None, fail_on=asked)
    default = (own or Severity.ERROR).value
    root = job.root_file.relative_to(job.search_root).as_posix()
    config = replace(job.config, fail_on=None)
    key = result_key(upload_digests(job.search_root), root, config, job.search_root, service_versions())
    if not job.verify_fixes:
        key = digest_key("unverified-fixes", FORMAT, key)
    return CacheKeys(request_key=request_key_, result_key=key, fail_on=asked or default, default_fail_on=default)


def restamp(report_json: str) -> str:
    """``report_json`` with this moment as its ``created`` time: a report shared with another
    client shows the time of that client's check, never the time of the check it came from."""
    return render(replace(Report.from_dict(json.loads(report_json)), created=report_timestamp()), "json")


def rerender(report_json: str, fail_on: str) -> tuple[str, str]:
    """``report_json`` with another ``fail_on``, and its verdict (``pass`` or ``fail``)."""
    report = replace(Report.from_dict(json.loads(report_json)), fail_on=Severity(fail_on))
    return render(report, "json"), "fail" if report.failed else "pass"
