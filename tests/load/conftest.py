"""Helpers for the loader tests: write small descriptions into tmp_path and load them."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

import pytest

from geomcheck.load import LoadedDescription, load_description, make_bundle
from geomcheck.thresholds import LoadLimits

Loader = Callable[..., LoadedDescription]


@pytest.fixture
def write(tmp_path: Path) -> Callable[[str, str], Path]:
    """Write ``text`` to ``tmp_path/name`` (folders created) and return the path."""

    def _write(name: str, text: str) -> Path:
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        return path

    return _write


@pytest.fixture
def load(tmp_path: Path, write: Callable[[str, str], Path]) -> Loader:
    """Write the root ``text`` (and ``files``) into tmp_path, load it with display paths relative to tmp_path."""

    def _load(
        text: str,
        name: str = "robot.urdf",
        files: Mapping[str, str] | None = None,
        args: Mapping[str, str] | None = None,
        packages: Mapping[str, str | Path] | None = None,
        search: tuple[str | Path, ...] = (),
        confined: bool = False,
        limits: LoadLimits | None = None,
    ) -> LoadedDescription:
        for other, content in (files or {}).items():
            write(other, content)
        root = write(name, text)
        bundle = make_bundle(root, packages, search, display_root=tmp_path, confined=confined)
        return load_description(bundle, args, limits)

    return _load
