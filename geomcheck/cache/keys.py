"""Content keys: canonical JSON of key parts, file digests and the versions a result depends on.

A key is the sha256 of the canonical JSON of its parts (sorted keys, no whitespace,
dataclasses as their fields, paths as posix strings, enums as their values), so equal
inputs give equal keys in every process and on every machine.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import hashlib
import json
import os
import re
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path, PurePath
from typing import Any

from geomcheck.version import __version__

HASH_CHUNK_BYTES = 1 << 20  # read size when hashing a file [bytes]

# Distributions whose behaviour shapes a report: xacro expands, trimesh/pycollada read
# meshes, numpy/scipy compute the geometry, coal/python-fcl answer collision queries, lxml parses.
RESULT_LIBRARIES = (
    "xacro",
    "lxml",
    "trimesh",
    "pycollada",
    "numpy",
    "scipy",
    "coal",
    "python-fcl",
    "fast-simplification",  # the scene section's decimated meshes
)


# returned as they are (exact types: a subclass of one takes the long way below)
_PLAIN = frozenset({type(None), bool, int, float, str})


_FIELD_NAMES: dict[type, tuple[str, ...] | None] = {}


def _field_names(kind: type) -> tuple[str, ...] | None:
    """The field names of a dataclass type, ``None`` for any other type (found once per type:
    a key of a large link holds thousands of poses)."""
    if kind not in _FIELD_NAMES:
        is_dataclass = dataclasses.is_dataclass(kind)
        _FIELD_NAMES[kind] = tuple(f.name for f in dataclasses.fields(kind)) if is_dataclass else None
    return _FIELD_NAMES[kind]


def canonical(value: Any, path: Callable[[PurePath], str] = PurePath.as_posix) -> Any:
    """``value`` as plain JSON data: dataclasses become ``{field: value}``, mappings get
    string keys, tuples and sets become lists (sets sorted), paths ``path(p)`` (posix
    strings by default), enums their values. :class:`TypeError` for anything else (a key
    must never depend on ``repr``)."""
    kind = type(value)
    if kind in _PLAIN:
        return value
    if kind is tuple or kind is list:
        return [canonical(v, path) for v in value]
    names = _field_names(kind)
    if names is not None:
        return {name: canonical(getattr(value, name), path) for name in names}
    if isinstance(value, enum.Enum):
        return canonical(value.value, path)
    if isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, PurePath):
        return path(value)
    if isinstance(value, Mapping):
        return {str(k): canonical(v, path) for k, v in value.items()}
    if isinstance(value, set | frozenset):
        return sorted(canonical(v, path) for v in value)
    if isinstance(value, list | tuple):
        return [canonical(v, path) for v in value]
    if isinstance(value, bytes):
        return hashlib.sha256(value).hexdigest()
    raise TypeError(f"cannot put a {type(value).__name__} in a cache key")


def canonical_json(value: Any) -> str:
    """The canonical JSON text of ``value`` (see :func:`canonical`)."""
    return json.dumps(canonical(value), sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def digest_key(*parts: Any) -> str:
    """The sha256 (hex) of the canonical JSON of ``parts``."""
    return hashlib.sha256(canonical_json(list(parts)).encode("utf-8")).hexdigest()


def every_digest(items: Iterable[Any], digest: Callable[[Any], str | None]) -> list[str] | None:
    """``digest(item)`` of each of ``items``, in order; ``None`` as soon as one has none (a
    mesh that did not load): a result over content of unknown digest is never stored."""
    digests = []
    for item in items:
        found = digest(item)
        if not found:
            return None
        digests.append(found)
    return digests


def bytes_sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def file_sha256(path: Path) -> str | None:
    """The sha256 (hex) of the file's bytes; ``None`` when it is not a readable file."""
    h = hashlib.sha256()
    try:
        with path.open("rb") as f:
            while chunk := f.read(HASH_CHUNK_BYTES):
                h.update(chunk)
    except OSError:
        return None
    return h.hexdigest()


def _distribution_version(name: str) -> str:
    from importlib import metadata

    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "absent"


def _normalised(name: str) -> str:
    """A distribution's name as installers write it in folder names (PEP 503, then ``-`` as ``_``)."""
    return re.sub(r"[-_.]+", "_", name).lower()


@functools.cache
def _installed_versions() -> dict[str, str]:
    """``{normalised name: version}`` read off the ``NAME-VERSION.dist-info`` folders on
    ``sys.path``, the first of a name winning as imports do: one listing per folder instead of
    ``importlib.metadata``'s import and searches (a warm check's start)."""
    found: dict[str, str] = {}
    for entry in sys.path:
        try:
            names = os.listdir(entry or os.curdir)
        except OSError:
            continue
        for folder in names:
            name, dash, version = folder.removesuffix(".dist-info").partition("-")
            if folder.endswith(".dist-info") and dash:
                found.setdefault(_normalised(name), version)
    return found


@functools.cache
def library_versions(names: Iterable[str] = RESULT_LIBRARIES) -> dict[str, str]:
    """``{distribution: version}`` of ``names`` (``absent`` when not installed); what no
    ``.dist-info`` folder names (an egg, a zip) is asked of ``importlib.metadata``."""
    installed = _installed_versions()
    return {name: installed.get(_normalised(name)) or _distribution_version(name) for name in names}


@functools.cache
def code_fingerprint() -> str:
    """geomcheck's version and a digest of its own source files.

    The version string alone does not change while geomcheck is developed; the source digest
    does, so an edited loader or check never reads results an older code computed.
    """
    package = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(__version__.encode())
    for path in sorted(package.rglob("*.py")):
        h.update(path.relative_to(package).as_posix().encode() + b"\0")
        h.update(path.read_bytes())
    return f"{__version__}+{h.hexdigest()[:16]}"


def relative(path: str | os.PathLike[str], base: Path) -> str:
    """``path`` relative to ``base`` (both made absolute) as posix text; absolute when no
    relative path leads there (another drive)."""
    try:
        return Path(os.path.relpath(Path(path).absolute(), base.absolute())).as_posix()
    except ValueError:
        return Path(path).absolute().as_posix()


def absolute(path: str, base: Path) -> str:
    """The absolute path of ``path`` (relative to ``base``, or already absolute), as text."""
    return os.path.normpath(base.absolute() / path)
