"""The robots of the shared corpus as ``robots.toml`` lists them, for tests that iterate them
(read by ``scripts/corpus_robots.py``, the one reader tests, scripts and benchmarks share).

A robot added to ``robots.toml`` is picked up by every test that iterates
:func:`corpus_robots`, with no code change.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

from geomcheck.load import load_description, make_bundle
from tests.corpustools import script

URDF = "urdf"  # the format of a table without a ``format`` key: URDF, or xacro producing it
CorpusRobot = Any  # scripts/corpus_robots.py CorpusRobot (loaded from the scripts folder)


def corpus_robots(corpus: Path, formats: tuple[str, ...] = (URDF,)) -> Iterator[CorpusRobot]:
    """The robots of ``corpus/robots.toml`` in the file's order, those of ``formats`` only."""
    return (robot for robot in script("corpus_robots").robots(corpus) if robot.format in formats)


def corpus_from_env() -> Path | None:
    """The corpus folder (GEOMCHECK_CORPUS), or ``None``: for parameters chosen at collection."""
    found: Path | None = script("corpus_robots").corpus_from_env()
    return found


def sample(robots: list[CorpusRobot]) -> list[CorpusRobot]:
    """The first robot of each kind (arm, mobile, legged, ...; with and without casters) in
    the file's order: what the default test run checks of a corpus-wide campaign, so that it
    meets every kind of robot; the whole corpus runs with ``pytest -m campaign``."""
    first: dict[tuple[str, bool], CorpusRobot] = {}
    for robot in robots:
        first.setdefault((robot.kind, robot.has_casters), robot)
    return [r for r in robots if first.get((r.kind, r.has_casters)) is r]


def robot_params(formats: tuple[str, ...] = (URDF,), default: Iterable[str] | None = None) -> list[Any]:
    """The names of the corpus's robots of ``formats`` as test parameters (none without a
    corpus): those named in ``default`` (by default the robots of :func:`sample`) run by
    default, the others are marked ``campaign`` (``pytest -m campaign`` runs them)."""
    corpus = corpus_from_env()
    if corpus is None:
        return []
    robots = list(corpus_robots(corpus, formats))
    sampled = set(default) if default is not None else {r.name for r in sample(robots)}
    return [pytest.param(r.name, id=r.name, marks=() if r.name in sampled else (pytest.mark.campaign,)) for r in robots]


def corpus_robot(corpus: Path, name: str) -> CorpusRobot:
    """The robot ``name`` of ``corpus/robots.toml`` (any format)."""
    [robot] = [r for r in script("corpus_robots").robots(corpus) if r.name == name]
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
    "robot_params",
    "sample",
]
