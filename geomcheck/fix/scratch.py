"""The scratch copy fixes are verified in: the description's folder copied under a temporary
folder, with a bundle that reads the copy; only a folder small enough is copied."""

from __future__ import annotations

import os
import shutil
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

from geomcheck.load import Bundle, LoadedDescription
from geomcheck.model import Mesh
from geomcheck.options import CheckOptions
from geomcheck.patch.apply import refuse_links, write_regular

MAX_SCRATCH_FILES = 20_000  # a description folder larger than this is not copied [files]
MAX_SCRATCH_BYTES = 1 << 30  # ... nor one larger than this [bytes]


def description_folder(loaded: LoadedDescription, srdf: Path | None) -> Path:
    """The folder a scratch copy needs: the root file, every source file (what fixes write), the
    SRDF and the folder of every mesh named relative to the root file. Meshes named by an
    absolute path, or in a package that holds no source file, are read where they are: the
    copy's bundle keeps packages outside the folder in place (a robot whose meshes lie in
    another package, far off in a workspace, is verified all the same)."""
    bundle = loaded.bundle
    places = [bundle.root_file.parent, *([srdf.absolute().parent] if srdf is not None else [])]
    places += [Path(os.path.normpath(bundle.display_root / f)) for f in loaded.document.sources]
    for link in loaded.robot.links:
        for shape in (*link.visuals, *link.collisions):
            if not isinstance(shape.geometry, Mesh):
                continue
            filename = shape.geometry.filename
            if "://" in filename and not filename.startswith("file://"):
                continue  # package://: found through the package map, in place when outside the folder
            path = Path(filename.removeprefix("file://"))
            if not path.is_absolute():  # relative to the root file: the copy must hold it where it is
                places.append(Path(os.path.normpath(bundle.root_file.parent / path)).parent)
    return Path(os.path.commonpath([str(p) for p in places]))


def small_enough(folder: Path) -> bool:
    files, size = 0, 0
    for _, _, names in os.walk(folder):
        files += len(names)
        if files > MAX_SCRATCH_FILES:
            return False
    for path in folder.rglob("*"):
        if path.is_file() and not path.is_symlink():
            size += path.stat().st_size
            if size > MAX_SCRATCH_BYTES:
                return False
    return True


class Scratch:
    """A copy of the description's folder under ``tmp`` (the folder keeps its name: packages
    found by folder name still are) and a bundle reading it, with maps between the two."""

    def __init__(self, bundle: Bundle, folder: Path, tmp: Path) -> None:
        self.original, self.folder = bundle, folder
        self.copy = tmp / folder.name
        shutil.copytree(folder, self.copy, symlinks=True)
        display_root = self.inside(bundle.display_root) if bundle.display_root.is_relative_to(folder) else self.copy
        self.bundle = Bundle(
            root_file=self.inside(bundle.root_file),
            packages={n: self.inside(d) if d.is_relative_to(folder) else d for n, d in bundle.packages.items()},
            display_root=display_root,
            confined=bundle.confined,
            allowed_roots=tuple(self.inside(r) if r.is_relative_to(folder) else r for r in bundle.allowed_roots),
            search_roots=tuple(self.inside(r) if r.is_relative_to(folder) else r for r in bundle.search_roots),
            allowed_env=bundle.allowed_env,
            env=bundle.env,
            uploaded=bundle.uploaded,
        )

    def inside(self, path: Path) -> Path:
        return self.copy / path.relative_to(self.folder)

    def options(self, options: CheckOptions) -> CheckOptions:
        """``options`` reading the copy's SRDF."""
        srdf = options.srdf.absolute() if options.srdf is not None else None
        return (
            replace(options, srdf=self.inside(srdf))
            if srdf is not None and srdf.is_relative_to(self.folder)
            else options
        )

    def original_display(self, display: str) -> str:
        """The original bundle's display path of the copy's display path ``display``."""
        copied = Path(os.path.normpath(self.bundle.display_root / display))
        return self.original.display(self.folder / copied.relative_to(self.copy))

    def copied_path(self, display: str) -> Path:
        """The copy of the file the original bundle shows as ``display``."""
        return self.inside(Path(os.path.normpath(self.original.display_root / display)))

    def write(self, texts: Mapping[str, str]) -> None:
        """Write the fixed texts (by the original's display path) into the copy; the copy keeps
        the description's symbolic links (they may point anywhere), so nothing is written through one."""
        for display, text in texts.items():
            path = self.copied_path(display)
            refuse_links(self.copy, path, display)
            write_regular(path, text.encode("utf-8"), display)

    def read(self, display: str) -> str:
        return self.copied_path(display).read_bytes().decode("utf-8", errors="replace")
