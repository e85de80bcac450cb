"""The whole check's cache: a ``geomcheck check`` of a description nobody edited reads its
report back instead of checking again.

What a check reads is only known once it ran, so lookups go in two steps, as the xacro
expansion's cache (:mod:`geomcheck.load.xacro_cache`) and ccache's manifests do. The
*context* (geomcheck's code, the libraries' versions, the bundle and the effective options)
keys a short list of *variants*: what one earlier check read, seen while it ran through
Python's audit hooks (PEP 578):

* every file it opened for reading, with its sha256 as it was when first opened (the files
  MuJoCo compiles included: geomcheck reads them for it, :mod:`geomcheck.load.mjcf_assets`),
  wherever it lies: a file of the description's own folders (the root file's, the packages',
  the search folders) or one a loader looked at is the description's even under the Python
  environment's prefix (a description package installed with pip or conda); elsewhere there,
  and in geomcheck's code and cache, reads are the interpreter's and libraries' own;
* every other path a loader looked at (the ``geomcheck.probe`` event) as what is there: a
  file of some size, a folder, or nothing; its bytes were not read, so they are not hashed
  (a file planted beside a description costs no more than a stat);
* every folder it listed, with the names in it;
* every environment variable its expansion read (``$(env)``, ``$(optenv)``: the
  ``geomcheck.env`` event), with its value (``None``: unset), and the folder ``$(cwd)`` named
  when it read that (the ``geomcheck.location`` event: a check of the same files elsewhere is
  another variant);
* the *tree* of the root file's folder and of every package the check looked into: each
  entry's path, kind and size, which also covers the existence tests the hooks do not see.

A variant holds when all of it is as it was; the report is then keyed by the context and the
variant. Files are compared by content, not by modification time, so a CI job that restores
the cache onto a fresh checkout hits it. A check whose expansion globbed includes (the
``geomcheck.volatile`` event) is not stored, nor one whose trees hold more than
:data:`MAX_TREE_ENTRIES` entries (a description in the home folder), nor one that saw a file
or path it looked at change while it ran (its size and modification time when first opened
or looked at, against after the check; its bytes when first opened, against after the
check, so that an edit that keeps the size and puts the modification time back is seen). A
report read back carries the time of this run.

Paths are kept relative to the display root, so the same files checked out in another folder
hit the same entry. This module imports neither numpy nor the loaders: a hit costs the
hashing of what the check read.
"""

from __future__ import annotations

import hashlib
import logging
import os
import stat
import sys
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from geomcheck.cache import active_store
from geomcheck.cache.keys import absolute, canonical, code_fingerprint, digest_key, file_sha256, library_versions
from geomcheck.cache.keys import relative as relative_to
from geomcheck.cache.store import Store, decode_json, encode_json
from geomcheck.diff_cache import options_key
from geomcheck.load.bundle import ENV_EVENT, LOCATION_EVENT, PROBE_EVENT, VOLATILE_EVENT, Bundle
from geomcheck.options import CheckOptions
from geomcheck.report.model import Report, report_timestamp

log = logging.getLogger("geomcheck.cache")

NAMESPACE = "check"
VARIANTS_NAMESPACE = "check-variants"
FORMAT = 1
MAX_VARIANTS = 8  # variants kept per context (branches switched back and forth) [count]
MAX_TREE_ENTRIES = 20_000  # entries of the watched trees one lookup may walk [count]
LIST_EVENTS = frozenset({"os.listdir", "os.scandir"})
UNWATCHED_NAMES = frozenset({".git", ".hg", ".svn", "__pycache__"})  # never read by a description
CODE_SUFFIXES = (".py", ".pyc", ".pyi", ".pth", ".so")  # imports, not the description
WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_TRUNC
LOCATION_KEY = "$(cwd)"  # among the variables a variant records: the folder an expansion's $(cwd) named


