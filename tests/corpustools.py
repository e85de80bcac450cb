"""``scripts/corpus_robots.py`` and ``scripts/precision.py`` loaded once as modules, and the
reports of the corpus robots computed once per test session (:class:`CorpusReports`)."""

from __future__ import annotations

import contextlib
import importlib.util
import sys
import types
from collections.abc import Iterator, Mapping
from pathlib import Path
from types import ModuleType
from typing import Any

from geomcheck.cache import Store, open_store, using_store

REPO = Path(__file__).resolve().parents[1]


def script(name: str) -> ModuleType:
    """The module of ``scripts/NAME.py``, loaded once."""
    module_name = f"script_{name}"
    if module_name in sys.modules:
        return sys.modules[module_name]
    scripts = str(REPO / "scripts")
    if scripts not in sys.path:
        sys.path.insert(0, scripts)  # precision.py imports corpus_robots beside it
    spec = importlib.util.spec_from_file_location(module_name, REPO / "scripts" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


class CorpusReports:
    """The JSON report of a default check of each robots.toml robot, computed on first use and
    shared by every test of the session: a corpus robot is checked once. The robots named in
    ``kept`` are checked with a stage cache store of their own in ``stores`` (a store only adds
    writes: on a miss a stage returns what it computed), kept for the test that reads their
    report back warm; the others with none."""

    def __init__(self, corpus: Path, stores: Path | None = None, kept: frozenset[str] = frozenset()) -> None:
        self.corpus = corpus
        self.robots = {r.name: r for r in script("corpus_robots").checked_robots(corpus)}
        self._documents: dict[str, dict[str, Any]] = {}
        self._stores = stores
        self._kept = kept
        self._filled: dict[str, Store] = {}

    def __getitem__(self, name: str) -> dict[str, Any]:
        if name not in self._documents:
            store = open_store(self._stores / name) if self._stores is not None and name in self._kept else None
            with using_store(store):
                self._documents[name] = script("precision").report_document(self.robots[name])
            if store is not None:
                self._filled[name] = store
        return self._documents[name]

    def store(self, name: str) -> Store | None:
        """The store the check of ``name`` filled, ``None`` when it was checked without one."""
        self[name]
        return self._filled.get(name)


@contextlib.contextmanager
def ros_packages(packages: Mapping[str, Path]) -> Iterator[None]:
    """The real xacro package's ``$(find NAME)`` answered from ``packages`` (xacro asks
    ament_index_python, which is not installed here)."""
    index = types.ModuleType("ament_index_python.packages")

    def share(name: str) -> str:
        if name not in packages:
            raise LookupError(f"package {name!r} not found")
        return str(packages[name])

    index.get_package_share_directory = share  # type: ignore[attr-defined]
    saved = {name: sys.modules.get(name) for name in ("ament_index_python", "ament_index_python.packages")}
    sys.modules["ament_index_python"] = types.ModuleType("ament_index_python")
    sys.modules["ament_index_python.packages"] = index
    try:
        yield
    finally:
        for name, module in saved.items():
            if module is None:
                sys.modules.pop(name, None)
            else:
                sys.modules[name] = module
