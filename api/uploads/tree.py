"""An upload tree: the folder an untrusted upload is written into, one checked path at a time.

Every path is validated before anything touches the disk: relative, posix separators, no
``..``, no control characters, bounded length and depth. Files are created with
``O_EXCL | O_NOFOLLOW`` inside folders this module made itself, so no entry can overwrite
another, follow a link, or land outside the tree. File count and the total unpacked size
are enforced while data streams in.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from api.errors import UploadError, UploadTooLarge

MAX_DEPTH = 64  # folders in one upload path [levels]
MAX_COMPONENT = 255  # characters of one path component (the usual file-system limit)
_CONTROL = re.compile(r"[\x00-\x1f\x7f]")
_DRIVE = re.compile(r"^[A-Za-z]:")


@dataclass(frozen=True)
class UploadLimits:
    """Limits of one upload: ``max_files`` entries, ``max_unpacked_bytes`` [bytes] in all,
    ``max_ratio`` unpacked / compressed [ratio], ``max_path_length`` [characters]."""

    max_files: int
    max_unpacked_bytes: int
    max_ratio: float
    max_path_length: int


def clean_path(name: str, max_length: int) -> PurePosixPath:
    """``name`` as a safe relative path (``./`` prefixes dropped); :class:`UploadError` naming it otherwise."""
    shown = _CONTROL.sub("?", name)[:200]
    if not name or len(name) > max_length:
        raise UploadError(f"upload path {shown!r} is empty or longer than {max_length} characters")
    if _CONTROL.search(name):
        raise UploadError(f"upload path {shown!r} contains control characters")
    if "\\" in name:
        raise UploadError(f"upload path {shown!r} contains a backslash; use '/' separators")
    if name.startswith("/") or _DRIVE.match(name):
        raise UploadError(f"upload path {shown!r} is absolute; paths must be relative to the package tree")
    parts = [p for p in name.split("/") if p not in ("", ".")]
    if ".." in parts:
        raise UploadError(f"upload path {shown!r} escapes the bundle ('..')")
    if not parts:
        raise UploadError(f"upload path {shown!r} names no file")
    if len(parts) > MAX_DEPTH or any(len(p) > MAX_COMPONENT for p in parts):
        raise UploadError(f"upload path {shown!r} is nested too deep or has an over-long component")
    return PurePosixPath(*parts)


class UploadTree:
    """Writes validated files under ``root`` (created empty), counting entries and bytes."""

    def __init__(self, root: Path, limits: UploadLimits) -> None:
        self.root = root
        self.limits = limits
        root.mkdir(parents=True, exist_ok=False)
        self.entries = 0
        self.unpacked_bytes = 0
        self.files: list[PurePosixPath] = []

    def count_entry(self, name: str) -> None:
        """Count one archive entry (file, folder or refused kind) against ``max_files``."""
        self.entries += 1
        if self.entries > self.limits.max_files:
            raise UploadTooLarge(f"upload has more than {self.limits.max_files} entries")

    def _make_dirs(self, rel: PurePosixPath) -> Path:
        current = self.root
        for part in rel.parts:
            current = current / part
            if current.is_symlink() or (current.exists() and not current.is_dir()):
                raise UploadError(f"upload path {rel.as_posix()!r} runs through a file")
            current.mkdir(exist_ok=True)
        return current

    def add_dir(self, name: str) -> None:
        self._make_dirs(clean_path(name, self.limits.max_path_length))

    def add_file(self, name: str, chunks: Iterable[bytes]) -> PurePosixPath:
        """Write ``chunks`` to the file ``name``; returns its clean relative path."""
        rel = clean_path(name, self.limits.max_path_length)
        folder = self._make_dirs(rel.parent) if rel.parent != PurePosixPath(".") else self.root
        target = folder / rel.name
        flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0)
        try:
            fd = os.open(target, flags, 0o644)
        except FileExistsError:
            raise UploadError(f"upload path {rel.as_posix()!r} occurs twice") from None
        except IsADirectoryError:
            raise UploadError(f"upload path {rel.as_posix()!r} is a folder") from None
        with os.fdopen(fd, "wb") as out:
            for chunk in chunks:
                self.unpacked_bytes += len(chunk)
                if self.unpacked_bytes > self.limits.max_unpacked_bytes:
                    raise UploadTooLarge(
                        f"upload unpacks to more than the limit of {self.limits.max_unpacked_bytes} bytes"
                    )
                out.write(chunk)
        self.files.append(rel)
        return rel
