"""Candidate root files of an upload: the URDF and xacro files holding a ``<robot>`` element,
the one a person means first.

The root of a description pulls the others in: a file another description includes is a
part, not a root; among the rest, the file that includes the most others (directly or
through them) is the whole robot, a sub-assembly test file (the PR2's ``caster.urdf.xacro``)
includes fewer; then a file in a ``robots/`` folder (the ROS convention for roots), a named
``<robot name="...">`` (include files usually leave the name out), the shallower path, and
the alphabetical one. The service takes the first when ``root`` is omitted and it is the
evident one (:func:`evident_root`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

_ROBOT = re.compile(rb"<robot[\s>/]")
_ROBOT_NAME = re.compile(rb"""<robot\b[^>]*?\bname\s*=\s*["']([^"']*)["']""", re.DOTALL)
_INCLUDE = re.compile(rb"""<(?:xacro:)?include\b[^>]*?\bfilename\s*=\s*["']([^"']+)["']""", re.DOTALL)
ROOT_FOLDERS = ("robots", "robot")  # where ROS description packages keep their root files
DESCRIPTION_SUFFIXES = (".urdf", ".xacro")
MAX_SCANNED_BYTES = 4 * 1024 * 1024  # of one file, when looking for package references or includes [bytes]


def description_candidates(folder: Path) -> list[str]:
    """Relative paths of the files under ``folder`` that look like descriptions, sorted."""
    found = [p for p in folder.rglob("*") if p.is_file() and p.name.endswith(DESCRIPTION_SUFFIXES)]
    return sorted(p.relative_to(folder).as_posix() for p in found)


@dataclass(frozen=True)
class Candidate:
    """A file of the upload that holds a ``<robot>``: its path relative to the upload root,
    the robot's ``name`` attribute (None when absent), whether another description includes
    it, and how many description files it pulls in (directly or through them)."""

    path: str
    robot: str | None
    included: bool
    pulls_in: int = 0

    @property
    def in_root_folder(self) -> bool:
        return any(part in ROOT_FOLDERS for part in PurePosixPath(self.path).parts[:-1])

    def rank(self) -> tuple[bool, int, bool, bool, int, str]:
        return (
            self.included,
            -self.pulls_in,
            not self.in_root_folder,
            self.robot is None,
            self.path.count("/"),
            self.path,
        )


def _head(path: Path) -> bytes:
    with path.open("rb") as fp:
        return fp.read(MAX_SCANNED_BYTES)


def _includes(texts: dict[str, bytes]) -> dict[str, set[str]]:
    """Per file, the description files it includes; an include names a file by a path of
    its own (``$(find pkg)/urdf/x.xacro``, ``../x.xacro``): its base name is enough."""
    by_name: dict[str, set[str]] = {}
    for rel in texts:
        by_name.setdefault(PurePosixPath(rel).name, set()).add(rel)
    return {
        rel: {
            other
            for m in _INCLUDE.finditer(text)
            for other in by_name.get(PurePosixPath(m.group(1).decode(errors="replace")).name, ())
            if other != rel
        }
        for rel, text in texts.items()
    }


def _reachable(start: str, includes: dict[str, set[str]]) -> set[str]:
    seen: set[str] = set()
    todo = list(includes.get(start, ()))
    while todo:
        rel = todo.pop()
        if rel not in seen:
            seen.add(rel)
            todo.extend(includes.get(rel, ()))
    seen.discard(start)
    return seen


def root_candidates(folder: Path) -> list[Candidate]:
    """The candidate root files under ``folder``, the likely root first."""
    texts = {rel: _head(folder / rel) for rel in description_candidates(folder)}
    includes = _includes(texts)
    included = {other for others in includes.values() for other in others}
    found = []
    for rel, text in texts.items():
        if not _ROBOT.search(text):
            continue
        named = _ROBOT_NAME.search(text)
        robot = named.group(1).decode(errors="replace") if named else None
        found.append(Candidate(rel, robot, rel in included, len(_reachable(rel, includes))))
    return sorted(found, key=Candidate.rank)


def evident_root(candidates: list[Candidate]) -> Candidate | None:
    """The root a person means, when one is evident: the only candidate, or the only one no
    other includes, or the one that pulls in strictly more files than any other."""
    if len(candidates) == 1:
        return candidates[0]
    roots = [c for c in candidates if not c.included]
    if len(roots) == 1:
        return roots[0]
    if len(roots) >= 2 and roots[0].pulls_in > roots[1].pulls_in:
        return roots[0]
    return None
