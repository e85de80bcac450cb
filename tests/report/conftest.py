"""Fixtures shared by the report tests."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

import pytest


@pytest.fixture(scope="session")
def html_samples() -> ModuleType:
    """``html_samples.py`` beside this file, the demo report the HTML tests render (loaded by
    path: the tests are imported in importlib mode, without packages)."""
    spec = importlib.util.spec_from_file_location("html_samples", Path(__file__).with_name("html_samples.py"))
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
