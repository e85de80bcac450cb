"""The robots of the shared corpus as ``robots.toml`` lists them, for tests that iterate them.

``robots.toml`` (in the folder GEOMCHECK_CORPUS names) holds one table per robot: its root
file, packages, xacro args and SRDF (paths relative to the corpus folder), its kind, whether it
has casters, and its format (absent: URDF or xacro). A robot added there is picked up by every
test that iterates :func:`corpus_robots`, with no code change.
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from geomcheck.load import load_description, make_bundle

URDF = "urdf"  # the format of a table without a ``format`` key: URDF, or xacro producing it
CORPUS_ENV = "GEOMCHECK_CORPUS"  # as tests/conftest.py reads it


@dataclass(frozen=True)
class CorpusRobot:
    """One table of ``robots.toml``, paths resolved against the corpus folder."""

    name: str
    root: Path
    packages: Mapping[str, Path] = field(default_factory=dict)
    args: Mapping[str, str] = field(default_factory=dict)
    srdf: Path | None = None
    kind: str = ""
    has_casters: bool = False
    format: str = URDF

    def __iter__(self) -> Iterator[object]:
        """(name, root, packages, args, srdf, kind, has_casters, format), for unpacking."""
        yield from (self.name, self.root, self.packages, self.args, self.srdf, self.kind, self.has_casters)
        yield self.format


def corpus_robots(corpus: Path, formats: tuple[str, ...] = (URDF,)) -> Iterator[CorpusRobot]:
    """The robots of ``corpus/robots.toml`` in the file's order, those of ``formats`` only."""
    tables = tomllib.loads((corpus / "robots.toml").read_text(encoding="utf-8"))
    for name, table in tables.items():
        robot = CorpusRobot(
            name=name,
            root=corpus / table["root"],
            packages={package: corpus / folder for package, folder in table.get("packages", {}).items()},
            args={key: str(value) for key, value in table.get("args", {}).items()},
            srdf=corpus / table["srdf"] if table.get("srdf") else None,
            kind=table.get("kind", ""),
            has_casters=bool(table.get("has_casters", False)),
            format=table.get("format", URDF),
        )
        if robot.format in formats:
            yield robot


def corpus_from_env() -> Path | None:
    """The corpus folder GEOMCHECK_CORPUS names, or ``None`` (for parameters chosen at collection)."""
    value = os.environ.get(CORPUS_ENV)
    path = Path(value).resolve() if value else None
    return path if path is not None and (path / "robots.toml").is_file() else None


def robot_names(formats: tuple[str, ...] = (URDF,)) -> list[str]:
    """The names of the corpus's robots of ``formats`` (none without a corpus): test parameters."""
    corpus = corpus_from_env()
    return [] if corpus is None else [r.name for r in corpus_robots(corpus, formats)]


def corpus_robot(corpus: Path, name: str) -> CorpusRobot:
    """The robot ``name`` of ``corpus/robots.toml`` (any format)."""
    [robot] = [r for r in corpus_robots(corpus, formats=(URDF, "mjcf", "sdf")) if r.name == name]
    return robot


def expanded_urdf(robot: CorpusRobot) -> bytes:
    """The robot's URDF (xacro expanded with its args), mesh filenames relative to its root
    file made absolute: a copy written in another folder reads the same meshes."""
    loaded = load_description(make_bundle(robot.root, packages=robot.packages), robot.args)
    root = etree.fromstring(loaded.document.text.encode("utf-8"), etree.XMLParser(remove_comments=True))
    folder = robot.root.resolve().parent
    for mesh in root.iter("mesh"):
        name = (mesh.get("filename") or "").strip()
        if name and "://" not in name and not Path(name).is_absolute():
            mesh.set("filename", str(folder / name))
    return bytes(etree.tostring(root, xml_declaration=True, encoding="utf-8"))


__all__ = [
    "URDF",
    "CorpusRobot",
    "corpus_from_env",
    "corpus_robot",
    "corpus_robots",
    "expanded_urdf",
    "robot_names",
]
