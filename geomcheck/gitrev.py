"""A read-only view of a git revision: the files of a commit exported to a temporary folder.

``git archive`` is used rather than a worktree so that the user's repository is never
written to (no ``.git/worktrees`` entry to clean up after an interrupted run). Submodule
contents and files marked ``export-ignore`` in .gitattributes are not exported; Git LFS
files come out as their pointers.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tarfile
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from geomcheck.errors import UsageError

GIT_TIMEOUT_S = 300.0  # one git command [s]


def git(args: Sequence[str], cwd: Path) -> subprocess.CompletedProcess[bytes]:
    """Run ``git args`` in ``cwd``; :class:`UsageError` with git's message when it fails."""
    if shutil.which("git") is None:
        raise UsageError("git is not installed (needed for `geomcheck diff --base`)")
    proc = subprocess.run(
        ["git", *args],
        cwd=cwd,
        capture_output=True,
        timeout=GIT_TIMEOUT_S,
        check=False,
        env={**os.environ, "GIT_TERMINAL_PROMPT": "0", "LC_ALL": "C"},
    )
    if proc.returncode != 0:
        reason = proc.stderr.decode(errors="replace").strip().splitlines()
        raise UsageError(f"git {' '.join(args)} failed in {cwd}: {reason[-1] if reason else proc.returncode}")
    return proc


def repo_root(path: Path) -> Path:
    """The top folder of the git work tree holding ``path``."""
    folder = path if path.is_dir() else path.parent
    out = git(["rev-parse", "--show-toplevel"], folder.resolve())
    return Path(out.stdout.decode().strip()).resolve()


def resolve_commit(root: Path, rev: str) -> str:
    """The full hash of commit ``rev``; a :class:`UsageError` naming ``rev`` when it is unknown
    (in a shallow CI clone, fetch it first)."""
    if rev.startswith("-"):
        raise UsageError(f"invalid revision {rev!r}")
    try:
        out = git(["rev-parse", "--verify", "--quiet", f"{rev}^{{commit}}"], root)
    except UsageError:
        raise UsageError(
            f"unknown git revision {rev!r} in {root} (in a shallow clone, fetch it: git fetch --depth=1 origin {rev})"
        ) from None
    return out.stdout.decode().strip()


@contextmanager
def exported_tree(root: Path, commit: str) -> Iterator[Path]:
    """The files of ``commit`` in a temporary folder, removed on exit."""
    with tempfile.TemporaryDirectory(prefix="geomcheck-base-") as tmp:
        archive = Path(tmp) / "tree.tar"
        target = Path(tmp) / "tree"
        target.mkdir()
        git(["archive", "--format=tar", f"--output={archive}", commit], root)
        with tarfile.open(archive) as tar:
            tar.extractall(target, filter=_inside_only)
        archive.unlink()
        yield target


def _inside_only(member: tarfile.TarInfo, dest: str) -> tarfile.TarInfo | None:
    """The ``data`` extraction filter, skipping (not failing on) members it refuses, such as
    symbolic links to absolute paths or out of the tree."""
    try:
        return tarfile.data_filter(member, dest)
    except tarfile.FilterError:
        return None


def map_into(path: Path, root: Path, tree: Path) -> Path:
    """``path`` in the exported ``tree`` when it lies in the work tree ``root``, else unchanged
    (folders outside the repository are the same for both revisions)."""
    resolved = path.resolve()
    if resolved.is_relative_to(root):
        return tree / resolved.relative_to(root)
    return path
