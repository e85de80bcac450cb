"""Which files a candidate root reads, in its default configuration, that the upload lacks.

A person uploads the files of the robot they want checked. When one robot of a package reads
meshes the package's own folders hold and another reads meshes of the same package that are not
there (a tree trimmed to the arm, whose full-robot xacro still names the body's meshes), the
upload is the first robot's.

Nothing runs xacro here, so what a robot reads is what it reads whatever its arguments: the
references outside every ``xacro:if`` and ``xacro:unless`` (an accessory switched on by an
environment variable is not read by default), in the files it includes outside them, and in
the macros it calls outside them, through the macros those call. Only literal references
count: ``package://NAME/path`` and ``$(find NAME)/path`` to a package the upload itself
provides, without a substitution left in the path. A package the upload does not hold is
another matter (a dependency the check reports), and a path built from arguments cannot be
known without running xacro.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from lxml import etree

from api.uploads.xml_elements import is_xacro, local_name
from geomcheck.load.bundle import discover_packages

_FILE_REFERENCE = re.compile(r"(?:package://([A-Za-z][\w.\-]*)|\$\(\s*find\s+([A-Za-z][\w.\-]*)\s*\))/(\S+)")
_SUBSTITUTED = re.compile(r"\$[({]")
_FIND_PREFIX = re.compile(r"^\$\(\s*find\s+[A-Za-z][\w.\-]*\s*\)/")
_CONDITIONS = frozenset({"if", "unless"})
_DEFINITIONS = frozenset({"property", "arg", "insert_block", "element", "attribute"})


@dataclass
class Reads:
    """What one scope (a file's top level or a macro's body) reads outside every condition:
    file references, macros called and files included (by base name)."""

    references: set[str] = field(default_factory=set)
    calls: set[str] = field(default_factory=set)
    includes: set[str] = field(default_factory=set)


@dataclass
class FileReads:
    top: Reads = field(default_factory=Reads)
    macros: dict[str, Reads] = field(default_factory=dict)


def _collect(element: etree._Element, scope: Reads, reads: FileReads) -> None:
    for child in element:
        if not isinstance(child.tag, str):
            continue
        name = local_name(child) if is_xacro(child) else None
        if name in _CONDITIONS or name in _DEFINITIONS:
            continue
        if name == "macro":
            body = reads.macros.setdefault(child.get("name", ""), Reads())
            _collect(child, body, reads)
            continue
        if name == "include":
            included = _FIND_PREFIX.sub("", child.get("filename", ""))
            if included and not _SUBSTITUTED.search(included):
                scope.includes.add(PurePosixPath(included).name)
            continue
        if name is not None:
            scope.calls.add(child.get("macro", "") if name == "call" else name)
        values = [*child.attrib.values(), child.text or ""]
        scope.references.update(m.group(0) for v in values for m in _FILE_REFERENCE.finditer(v))
        _collect(child, scope, reads)


def file_reads(root: etree._Element | None) -> FileReads:
    """What a parsed description (``None``: one that could not be parsed) reads, per scope."""
    reads = FileReads()
    if root is not None:
        scope = reads.top
        scope.references.update(m.group(0) for v in root.attrib.values() for m in _FILE_REFERENCE.finditer(v))
        _collect(root, scope, reads)
    return reads


def default_references(start: str, reads: dict[str, FileReads]) -> set[str]:
    """The file references the description ``start`` reads whatever its arguments: a fixed
    point over the files it includes and the macros it calls, wherever they are defined."""
    by_name: dict[str, set[str]] = {}
    for rel in reads:
        by_name.setdefault(PurePosixPath(rel).name, set()).add(rel)
    files: set[str] = {start}
    called: set[str] = set()
    while True:
        macros: dict[str, Reads] = {}
        for rel in sorted(files):
            for name, body in reads[rel].macros.items():
                macros.setdefault(name, body)
        scopes = [reads[rel].top for rel in sorted(files)] + [macros[name] for name in sorted(called)]
        calls = {name for scope in scopes for name in scope.calls} & macros.keys()
        more = {rel for scope in scopes for name in scope.includes for rel in by_name.get(name, ())}
        if calls <= called and more <= files:
            return {reference for scope in scopes for reference in scope.references}
        files |= more
        called |= calls


def missing_files(folder: Path, trees: dict[str, etree._Element | None], starts: list[str]) -> dict[str, list[str]]:
    """Per description of ``starts`` (paths relative to ``folder``; ``trees`` holds every
    description file parsed), the files of the upload's own packages it reads by default that
    the upload does not hold, as written, sorted."""
    packages = {name: path.resolve() for name, path in discover_packages([folder]).items()}
    top = folder.resolve()
    reads = {rel: file_reads(root) for rel, root in trees.items()}
    out: dict[str, list[str]] = {}
    for rel in starts:
        absent = []
        for reference in default_references(rel, reads):
            match = _FILE_REFERENCE.fullmatch(reference)
            if match is None:
                continue
            name, tail = match.group(1) or match.group(2), match.group(3)
            if name not in packages or _SUBSTITUTED.search(tail):
                continue
            target = Path(os.path.normpath(packages[name] / tail))
            if target.is_relative_to(top) and not target.is_file():
                absent.append(reference)
        out[rel] = sorted(absent)
    return out