@dataclass
class Reads:
    """What a running check read: absolute paths of files opened, folders listed, paths probed."""

    files: set[str] = field(default_factory=set)
    folders: set[str] = field(default_factory=set)
    probes: set[str] = field(default_factory=set)
    environment: set[str] = field(default_factory=set)
    volatile: str | None = None
    # what was there when it was first opened or looked at: an edit made while the check ran
    # shows as a change (size and modification time of a file; the kind of a probed path)
    stamps: dict[str, object] = field(default_factory=dict)
    # the sha256 of each description file as it was when the check first opened it: an edit
    # that keeps the size and puts the modification time back shows too
    hashes: dict[str, str | None] = field(default_factory=dict)
    # the description's own folders (read there is the description's, whatever folder they are
    # in) and the interpreter's, libraries' and geomcheck's (read there is theirs, elsewhere)
    own: tuple[str, ...] = ()
    ignored: tuple[str, ...] = ()
    never: tuple[str, ...] = ()  # geomcheck's own code and cache, and the kernel's files: never the description's

    def description_file(self, path: str) -> bool:
        """Whether a file opened at ``path`` is one the description's result depends on: in the
        description's own folders or looked at by a loader, wherever they are (a description
        installed in the Python environment's prefix is one), else outside the interpreter's and
        libraries' folders; never code an import reads."""
        if path.endswith(CODE_SUFFIXES) or path.startswith(self.never):
            return False
        return path.startswith(self.own) or path in self.probes or not path.startswith(self.ignored)


_RECORDING: list[Reads] = []  # the check being recorded (the CLI checks one description at a time)
_HOOKED: list[bool] = []


def _path_text(value: object) -> str | None:
    if isinstance(value, str | bytes | os.PathLike):
        return os.path.abspath(os.fsdecode(value))
    return None  # a file descriptor


def _opened_for_reading(mode: object, flags: object) -> bool:
    if isinstance(mode, str):
        return "r" in mode and "+" not in mode
    return isinstance(flags, int) and not flags & WRITE_FLAGS


def _audit(event: str, args: tuple[Any, ...]) -> None:
    """The process's audit hook: records into the check being recorded, if any (cheap otherwise).
    It never raises: an exception in an audit hook would fail the operation it watches."""
    if not _RECORDING:
        return
    try:
        _record(_RECORDING[-1], event, args)
    except Exception as err:  # an event of unexpected shape: the check is not stored
        _RECORDING[-1].volatile = f"unrecorded {event} event ({type(err).__name__})"


def _record(reads: Reads, event: str, args: tuple[Any, ...]) -> None:
    if event == "open":
        path = _path_text(args[0])
        if path is not None and _opened_for_reading(args[1], args[2]):
            reads.files.add(path)
            reads.stamps.setdefault(path, _stamp(path))
            if path not in reads.hashes and reads.description_file(path):
                reads.hashes[path] = None  # hashing opens the file too: that event finds it here
                reads.hashes[path] = _sha256_or_absent(path)
    elif event in LIST_EVENTS:
        path = _path_text(args[0] if args[0] is not None else ".")
        if path is not None:
            reads.folders.add(path)
    elif event == PROBE_EVENT:
        if (path := _path_text(args[0])) is not None:
            reads.probes.add(path)
            reads.stamps.setdefault(path, _stamp(path))
    elif event == ENV_EVENT:
        reads.environment.add(str(args[0]))
    elif event == LOCATION_EVENT:
        reads.environment.add(LOCATION_KEY)
    elif event == VOLATILE_EVENT:
        reads.volatile = str(args[0])


def record_reads(
    own: Iterable[str | os.PathLike[str]] = (), ignored: Iterable[str] = (), never: Iterable[str] = ()
) -> Reads:
    """Start recording what this process reads (until :func:`stop_recording`); files opened in
    the ``own`` folders, or outside the ``ignored`` ones, and never in the ``never`` ones, are
    hashed as they are first opened."""
    if not _HOOKED:  # an audit hook cannot be removed: one for the process, idle when not recording
        sys.addaudithook(_audit)
        _HOOKED.append(True)
    reads = Reads(
        own=tuple(os.path.join(os.path.abspath(f), "") for f in own), ignored=tuple(ignored), never=tuple(never)
    )
    _RECORDING.append(reads)
    return reads


