"""From an unpacked upload tree to the folders a bundle is made of.

Report paths are relative to the *upload root*: the top level of the archive or the form's
file tree. When that top level is itself a ROS package, it is moved into a folder named
after the package (its package.xml ``<name>``; for a legacy manifest.xml package, the one
package name the root file refers to that nothing in the upload provides), so
``$(find pr2_description)`` and ``package://pr2_description/...`` resolve exactly as they
would in a ROS workspace, and the upload root stays the package folder.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from api.errors import UploadError
from api.uploads.roots import (
    MAX_SCANNED_BYTES,
    Candidate,
    RootChoice,
    choose,
    description_candidates,
    root_candidates,
)
from api.uploads.tree import clean_path
from geomcheck.load.bundle import discover_packages, read_package_name

_PACKAGE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_.\-]*")
_REFERENCE = re.compile(rb"\$\(\s*find\s+([A-Za-z][A-Za-z0-9_.\-]*)\s*\)|package://([A-Za-z][A-Za-z0-9_.\-]*)/")


@dataclass(frozen=True)
class Layout:
    """Where a check reads from: ``root_file`` inside ``display_root`` (the upload root),
    packages discovered under ``search_root``, optional ``srdf`` file."""

    display_root: Path
    search_root: Path
    root_file: Path
    root_relative: str
    srdf: Path | None
    root_choice: RootChoice | None = None


def referenced_packages(path: Path) -> set[str]:
    """Package names ``path`` refers to through ``$(find NAME)`` or ``package://NAME/``."""
    with path.open("rb") as fp:
        data = fp.read(MAX_SCANNED_BYTES)
    return {(m.group(1) or m.group(2)).decode() for m in _REFERENCE.finditer(data)}


def is_package(folder: Path) -> bool:
    return (folder / "package.xml").is_file() or (folder / "manifest.xml").is_file()


def top_level_package_name(tree_root: Path, root_file: Path) -> str | None:
    """Name of the package at the top of the upload, when it is one and its name can be known."""
    if (tree_root / "package.xml").is_file():
        name = read_package_name(tree_root)
        if name != tree_root.name and _PACKAGE_NAME.fullmatch(name):
            return name
    provided = set(discover_packages([tree_root])) - {tree_root.name}
    unresolved = referenced_packages(root_file) - provided
    if len(unresolved) == 1:
        return unresolved.pop()
    return None


def choose_root(folder: Path, root: str | None, max_length: int) -> RootChoice:
    """The root file: ``root`` when given (it must exist), else the one the upload's files point
    to (:func:`api.uploads.roots.choose`: the only description, or the one that makes the robot and pulls
    the others in), with why and the alternatives. :class:`UploadError` when the upload holds no
    description, or several robots no signal tells apart (the request must name one)."""
    if root:
        return _named_root(folder, root, max_length)
    candidates = description_candidates(folder)
    if len(candidates) == 1:
        return RootChoice(candidates[0], False, "the only robot description in the upload")
    if not candidates:
        raise _no_description(folder)
    ranked = root_candidates(folder)
    chosen = choose(ranked)
    if chosen is not None:
        return chosen
    raise _undecided(ranked, candidates)


def _shown(names: list[str], most: int, more: str = " ...") -> str:
    """The first ``most`` of ``names``, then ``more`` when there are others."""
    return ", ".join(names[:most]) + (more if len(names) > most else "")


def _named_root(folder: Path, root: str, max_length: int) -> RootChoice:
    """The root the request names, which must be a file of the upload."""
    rel = clean_path(root, max_length).as_posix()
    if not (folder / rel).is_file():
        shown = _shown(description_candidates(folder), 8)
        raise UploadError(f"root file {rel!r} is not in the upload; description files: {shown or 'none'}")
    return RootChoice(rel, True, "named by the request")


def _no_description(folder: Path) -> UploadError:
    """The refusal of an upload without a description, naming a few of its files."""
    files = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())
    shown = _shown(files, 5, f" and {len(files) - 5} more")
    return UploadError(
        "the upload holds no robot description (URDF or xacro .urdf/.xacro, MJCF .xml, SDFormat .sdf): add it "
        f"to it; it holds {len(files)} file{'s' if len(files) != 1 else ''}{': ' + shown if files else ''}"
    )


def _undecided(ranked: list[Candidate], candidates: list[str]) -> UploadError:
    """The refusal of an upload whose likeliest roots nothing tells apart: the request must name one."""
    tied = [c.path for c in ranked if c.signals() == ranked[0].signals()] if ranked else []
    rest = [c.path for c in ranked if c.path not in tied]
    shown = _shown(tied, 8, f" and {len(tied) - 8} more") if ranked else _shown(candidates, 8)
    others = f"; other description files, likely root first: {_shown(rest, 5)}" if rest else ""
    return UploadError(
        f"name the root file with the 'root' parameter: {len(tied) or len(candidates)} files could each be the "
        f"robot, and nothing in the upload says which: {shown or 'none'}{others}"
    )


def arrange(tree_root: Path, root: str | None, srdf: str | None, max_length: int) -> Layout:
    """Decide the root file and package folders of the upload in ``tree_root`` (renaming it if needed)."""
    choice = choose_root(tree_root, root, max_length)
    rel = choice.path
    display_root = tree_root
    search_root = tree_root
    if is_package(tree_root):
        name = top_level_package_name(tree_root, tree_root / rel)
        if name is not None:
            workspace = tree_root.parent / "ws"
            workspace.mkdir()
            display_root = tree_root.rename(workspace / name)
            search_root = workspace
    srdf_path = None
    if srdf:
        srdf_rel = clean_path(srdf, max_length)
        srdf_path = display_root / PurePosixPath(srdf_rel)
        if not srdf_path.is_file():
            raise UploadError(f"SRDF file {srdf_rel.as_posix()!r} is not in the upload")
    return Layout(
        display_root=display_root,
        search_root=search_root,
        root_file=display_root / rel,
        root_relative=rel,
        srdf=srdf_path,
        root_choice=choice,
    )
