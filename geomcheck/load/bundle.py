"""A bundle: the root file of a description plus the ROS packages it may refer to."""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from geomcheck.errors import InputError, SandboxViolation, UsageError


@dataclass(frozen=True)
class Bundle:
    """Root file, package map and file-access policy of one check.

    ``packages`` maps ROS package names to absolute directories. ``display_root`` is the
    directory report paths are relative to. When ``confined`` (uploads), every file the
    loader opens must lie under one of ``allowed_roots``.
    """

    root_file: Path
    packages: Mapping[str, Path] = field(default_factory=dict)
    display_root: Path = field(default_factory=Path.cwd)
    confined: bool = False
    allowed_roots: tuple[Path, ...] = ()

    def display(self, path: str | os.PathLike[str]) -> str:
        """``path`` relative to ``display_root`` with posix separators (absolute if on another drive)."""
        p = Path(path)
        try:
            rel = os.path.relpath(p, self.display_root)
        except ValueError:
            return p.as_posix()
        return Path(rel).as_posix()

    def check_access(self, path: Path) -> Path:
        """``path`` resolved; :class:`SandboxViolation` when confined and outside ``allowed_roots``."""
        resolved = path.resolve()
        if self.confined and not any(resolved.is_relative_to(r) for r in self.allowed_roots):
            raise SandboxViolation(f"access outside the uploaded bundle refused: {path}")
        return resolved

    def package_dir(self, name: str) -> Path | None:
        return self.packages.get(name)


def read_package_name(directory: Path) -> str:
    """Package name of ``directory``: ``<name>`` of its package.xml, else the folder name."""
    manifest = directory / "package.xml"
    if manifest.is_file():
        from geomcheck.load.xmlsafe import parse_bytes

        try:
            root = parse_bytes(manifest.read_bytes(), str(manifest))
        except InputError:
            return directory.name
        name = root.findtext("name")
        if name and name.strip():
            return name.strip()
    return directory.name


def discover_packages(search_roots: Iterable[Path], max_depth: int = 8) -> dict[str, Path]:
    """Every directory under ``search_roots`` (the roots included) holding package.xml or
    manifest.xml, by package name; the first found wins, in sorted walk order."""
    found: dict[str, Path] = {}
    for root in search_roots:
        root = root.resolve()
        if not root.is_dir():
            raise UsageError(f"search path is not a directory: {root}")
        base_depth = len(root.parts)
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames.sort()
            dirnames[:] = [d for d in dirnames if not d.startswith(".")]
            if len(Path(dirpath).parts) - base_depth >= max_depth:
                dirnames[:] = []
            if "package.xml" in filenames or "manifest.xml" in filenames:
                directory = Path(dirpath)
                found.setdefault(read_package_name(directory), directory)
    return found


def make_bundle(
    root_file: str | os.PathLike[str],
    packages: Mapping[str, str | os.PathLike[str]] | None = None,
    search: Iterable[str | os.PathLike[str]] = (),
    display_root: str | os.PathLike[str] | None = None,
    confined: bool = False,
) -> Bundle:
    """Bundle for ``root_file``: explicit ``packages`` win over those discovered under
    ``search``; the package holding the root file (nearest ancestor with a manifest) is
    always known. :class:`InputError` when the root file does not exist."""
    root = Path(root_file)
    if not root.is_file():
        raise InputError(f"no such file: {root}")
    root = root.resolve()
    found = discover_packages([Path(s) for s in search])
    for parent in root.parents:
        if (parent / "package.xml").is_file() or (parent / "manifest.xml").is_file():
            found.setdefault(read_package_name(parent), parent)
            break
    for name, directory in (packages or {}).items():
        path = Path(directory)
        if not path.is_dir():
            raise UsageError(f"package {name}: not a directory: {directory}")
        found[name] = path.resolve()
    disp = Path(display_root).resolve() if display_root is not None else Path.cwd()
    allowed = (disp, *found.values()) if confined else ()
    return Bundle(
        root_file=root,
        packages=dict(sorted(found.items())),
        display_root=disp,
        confined=confined,
        allowed_roots=tuple(p.resolve() for p in allowed),
    )