def stop_recording(reads: Reads) -> None:
    if reads in _RECORDING:
        _RECORDING.remove(reads)


def _interpreter_roots() -> tuple[str, ...]:
    """Folders whose reads are the interpreter's and the libraries', unless a description lies there."""
    return tuple(os.path.join(os.path.abspath(r), "") for r in {sys.prefix, sys.base_prefix, sys.exec_prefix})


def _own_roots(store: Store) -> tuple[str, ...]:
    """Folders whose reads are never the description's: geomcheck's code, its cache, the kernel's."""
    roots = {str(Path(__file__).resolve().parent), str(store.root)}
    return (*(os.path.join(os.path.abspath(r), "") for r in roots), "/proc/", "/sys/", "/dev/")


def _ignored_roots(store: Store) -> tuple[str, ...]:
    """Folders whose reads are the interpreter's, the libraries' and geomcheck's own, not the description's."""
    return (*_interpreter_roots(), *_own_roots(store))


def description_folders(bundle: Bundle) -> tuple[Path, ...]:
    """The folders whose files are the description's wherever they are: the root file's, the
    packages' and the search folders (a description package installed into the Python
    environment lies under the interpreter's prefix, and is hashed all the same)."""
    return (bundle.root_file.parent, *bundle.packages.values(), *bundle.search_roots)


def watched_trees(bundle: Bundle, touched: Iterable[str]) -> list[Path]:
    """The folders whose trees a variant records: the root file's and those of the packages
    holding a path the check ``touched`` (absolute paths), none inside another. A package the
    check never looked into cannot change its report without an edit to what it did read."""
    used = [os.path.join(p, "") for p in touched]
    packages = [Path(p).resolve() for p in bundle.packages.values()]
    near = [d for d in packages if any(u.startswith(os.path.join(str(d), "")) for u in used)]
    folders = sorted({bundle.root_file.parent.resolve(), *near})
    kept: list[Path] = []
    for folder in folders:
        if not any(folder.is_relative_to(k) for k in kept):
            kept.append(folder)
    return kept


def tree_digest(folder: Path, budget: list[int], unwatched: frozenset[str] = frozenset()) -> str | None:
    """The sha256 of ``folder``'s tree (each entry's relative path, kind and file size, in
    sorted order; links as their targets, never followed), without version-control folders
    and the absolute paths in ``unwatched`` (the cache, the report being written); ``None``
    once ``budget[0]`` entries are spent, or when the folder cannot be read."""
    h = hashlib.sha256()
    pending = [str(folder)]
    # every entry's path starts with the folder's and a separator: cutting it is os.path.relpath's
    # answer without its two abspath calls per entry (half the walk's time on a large folder)
    prefix = len(os.path.join(str(folder), ""))
    try:
        while pending:
            current = pending.pop()
            with os.scandir(current) as listing:
                entries = sorted(
                    (e for e in listing if e.name not in UNWATCHED_NAMES and e.path not in unwatched),
                    key=lambda e: e.name,
                )
            budget[0] -= len(entries)
            if budget[0] < 0:
                return None
            for entry in entries:
                rel = entry.path[prefix:]
                if entry.is_symlink():
                    h.update(f"l\0{rel}\0{os.readlink(entry.path)}\n".encode(errors="surrogateescape"))
                elif entry.is_dir():
                    h.update(f"d\0{rel}\n".encode(errors="surrogateescape"))
                    pending.append(entry.path)
                else:
                    h.update(f"f\0{rel}\0{entry.stat().st_size}\n".encode(errors="surrogateescape"))
    except OSError:
        return None
    return h.hexdigest()


def listing_digest(folder: str) -> str | None:
    """The sha256 of the sorted names in ``folder``; ``None`` when it cannot be listed."""
    try:
        names = sorted(os.listdir(folder))
    except OSError:
        return None
    return hashlib.sha256("\0".join(names).encode(errors="surrogateescape")).hexdigest()


