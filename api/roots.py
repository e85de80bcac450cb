"""Candidate root files of an upload: the files whose root element is a description's
(``<robot>`` URDF and xacro, ``<mujoco>`` MJCF, ``<sdf>`` SDFormat), the one a person means first.

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
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

# the first element after the prolog (declaration, comments, processing instructions, doctype)
_PROLOG = re.compile(rb"\A(?:\s+|<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^>]*>)*", re.DOTALL)
_FIRST_TAG = re.compile(rb"<(?:[\w.-]+:)?([\w.-]+)")
ROOT_TAGS = (b"robot", b"mujoco", b"sdf")  # URDF and xacro, MJCF, SDFormat
# the name a description gives its robot: <robot name>, <mujoco model>, SDFormat's <model name>
_ROBOT_NAME = re.compile(rb"""<(?:robot|mujoco|model)\b[^>]*?\b(?:name|model)\s*=\s*["']([^"']*)["']""", re.DOTALL)
# includes by file (xacro filename=, MJCF file=) and SDFormat's model:// folder
_INCLUDE = re.compile(rb"""<(?:xacro:)?include\b[^>]*?\b(?:file|filename)\s*=\s*["']([^"']+)["']""", re.DOTALL)
_MODEL_URI = re.compile(rb"<uri>\s*model://([^/<\s]+)")
ROOT_FOLDERS = ("robots", "robot")  # where ROS description packages keep their root files
DESCRIPTION_SUFFIXES = (".urdf", ".xacro", ".sdf", ".xml")  # .xml: MJCF, SDFormat and URDF alike
MAX_SCANNED_BYTES = 4 * 1024 * 1024  # of one file, when looking for package references or includes [bytes]
PROLOG_BYTES = 64 * 1024  # read of an .xml file to find its root element (licence comments come first) [bytes]


def root_tag(head: bytes) -> bytes | None:
    """Local name of the first element of an XML text's head, ``None`` when there is none."""
    found = _FIRST_TAG.match(head, _PROLOG.match(head).end())  # type: ignore[union-attr]
    return found.group(1) if found else None


def description_candidates(folder: Path) -> list[str]:
    """Relative paths of the files under ``folder`` that may be descriptions, sorted: URDF,
    xacro and SDFormat files by suffix, ``.xml`` files only when their root element is a
    description's (``package.xml`` and launch files are not)."""
    found = []
    for path in folder.rglob("*"):
        if not path.is_file() or not path.name.lower().endswith(DESCRIPTION_SUFFIXES):
            continue
        if path.name.lower().endswith(".xml") and root_tag(_head(path, PROLOG_BYTES)) not in ROOT_TAGS:
            continue
        found.append(path.relative_to(folder).as_posix())
    return sorted(found)


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


def _head(path: Path, size: int = MAX_SCANNED_BYTES) -> bytes:
    with path.open("rb") as fp:
        return fp.read(size)


def _includes(texts: dict[str, bytes]) -> dict[str, set[str]]:
    """Per file, the description files it includes; an include names a file by a path of
    its own (``$(find pkg)/urdf/x.xacro``, ``../x.xacro``): its base name is enough. An
    SDFormat ``model://NAME`` names a folder: every description under a folder NAME."""
    by_name: dict[str, set[str]] = {}
    by_folder: dict[str, set[str]] = {}
    for rel in texts:
        path = PurePosixPath(rel)
        by_name.setdefault(path.name, set()).add(rel)
        for folder in path.parts[:-1]:
            by_folder.setdefault(folder, set()).add(rel)

    def found(pattern: re.Pattern[bytes], text: bytes, files: Callable[[str], set[str]]) -> set[str]:
        return {f for m in pattern.finditer(text) for f in files(m.group(1).decode(errors="replace"))}

    def by_base_name(path: str) -> set[str]:
        return by_name.get(PurePosixPath(path).name, set())

    def in_folder(name: str) -> set[str]:
        return by_folder.get(name, set())

    return {
        rel: (found(_INCLUDE, text, by_base_name) | found(_MODEL_URI, text, in_folder)) - {rel}
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
        if root_tag(text[:PROLOG_BYTES]) not in ROOT_TAGS and not (rel.endswith(".xacro") and b"<robot" in text):
            continue  # a xacro may open with macros before its <robot>; others must start with one
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
