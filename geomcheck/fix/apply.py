"""Applying edits to source text, writing the files, and the unified diff of the change."""

from __future__ import annotations

import difflib
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from geomcheck.errors import InputError
from geomcheck.fix.model import Edit
from geomcheck.load import Bundle

DIFF_CONTEXT = 3  # lines of context around each change, as diff -u


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


def unified_diff(before: Mapping[str, str], after: Mapping[str, str], context: int = DIFF_CONTEXT) -> str:
    """A ``git apply``-able unified diff (``a/``, ``b/`` prefixes) from ``before`` to ``after`` (display paths).

    Lines are matched without difflib's "popular line" heuristic, which in long files pairs
    repeated lines such as ``<geometry>`` wrongly and shows them as changed."""
    out = []
    for file in sorted(after):
        old, new = before[file].splitlines(keepends=True), after[file].splitlines(keepends=True)
        groups = list(difflib.SequenceMatcher(None, old, new, autojunk=False).get_grouped_opcodes(context))
        if not groups:
            continue
        out.extend([f"--- a/{file}\n", f"+++ b/{file}\n"])
        for group in groups:
            (_, i1, _, j1, _), (_, _, i2, _, j2) = group[0], group[-1]
            out.append(f"@@ -{_range(i1, i2)} +{_range(j1, j2)} @@\n")
            for tag, a1, a2, b1, b2 in group:
                if tag == "equal":
                    out.extend(_lines(" ", old[a1:a2]))
                    continue
                out.extend(_lines("-", old[a1:a2]))
                out.extend(_lines("+", new[b1:b2]))
    return "".join(out)


def _range(start: int, stop: int) -> str:
    """``start,count`` of a hunk, 1-based (``start`` is the line before an empty range)."""
    count = stop - start
    return f"{start + 1 if count else start},{count}" if count != 1 else f"{start + 1}"


def _lines(prefix: str, lines: list[str]) -> list[str]:
    return [
        prefix + line if line.endswith("\n") else f"{prefix}{line}\n\\ No newline at end of file\n" for line in lines
    ]


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