def _sha256_or_absent(path: str) -> str | None:
    return file_sha256(Path(path)) if os.path.isfile(path) else None


def _stamp(path: str) -> tuple[int, int, int] | None:
    """Kind, size and modification time [ns] of what is at ``path`` (``None``: nothing)."""
    try:
        found = os.stat(path)
    except OSError:
        return None
    return stat.S_IFMT(found.st_mode), found.st_size, found.st_mtime_ns


def _kind(path: str) -> str | None:
    """What is at ``path`` without reading it: ``file:SIZE``, ``folder``, ``other`` or ``None``."""
    found = _stamp(path)
    if found is None:
        return None
    mode, size, _ = found
    if stat.S_ISREG(mode):
        return f"file:{size}"
    return "folder" if stat.S_ISDIR(mode) else "other"


def variable(name: str, here: str) -> str | None:
    """The value of the variable ``name`` now (``None``: unset); :data:`LOCATION_KEY`'s is
    ``here``, the folder ``$(cwd)`` names."""
    return here if name == LOCATION_KEY else os.environ.get(name)


def observe(
    variant: Mapping[str, Any], base: Path, unwatched: frozenset[str] = frozenset(), here: str = ""
) -> dict[str, Any] | None:
    """What ``variant``'s trees, files, probed paths, folders and variables are now (its own
    shape; ``here``: the folder ``$(cwd)`` names), ``None`` when a tree is over the budget or
    unreadable."""
    budget = [MAX_TREE_ENTRIES]
    trees: dict[str, str] = {}
    for folder in variant["trees"]:
        digest = tree_digest(Path(absolute(folder, base)), budget, unwatched)
        if digest is None:
            return None
        trees[folder] = digest
    return {
        "trees": trees,
        "files": {p: _sha256_or_absent(absolute(p, base)) for p in variant["files"]},
        "probes": {p: _kind(absolute(p, base)) for p in variant["probes"]},
        "folders": {p: listing_digest(absolute(p, base)) for p in variant["folders"]},
        "environment": {name: variable(name, here) for name in variant["environment"]},
    }


def check_context(bundle: Bundle, options: CheckOptions) -> str:
    """The key of everything but the files a check of ``bundle`` with ``options`` depends on."""
    base = bundle.display_root

    def relative(path: Any) -> str:
        return relative_to(path, base)

    return digest_key(
        NAMESPACE,
        FORMAT,
        code_fingerprint(),
        library_versions(),
        canonical(bundle, path=relative),
        options_key(options, path=relative),
    )


def _variants(store: Store, context: str) -> list[dict[str, Any]]:
    found = store.get_json(VARIANTS_NAMESPACE, context)
    if not isinstance(found, list):
        return []
    shape = ("trees", "files", "probes", "folders", "environment")
    return [v for v in found if isinstance(v, dict) and all(isinstance(v.get(k), dict) for k in shape)]


def _lookup(store: Store, context: str, base: Path, unwatched: frozenset[str], here: str) -> Report | None:
    for variant in _variants(store, context):
        now = observe(variant, base, unwatched, here)
        if now is None or now != variant:
            continue
        # an entry that is no report is discarded by the store and checked again
        found = store.get_decoded(NAMESPACE, digest_key(NAMESPACE, context, variant), _decode_report)
        if found is not None:
            return found
    return None


def _decode_report(payload: bytes) -> Report:
    return Report.from_dict(decode_json(payload))


