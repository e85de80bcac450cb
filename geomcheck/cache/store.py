"""A content-addressed store of computed results on disk, shared by concurrent processes.

Layout: ``ROOT/NAMESPACE/KK/KEY`` where ``KEY`` is a sha256 (hex) computed by the caller
from everything the result depends on (:func:`geomcheck.cache.keys.digest_key`) and ``KK``
its first two characters. Each entry is a header line ``geomcheck-cache/2 <namespace> <key>
<sha256 of the payload>`` followed by the payload.

* Writes go to a temporary file in the entry's folder, then ``os.replace`` it into place:
  a reader sees the old entry, the new one or none, never half of one, and two processes
  computing the same result both succeed (the last rename wins; both wrote the same bytes).
* Reads trust nothing they find: the entry is opened without following a link
  (``O_NOFOLLOW``, non-blocking), must be a regular file (``fstat``; a FIFO would block, a
  link to ``/dev/zero`` would never end) of at most :data:`MAX_ENTRY_BYTES`, and must name
  its own namespace and key in its header (a valid entry copied under another key would
  give another result's answer) and match its payload's digest. An entry that cannot be
  read, fails verification or cannot be decoded is deleted and recomputed, with a debug log
  line.
  Payloads are JSON or ``.npz`` without pickles, so a tampered entry can at worst make a
  result be recomputed, never run code.
* The store's size is capped: a hit refreshes the entry's modification time and, once a
  process has written more than a sixteenth of the cap, the least recently used entries
  are removed until the store is back under it.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import logging
import os
import stat
import tempfile
import time
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from geomcheck.cache.keys import digest_key
from geomcheck.errors import UsageError

if TYPE_CHECKING:
    import numpy as np

log = logging.getLogger("geomcheck.cache")

T = TypeVar("T")

CACHE_DIR_ENV = "GEOMCHECK_CACHE_DIR"
CACHE_MAX_ENV = "GEOMCHECK_CACHE_MAX_MB"
DEFAULT_MAX_BYTES = 1024 * 1024 * 1024  # size cap of the whole store [bytes]
EVICT_AFTER_FRACTION = 1 / 16  # bytes written by one process before it checks the cap [fraction of the cap]
EVICT_TO_FRACTION = 0.9  # eviction stops below this share of the cap [fraction]
STALE_TEMP_S = 3600.0  # a temporary file this old belongs to a process that died [s]
HEADER_MAGIC = b"geomcheck-cache/2 "
MAX_ENTRY_BYTES = 512 * 1024 * 1024  # one entry, header included; larger files are not read [bytes]
TEMP_PREFIX = ".tmp-"
NAMESPACE_CHARS = frozenset("abcdefghijklmnopqrstuvwxyz0123456789-_")


def default_cache_dir() -> Path:
    """``$GEOMCHECK_CACHE_DIR``, else ``$XDG_CACHE_HOME/geomcheck``, else ``~/.cache/geomcheck``."""
    explicit = os.environ.get(CACHE_DIR_ENV)
    if explicit:
        return Path(explicit)
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg) if xdg and Path(xdg).is_absolute() else Path.home() / ".cache"
    return base / "geomcheck"


def default_max_bytes() -> int:
    """The size cap [bytes]: ``$GEOMCHECK_CACHE_MAX_MB`` mebibytes, else :data:`DEFAULT_MAX_BYTES`."""
    text = os.environ.get(CACHE_MAX_ENV)
    if not text:
        return DEFAULT_MAX_BYTES
    try:
        megabytes = float(text)
    except ValueError:
        raise UsageError(f"{CACHE_MAX_ENV} must be a number of mebibytes, got {text!r}") from None
    if not megabytes > 0:
        raise UsageError(f"{CACHE_MAX_ENV} must be positive, got {text!r}")
    return int(megabytes * 1024 * 1024)


class CorruptEntry(Exception):
    """An entry whose bytes do not verify or decode (it is recomputed, never used)."""


@dataclass
class Store:
    """The cache store in folder ``root``, capped at ``max_bytes`` [bytes].

    ``hits`` and ``misses`` count lookups of this instance (benchmarks print them).
    """

    root: Path
    max_bytes: int = DEFAULT_MAX_BYTES
    hits: int = 0
    misses: int = 0
    _written: int = field(default=0, repr=False)

    # --- raw entries ------------------------------------------------------------------

    def path(self, namespace: str, key: str) -> Path:
        """Where entry ``key`` of ``namespace`` lives; :class:`ValueError` for names that
        could leave the store."""
        if not namespace or not set(namespace) <= NAMESPACE_CHARS:
            raise ValueError(f"cache namespace must be lowercase letters, digits, '-' or '_', got {namespace!r}")
        if len(key) < 16 or not all(c in "0123456789abcdef" for c in key):
            raise ValueError(f"cache key must be a hex digest, got {key!r}")
        return self.root / namespace / key[:2] / key

    def get_bytes(self, namespace: str, key: str) -> bytes | None:
        """The verified payload of the entry, ``None`` when there is none. A corrupt entry is
        deleted (debug log line) and reported as absent."""
        path = self.path(namespace, key)
        try:
            payload = _verified(_read_entry(path, min(self.max_bytes, MAX_ENTRY_BYTES)), namespace, key)
        except FileNotFoundError:
            self.misses += 1
            return None
        except OSError as err:
            self._discard(path, f"unreadable ({err.strerror})")
            self.misses += 1
            return None
        except CorruptEntry as err:
            self._discard(path, str(err))
            self.misses += 1
            return None
        self.hits += 1
        return payload

    def put_bytes(self, namespace: str, key: str, payload: bytes) -> None:
        """Store ``payload`` as entry ``key`` (atomically; a failure to write is logged and
        ignored: the cache only ever saves time)."""
        path = self.path(namespace, key)
        header = _header(namespace, key, payload)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, temp = tempfile.mkstemp(prefix=TEMP_PREFIX, dir=path.parent)
            try:
                with os.fdopen(fd, "wb") as f:
                    f.write(header)
                    f.write(payload)
                os.replace(temp, path)
            except BaseException:
                with contextlib.suppress(OSError):
                    os.unlink(temp)
                raise
        except OSError as err:
            log.debug("cache: cannot write %s: %s", path, err)
            return
        self._written += len(header) + len(payload)
        if self._written >= self.max_bytes * EVICT_AFTER_FRACTION:
            self._written = 0
            self.evict()

    def discard(self, namespace: str, key: str, reason: str) -> None:
        """Remove an entry whose payload turned out unusable (debug log line)."""
        self._discard(self.path(namespace, key), reason)

    def _discard(self, path: Path, reason: str) -> None:
        log.debug("cache: entry %s is %s; recomputing it", path, reason)
        with contextlib.suppress(OSError):
            path.unlink()

    # --- typed helpers ----------------------------------------------------------------

    def get_or_compute(
        self,
        namespace: str,
        key_parts: Any,
        compute: Callable[[], T],
        encode: Callable[[T], bytes],
        decode: Callable[[bytes], T],
    ) -> T:
        """The result keyed by ``key_parts`` (anything :func:`~geomcheck.cache.keys.canonical`
        takes): decoded from the store, else ``compute()``d, encoded and stored. A payload
        that ``decode`` rejects (any exception) is discarded and recomputed."""
        key = digest_key(namespace, key_parts)
        found = self.get_decoded(namespace, key, decode)
        if found is not None:
            return found
        value = compute()
        self.put_bytes(namespace, key, encode(value))
        return value

    def get_decoded(self, namespace: str, key: str, decode: Callable[[bytes], T]) -> T | None:
        """Entry ``key`` decoded, ``None`` when absent, corrupt or rejected by ``decode`` (any
        exception: the entry is discarded, never trusted); ``decode`` never returns ``None``."""
        payload = self.get_bytes(namespace, key)
        if payload is None:
            return None
        try:
            return decode(payload)
        except Exception as err:  # a payload that verifies but does not decode
            self.hits -= 1
            self.misses += 1
            self.discard(namespace, key, f"undecodable ({type(err).__name__}: {err})")
            return None

    def get_json(self, namespace: str, key: str) -> Any | None:
        """A JSON entry, ``None`` when absent or corrupt (as :meth:`get_decoded`)."""
        return self.get_decoded(namespace, key, json.loads)

    def put_json(self, namespace: str, key: str, value: Any) -> None:
        self.put_bytes(namespace, key, encode_json(value))

    def get_arrays(self, namespace: str, key: str) -> dict[str, np.ndarray] | None:
        """A ``.npz`` entry as ``{name: array}``, ``None`` when absent or corrupt (as :meth:`get_decoded`)."""
        return self.get_decoded(namespace, key, decode_arrays)

    def put_arrays(self, namespace: str, key: str, arrays: Mapping[str, np.ndarray]) -> None:
        self.put_bytes(namespace, key, encode_arrays(arrays))

    # --- size cap ---------------------------------------------------------------------

    def entries(self) -> Iterator[tuple[Path, os.stat_result]]:
        """Every entry (and leftover temporary file) with its ``stat``."""
        if not self.root.is_dir():
            return
        for dirpath, _, filenames in os.walk(self.root):
            for name in filenames:
                path = Path(dirpath) / name
                with contextlib.suppress(OSError):
                    yield path, path.lstat()  # a link is counted as itself, never followed

    def size(self) -> int:
        """Bytes held by the store's entries."""
        return sum(st.st_size for _, st in self.entries())

    def evict(self) -> int:
        """Remove the least recently used entries until the store holds at most
        ``EVICT_TO_FRACTION`` of the cap (nothing when it is under the cap), and temporary
        files of processes that died. Returns the number of files removed."""
        now = time.time()
        found, removed, total = [], 0, 0
        for path, st in self.entries():
            if path.name.startswith(TEMP_PREFIX):
                if now - st.st_mtime > STALE_TEMP_S:
                    with contextlib.suppress(OSError):
                        path.unlink()
                        removed += 1
                continue
            found.append((st.st_mtime, path.as_posix(), st.st_size))
            total += st.st_size
        if total <= self.max_bytes:
            return removed
        target = self.max_bytes * EVICT_TO_FRACTION
        for _, name, size in sorted(found):
            if total <= target:
                break
            with contextlib.suppress(OSError):
                os.unlink(name)
                removed += 1
            total -= size
        log.debug("cache: evicted %d entries from %s", removed, self.root)
        return removed

    def clear(self) -> None:
        """Remove every entry."""
        for path, _ in list(self.entries()):
            with contextlib.suppress(OSError):
                path.unlink()


