"""Candidate root files of an upload: the URDF and xacro files holding a ``<robot>`` element,
the likely root first.

A file other descriptions include is a part, not a root; a named ``<robot name="...">`` is
a whole robot more often than an unnamed one (xacro include files usually leave the name
out); among equals the shallower path wins, then the alphabetical one.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from api.layout import MAX_SCANNED_BYTES, description_candidates

_ROBOT = re.compile(rb"<robot[\s>/]")
_ROBOT_NAME = re.compile(rb"""<robot\b[^>]*?\bname\s*=\s*["']([^"']*)["']""", re.DOTALL)
_INCLUDE = re.compile(rb"""<(?:xacro:)?include\b[^>]*?\bfilename\s*=\s*["']([^"']+)["']""", re.DOTALL)


@dataclass(frozen=True)
class Candidate:
    """A file of the upload that holds a ``<robot>``: its path relative to the upload root,
    the robot's ``name`` attribute (None when absent), whether another candidate includes it."""

    path: str
    robot: str | None
    included: bool


def _head(path: Path) -> bytes:
    with path.open("rb") as fp:
        return fp.read(MAX_SCANNED_BYTES)


def root_candidates(folder: Path) -> list[Candidate]:
    """The candidate root files under ``folder``, likely root first."""
    texts = {rel: _head(folder / rel) for rel in description_candidates(folder)}
    texts = {rel: text for rel, text in texts.items() if _ROBOT.search(text)}
    # an include names a file by a path of its own ($(find pkg)/urdf/x.xacro, ../x.xacro): its base name is enough
    included = {
        PurePosixPath(m.group(1).decode(errors="replace")).name
        for rel, text in texts.items()
        for m in _INCLUDE.finditer(text)
    }
    found = []
    for rel, text in texts.items():
        named = _ROBOT_NAME.search(text)
        robot = named.group(1).decode(errors="replace") if named else None
        found.append(Candidate(rel, robot, PurePosixPath(rel).name in included))
    return sorted(found, key=lambda c: (c.included, c.robot is None, _depth(c.path), c.path))


def _depth(path: str) -> int:
    return path.count("/")
