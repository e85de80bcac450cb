"""Applying edits to source text, writing the files, and the unified diff of the change."""

from __future__ import annotations

import difflib
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from geomcheck.errors import InputError
from geomcheck.fix.model import Edit
from geomcheck.load import Bundle


def apply_edits(text: str, edits: Iterable[Edit]) -> str:
    """``text`` with ``edits`` (of one file, not overlapping) made; every other character kept."""
    out = text
    for edit in sorted(edits, key=lambda e: (e.start, e.end), reverse=True):
        out = out[: edit.start] + edit.replacement + out[edit.end :]
    return out


def fixed_sources(sources: Mapping[str, str], edits: Iterable[Edit]) -> dict[str, str]:
    """The new text of every file ``edits`` change, by display path."""
    per_file: dict[str, list[Edit]] = {}
    for edit in edits:
        per_file.setdefault(edit.file, []).append(edit)
    out = {}
    for file, file_edits in per_file.items():
        new = apply_edits(sources[file], file_edits)
        if new != sources[file]:
            out[file] = new
    return out


def unified_diff(before: Mapping[str, str], after: Mapping[str, str]) -> str:
    """A ``git apply``-able unified diff (``a/``, ``b/`` prefixes) from ``before`` to ``after`` (display paths)."""
    chunks = []
    for file in sorted(after):
        lines = difflib.unified_diff(
            before[file].splitlines(keepends=True),
            after[file].splitlines(keepends=True),
            fromfile=f"a/{file}",
            tofile=f"b/{file}",
        )
        for line in lines:
            chunks.append(line if line.endswith("\n") else line + "\n\\ No newline at end of file\n")
    return "".join(chunks)


def source_path(bundle: Bundle, display: str) -> Path:
    """The file behind display path ``display``, checked against the bundle's sandbox."""
    return bundle.check_access(Path(os.path.normpath(bundle.display_root / display)))


def write_sources(bundle: Bundle, before: Mapping[str, str], after: Mapping[str, str]) -> list[Path]:
    """Write each changed file; refuses (:class:`InputError`) a file that changed on disk since it was read."""
    paths = {file: source_path(bundle, file) for file in after}
    for file, path in paths.items():
        if path.read_bytes().decode("utf-8", errors="replace") != before[file]:
            raise InputError(f"{file} changed on disk since it was checked; run the fix again")
    for file, path in paths.items():
        path.write_bytes(after[file].encode("utf-8"))
    return sorted(paths.values())