def _header(namespace: str, key: str, payload: bytes) -> bytes:
    return HEADER_MAGIC + f"{namespace} {key} {hashlib.sha256(payload).hexdigest()}\n".encode("ascii")


_READ_FLAGS = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)


def _read_entry(path: Path, max_bytes: int) -> bytes:
    """The bytes of the entry file ``path``: opened without following a link and without
    blocking, a regular file of at most ``max_bytes``; its modification time refreshed (least
    recently used is judged by it). :class:`CorruptEntry` otherwise; ``OSError`` as raised
    (``FileNotFoundError`` for no entry; a link gives ``ELOOP``)."""
    fd = os.open(path, _READ_FLAGS)
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise CorruptEntry("not a regular file")
        if info.st_size > max_bytes:
            raise CorruptEntry(f"too large ({info.st_size} bytes, at most {max_bytes})")
        chunks, left = [], max_bytes + 1
        while left > 0:  # read to the end, not trusting st_size: the file may be growing
            chunk = os.read(fd, min(left, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
        if left <= 0:
            raise CorruptEntry(f"too large (more than {max_bytes} bytes)")
        with contextlib.suppress(OSError):
            os.utime(fd)
        return b"".join(chunks)
    finally:
        os.close(fd)


def _verified(raw: bytes, namespace: str, key: str) -> bytes:
    """The payload of entry bytes ``raw`` stored as ``key`` of ``namespace``;
    :class:`CorruptEntry` when the header, the key it names or the digest is wrong."""
    head, sep, payload = raw.partition(b"\n")
    if not sep or not head.startswith(HEADER_MAGIC):
        raise CorruptEntry("not a geomcheck cache entry")
    fields = head[len(HEADER_MAGIC) :].decode("ascii", errors="replace").split(" ")
    if len(fields) != 3:
        raise CorruptEntry("not a geomcheck cache entry")
    if fields[:2] != [namespace, key]:
        raise CorruptEntry("stored under another key than its own")
    if hashlib.sha256(payload).hexdigest() != fields[2]:
        raise CorruptEntry("corrupt (payload digest mismatch)")
    return payload


def encode_json(value: Any) -> bytes:
    return json.dumps(value, separators=(",", ":"), ensure_ascii=False).encode("utf-8")


def decode_json(payload: bytes) -> Any:
    return json.loads(payload)


def encode_arrays(arrays: Mapping[str, np.ndarray]) -> bytes:
    """``{name: array}`` as an uncompressed ``.npz`` (numeric arrays only: no pickles)."""
    import numpy as np

    buffer = io.BytesIO()
    named: dict[str, Any] = {name: np.asarray(a) for name, a in arrays.items()}
    np.savez(buffer, allow_pickle=False, **named)
    return buffer.getvalue()


def decode_arrays(payload: bytes) -> dict[str, np.ndarray]:
    """The arrays of an ``.npz`` payload; object arrays are refused (``allow_pickle=False``)."""
    import numpy as np

    with np.load(io.BytesIO(payload), allow_pickle=False) as archive:
        return {name: archive[name] for name in archive.files}


def open_store(root: Path | None = None, max_bytes: int | None = None) -> Store:
    """The store at ``root`` (default :func:`default_cache_dir`) with cap ``max_bytes``
    (default :func:`default_max_bytes`)."""
    return Store(root or default_cache_dir(), max_bytes if max_bytes is not None else default_max_bytes())
