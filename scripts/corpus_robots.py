"""The robots of the shared corpus, as ``robots.toml`` lists them.

``../shared/corpus/robots.toml`` has one table per robot configuration: its root file,
packages, xacro arguments, kind, whether it has casters, its SRDF and its format (every path
relative to the corpus folder). Tests, scripts and benchmarks iterate over :func:`robots`, so a
robot added there needs no code change. The corpus is ``$GEOMCHECK_CORPUS`` (what ``.ci/run``
sets) or ``../shared/corpus`` beside the repository.
"""

from __future__ import annotations

import json
import os
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
MANIFEST = "robots.toml"
CHECKED_FORMATS = (
    "urdf",
    "mjcf",
    "sdf",
)  # the formats whose corpus robots the golden reports and the precision ledger cover


@dataclass(frozen=True)
class CorpusRobot:
    """One table of ``robots.toml``: ``name`` is the table's name; paths are absolute."""

    name: str
    root: Path
    corpus: Path
    packages: Mapping[str, Path] = field(default_factory=dict)
    args: Mapping[str, str] = field(default_factory=dict)
    srdf: Path | None = None
    kind: str = ""
    has_casters: bool = False
    format: str = "urdf"

    @property
    def checked(self) -> bool:
        """Whether geomcheck loads this robot's format."""
        return self.format in CHECKED_FORMATS


def corpus_dir() -> Path | None:
    """The corpus folder, or ``None`` when there is none (tests skip, scripts say so)."""
    value = os.environ.get("GEOMCHECK_CORPUS")
    path = Path(value) if value else REPO.parent / "shared" / "corpus"
    return path.resolve() if (path / MANIFEST).is_file() else None


def corpus_from_env() -> Path | None:
    """The corpus folder ``$GEOMCHECK_CORPUS`` names (no fallback: tests run on the corpus
    only when told to), or ``None``."""
    value = os.environ.get("GEOMCHECK_CORPUS")
    path = Path(value).resolve() if value else None
    return path if path is not None and (path / MANIFEST).is_file() else None


def robots(corpus: Path) -> list[CorpusRobot]:
    """Every robot of ``corpus/robots.toml``, in the file's order."""
    with (corpus / MANIFEST).open("rb") as handle:
        tables = tomllib.load(handle)
    return [robot(corpus, name, table) for name, table in tables.items()]


def robot(corpus: Path, name: str, table: Mapping[str, object]) -> CorpusRobot:
    packages = table.get("packages") or {}
    args = table.get("args") or {}
    srdf = table.get("srdf")
    assert isinstance(packages, Mapping) and isinstance(args, Mapping), name
    return CorpusRobot(
        name=name,
        root=corpus / str(table["root"]),
        corpus=corpus,
        packages={str(k): corpus / str(v) for k, v in packages.items()},
        args={str(k): str(v) for k, v in args.items()},
        srdf=corpus / str(srdf) if srdf else None,
        kind=str(table.get("kind", "")),
        has_casters=bool(table.get("has_casters", False)),
        format=str(table.get("format", "urdf")),
    )


def check_document(
    root: Path,
    packages: Mapping[str, Path],
    display_root: Path,
    args: Mapping[str, str],
    srdf: Path | None,
    search: tuple[Path, ...] = (),
) -> dict[str, Any]:
    """The JSON report (parsed) of a default check of ``root``: what the golden, precision
    and corpus tests compare."""
    from geomcheck.load import make_bundle
    from geomcheck.options import CheckOptions
    from geomcheck.pipeline import run_check
    from geomcheck.report import json_format

    bundle = make_bundle(root, packages, search, display_root=display_root)
    report = run_check(bundle, CheckOptions(args=dict(args), srdf=srdf))
    document: dict[str, Any] = json.loads(json_format.render(report))
    return document


def checked_robots(corpus: Path) -> list[CorpusRobot]:
    """The robots whose format geomcheck loads."""
    return [r for r in robots(corpus) if r.checked]
