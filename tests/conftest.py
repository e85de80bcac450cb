"""Shared fixtures. The real-robot corpus is reached through GEOMCHECK_CORPUS; without it
the tests that need it are skipped with a message saying so."""

from __future__ import annotations

import os
from collections import Counter
from pathlib import Path

import pytest

from tests.corpustools import CorpusReports
from tests.schematools import report_errors

CORPUS_ENV = "GEOMCHECK_CORPUS"


def corpus_dir() -> Path | None:
    value = os.environ.get(CORPUS_ENV)
    if not value:
        return None
    path = Path(value).resolve()
    return path if path.is_dir() else None


@pytest.fixture(scope="session")
def corpus() -> Path:
    """The shared corpus folder (``pr2_2009/``, ``example-robot-data/``), or a skip."""
    path = corpus_dir()
    if path is None:
        pytest.skip(f"shared robot corpus not available: set {CORPUS_ENV} to ../shared/corpus")
    return path


@pytest.fixture(scope="session")
def pr2_root(corpus: Path) -> Path:
    return corpus / "pr2_2009"


@pytest.fixture(scope="session")
def erd_root(corpus: Path) -> Path:
    return corpus / "example-robot-data"


@pytest.fixture(autouse=True)
def _reproducible_time(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1767225600")


@pytest.fixture(autouse=True)
def _private_cache(monkeypatch: pytest.MonkeyPatch, tmp_path_factory: pytest.TempPathFactory) -> None:
    """Each test's CLI runs cache in a folder of their own: never in the user's cache, never
    a result of another test."""
    monkeypatch.setenv("GEOMCHECK_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))


@pytest.fixture(autouse=True)
def _trusted_cli(monkeypatch: pytest.MonkeyPatch) -> None:
    """The CLI runs in-process in tests, also where CI=true would make it untrusted; its stage
    lines on a non-terminal stderr come after an hour, so a test reading stderr is not at the
    mercy of the machine's load (the tests of the lines set what they need)."""
    monkeypatch.setenv("GEOMCHECK_UNTRUSTED", "0")
    monkeypatch.setenv("GEOMCHECK_PROGRESS_AFTER_S", "3600")


def validate_report(document: object) -> None:
    """Fail the test when ``document`` (a parsed JSON report) does not match docs/report-schema.json
    (tests/schematools.py)."""
    errors = report_errors(document)
    if errors:
        pytest.fail(f"report does not match docs/report-schema.json ({len(errors)} errors): {'; '.join(errors[:5])}")


@pytest.fixture(autouse=True)
def _validated_reports(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every JSON report the tests produce (CLI renderer in-process, API responses) is
    validated against the published schema."""
    import json

    import httpx
    import httpx2  # starlette's TestClient

    from geomcheck.report import json_format

    render = json_format.render

    def validating_render(report: object) -> str:
        text = render(report)  # type: ignore[arg-type]
        validate_report(json.loads(text))
        return text

    monkeypatch.setattr(json_format, "render", validating_render)
    send = httpx.Client.send

    def check_response(response: httpx.Response | httpx2.Response, streamed: bool) -> None:
        if streamed or not response.headers.get("content-type", "").startswith("application/json"):
            return
        try:
            body = response.json()
        except ValueError:
            return
        if isinstance(body, dict) and body.get("schema") == "geomcheck.report/1":
            validate_report(body)
        elif isinstance(body, dict) and isinstance(body.get("report"), dict):
            validate_report(body["report"])

    def validating_send(self: httpx.Client, request: httpx.Request, **kwargs: object) -> httpx.Response:
        response = send(self, request, **kwargs)  # type: ignore[arg-type]
        check_response(response, bool(kwargs.get("stream")))
        return response

    monkeypatch.setattr(httpx.Client, "send", validating_send)
    send2 = httpx2.Client.send

    def validating_send2(self: httpx2.Client, request: httpx2.Request, **kwargs: object) -> httpx2.Response:
        response = send2(self, request, **kwargs)  # type: ignore[arg-type]
        check_response(response, bool(kwargs.get("stream")))
        return response

    monkeypatch.setattr(httpx2.Client, "send", validating_send2)


WORKERS_PER_CORE_EXTRA = 1  # pytest-xdist workers beyond one per core [count]


def pytest_xdist_auto_num_workers(config: pytest.Config) -> int | None:
    """``-n auto``: one worker per core and one more. A third of the suite's time is spent
    waiting (for a server, a browser, a Celery worker, a timeout to pass), during which a
    worker holds no core: the extra worker computes then. ``PYTEST_XDIST_AUTO_NUM_WORKERS``
    still decides when it is set."""
    if os.environ.get("PYTEST_XDIST_AUTO_NUM_WORKERS"):
        return None  # pytest-xdist's own hook reads it
    return len(os.sched_getaffinity(0)) + WORKERS_PER_CORE_EXTRA


CORPUS_REPORTS_GROUP = "corpus-reports"


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist's own hook reads the groups
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Send tests to pytest-xdist's workers (``-n``, ``--dist loadgroup``) in groups: every
    test that reads the session's corpus reports in one group, so that each corpus robot is
    still checked once per run, and the other tests by module, so that a module's services and
    fixtures are started once.

    Groups are handed out in this order (``--no-loadscope-reorder``): the corpus reports, the
    longest; then the modules marked ``long`` (tens of seconds of computing or waiting in a few
    tests); then the others, most tests first. A long group handed out last would end the run
    alone while the other workers stand idle."""

    def reads_reports(item: pytest.Item) -> bool:
        return "corpus_reports" in getattr(item, "fixturenames", ())

    groups = {i.nodeid: CORPUS_REPORTS_GROUP if reads_reports(i) else i.nodeid.split("::")[0] for i in items}
    sizes = Counter(groups.values())
    for item in items:
        item.add_marker(pytest.mark.xdist_group(groups[item.nodeid]))

    def rank(item: pytest.Item) -> tuple[int, int, str]:
        group = groups[item.nodeid]
        first = 0 if group == CORPUS_REPORTS_GROUP else 1 if item.get_closest_marker("long") else 2
        return first, -sizes[group], group

    items.sort(key=rank)


@pytest.fixture(scope="session")
def corpus_reports(corpus: Path, tmp_path_factory: pytest.TempPathFactory) -> CorpusReports:
    """Each robots.toml robot's default report (JSON document), computed once per session
    and shared by every test that reads it; the default run's sample of URDF robots checked
    with a stage cache store each, which the cache's test reads back warm."""
    from tests.corpus_robots import corpus_robots, sample

    kept = frozenset(r.name for r in sample(list(corpus_robots(corpus))))
    return CorpusReports(corpus, tmp_path_factory.mktemp("corpus-stores"), kept)