def _description_reads(reads: Reads, store: Store) -> tuple[set[str], set[str], set[str]]:
    """The files, probed paths and listed folders of ``reads`` that are the description's: not
    the import paths, and folders only inside the description's own roots or outside the
    ignored ones."""
    ignored = (*reads.ignored, *reads.never) if reads.ignored or reads.never else _ignored_roots(store)
    import_paths = {os.path.abspath(p or os.curdir) for p in sys.path}  # listed by imports made while checking

    def description_path(path: str) -> bool:
        return path not in import_paths and (path in reads.probes or reads.description_file(path))

    def description_folder(path: str) -> bool:
        inside = os.path.join(path, "")
        if not description_path(path) or inside.startswith(reads.never):
            return False
        return inside.startswith(reads.own) or not inside.startswith(ignored)

    files = {p for p in reads.files if description_path(p)}
    probes = {p for p in reads.probes - reads.files if description_path(p)}
    folders = {p for p in reads.folders if description_folder(p)}
    return files, probes, folders


def _hashes_if_unchanged(reads: Reads, files: set[str], probes: set[str]) -> dict[str, str | None] | None:
    """The sha256 of each of ``files`` now; ``None`` when a file or probed path changed since
    the check looked at it."""
    if any(_stamp(p) != reads.stamps.get(p) for p in files | probes):
        return None
    hashes = {p: _sha256_or_absent(p) for p in sorted(files)}
    if any(p in reads.hashes and hashes[p] != reads.hashes[p] for p in files):
        return None  # edited while checked, its modification time put back: the report is of the old bytes
    return hashes


def recorded_variant(reads: Reads, bundle: Bundle, store: Store, unwatched: frozenset[str]) -> dict[str, Any] | None:
    """The variant of a check of ``bundle`` that read ``reads``: what is there now. ``None``
    when it cannot be kept: a tree over the budget, or a file or probed path changed since the
    check looked at it (edited while it ran)."""
    base = bundle.display_root
    files, probes, folders = _description_reads(reads, store)
    hashes = _hashes_if_unchanged(reads, files, probes)
    if hashes is None:
        return None
    trees = {relative_to(t, base): "" for t in watched_trees(bundle, files | probes | folders)}
    observed = observe({"trees": trees, "files": {}, "probes": {}, "folders": {}, "environment": {}}, base, unwatched)
    if observed is None:
        return None
    return {
        "trees": observed["trees"],
        "files": {relative_to(p, base): hashes[p] for p in sorted(files)},
        "probes": {relative_to(p, base): _kind(p) for p in sorted(probes)},
        "folders": {relative_to(p, base): listing_digest(p) for p in sorted(folders)},
        "environment": {name: variable(name, bundle.working_folder()) for name in sorted(reads.environment)},
    }


def cached_check(
    bundle: Bundle,
    options: CheckOptions,
    check: Callable[[Bundle, CheckOptions], Report],
    outputs: Iterable[str | os.PathLike[str]] = (),
) -> Report:
    """``check(bundle, options)``, answered from the active store when an earlier check read
    the very same files (see the module docstring); computed every time with no store active.
    ``outputs`` are files the caller writes (the report): their changes are not edits."""
    store = active_store()
    if store is None:
        return check(bundle, options)
    base = bundle.display_root
    unwatched = frozenset(os.path.abspath(p) for p in (store.root, *outputs))
    try:
        context = check_context(bundle, options)
    except TypeError as err:  # an option no key can hold: never cached, never a failure
        log.debug("cache: check not cached: %s", err)
        return check(bundle, options)
    found = _lookup(store, context, base, unwatched, bundle.working_folder())
    if found is not None:
        return replace(found, created=report_timestamp())
    reads = record_reads(description_folders(bundle), _interpreter_roots(), _own_roots(store))
    try:
        report = check(bundle, options)
    finally:
        stop_recording(reads)
    if reads.volatile is not None:
        log.debug("cache: check not stored: %s", reads.volatile)
        return report
    variant = recorded_variant(reads, bundle, store, unwatched)
    if variant is None:
        log.debug("cache: check not stored: its trees are too large to watch, or it was edited while checked")
        return report
    store.put_bytes(NAMESPACE, digest_key(NAMESPACE, context, variant), encode_json(report.to_dict()))
    kept = [v for v in _variants(store, context) if v != variant][: MAX_VARIANTS - 1]
    store.put_json(VARIANTS_NAMESPACE, context, [variant, *kept])
    return report
