"""Applying edits to source text, writing the files, and the unified diff of the change."""

from __future__ import annotations

import difflib
import os
import stat
from collections.abc import Iterable, Mapping
from pathlib import Path

from geomcheck.errors import InputError
from geomcheck.fixes.model import Edit
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
        old, new = patch_lines(before[file]), patch_lines(after[file])
        groups = list(difflib.SequenceMatcher(None, old, new, autojunk=False).get_grouped_opcodes(context))
        if not groups:
            continue
        out.extend([f"--- {patch_name('a/' + file)}\n", f"+++ {patch_name('b/' + file)}\n"])
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


def patch_lines(text: str) -> list[str]:
    """``text`` cut into lines as ``patch`` and ``git apply`` cut them: at ``\\n`` only (a CR,
    U+2028 or NEL inside a line stays in it; ``str.splitlines`` would cut there and the hunk
    would no longer match the file)."""
    parts = text.split("\n")
    lines = [part + "\n" for part in parts[:-1]]
    if parts[-1]:
        lines.append(parts[-1])
    return lines


_QUOTED = {'"': '\\"', "\\": "\\\\", "\t": "\\t", "\n": "\\n", "\r": "\\r"}


def patch_name(name: str) -> str:
    """A file name on a ``---``/``+++`` line as git writes it: C-quoted when it holds a quote,
    backslash or control character, followed by a tab when it holds a space (GNU ``patch``
    otherwise ends the name at the first space)."""
    if any(c in _QUOTED or ord(c) < 0x20 or ord(c) == 0x7F for c in name):
        quoted = "".join(_QUOTED.get(c) or (f"\\{ord(c):03o}" if ord(c) < 0x20 or ord(c) == 0x7F else c) for c in name)
        return f'"{quoted}"'
    return f"{name}\t" if " " in name else name


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


def fix_tree(bundle: Bundle) -> Path:
    """The folder fixes may write in: the current folder when the root file lies inside it (a
    repository checked from its top), else the package holding the root file, else its folder.
    Resolved: a description reached through a link is written where it really is."""
    root = bundle.root_file.resolve()
    here = bundle.display_root.resolve()
    if root.is_relative_to(here):
        return here
    for folder in root.parents:
        if (folder / "package.xml").is_file() or (folder / "manifest.xml").is_file():
            return folder
    return root.parent


def writable_path(bundle: Bundle, display: str, tree: Path) -> Path:
    """The file behind display path ``display`` when a fix may write it: inside ``tree`` by its
    own path (``..`` resolved as text), with no symbolic link between ``tree`` and the file,
    and inside the bundle's sandbox; :class:`InputError` otherwise (an include such as
    ``../../other/robot.xacro`` or a link to a file elsewhere is read, never written)."""
    path = Path(os.path.normpath(bundle.display_root.resolve() / display))
    if not path.is_relative_to(tree):
        raise InputError(f"{display} is outside the checked folder: fixes write only inside it")
    refuse_links(tree, path, display)
    return bundle.check_access(path)


def writable(bundle: Bundle, display: str) -> bool:
    """Whether a fix may write the file behind display path ``display`` (:func:`writable_path`)."""
    try:
        writable_path(bundle, display, fix_tree(bundle))
    except InputError:
        return False
    return True


def refuse_links(tree: Path, path: Path, display: str) -> None:
    """:class:`InputError` when a folder or file between ``tree`` and ``path`` is a symbolic link."""
    current = tree
    for part in path.relative_to(tree).parts:
        current = current / part
        if current.is_symlink():
            raise InputError(f"{display} is reached through a symbolic link: fixes never write through one")


def write_regular(path: Path, data: bytes, display: str) -> None:
    """Write ``data`` over the regular file ``path``, never following a link put there since
    it was checked (``O_NOFOLLOW``) and never into a FIFO or device."""
    flags = os.O_WRONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as err:
        raise InputError(f"cannot write {display}: {err.strerror}") from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise InputError(f"{display} is not a regular file: fixes write only regular files")
        os.ftruncate(fd, 0)
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view) :]
    finally:
        os.close(fd)


def write_sources(bundle: Bundle, before: Mapping[str, str], after: Mapping[str, str]) -> list[Path]:
    """Write each changed file; refuses (:class:`InputError`, nothing written) a file outside
    :func:`fix_tree`, one reached through a symbolic link, and one that changed on disk since
    it was read."""
    tree = fix_tree(bundle)
    paths = {file: writable_path(bundle, file, tree) for file in after}
    for file, path in paths.items():
        if path.read_bytes().decode("utf-8", errors="replace") != before[file]:
            raise InputError(f"{file} changed on disk since it was checked; run the fix again")
    for file, path in paths.items():
        write_regular(path, after[file].encode("utf-8"), file)
    return sorted(paths.values())
