"""Shared fixtures. The real-robot corpus is reached through GEOMCHECK_CORPUS; without it
the tests that need it are skipped with a message saying so."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

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
