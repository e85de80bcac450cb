"""Safe unpacking of uploaded archives (zip, tar, gzip'd tar) into an :class:`UploadTree`.

Nothing in an archive is trusted: entry counts come from the central directory's real
size, sizes are counted while decompressing (headers may lie), the unpacked/compressed
ratio is watched as the data streams, and links, devices and paths leaving the tree are
refused. Every refusal is an :class:`UploadError` with a one-line reason.
"""

from __future__ import annotations

import gzip
import stat
import struct
import tarfile
import zipfile
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from api.errors import UploadError, UploadTooLarge
from api.uploads.tree import UploadTree

CHUNK = 64 * 1024  # bytes read per step while unpacking
RATIO_FLOOR = 1024 * 1024  # the ratio limit applies once this much is unpacked [bytes]
CENTRAL_ENTRY_MAX = 46 + 1024 + 1024  # one central-directory record: fixed part, name, extra [bytes]
TAR_OVERHEAD = 1536  # header and padding per tar entry, upper bound [bytes]

ZIP_TYPES = frozenset({"application/zip", "application/x-zip-compressed"})
ZIP_METHODS = frozenset({zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED})  # decompressed with a bound per read
ZIP_METHOD_NAMES = {zipfile.ZIP_BZIP2: "bzip2", zipfile.ZIP_LZMA: "LZMA", 93: "Zstandard", 9: "Deflate64"}
TGZ_TYPES = frozenset({"application/gzip", "application/x-gzip", "application/x-tar+gzip", "application/x-tgz"})
TAR_TYPES = frozenset({"application/x-tar"})
ARCHIVE_TYPES = ZIP_TYPES | TGZ_TYPES | TAR_TYPES
SNIFF_BYTES = 512  # what content recognition reads of a body [bytes]


def sniffed_type(head: bytes, declared: str) -> str:
    """The media type of a body by its first bytes: a zip, gzip or tar archive is one
    whatever the Content-Type says (a zip sent as application/xml is a zip), and a body that
    starts like XML is XML; anything else keeps ``declared``."""
    if head.startswith((b"PK\x03\x04", b"PK\x05\x06")):
        return declared if declared in ZIP_TYPES else "application/zip"
    if head.startswith(b"\x1f\x8b"):
        return declared if declared in TGZ_TYPES else "application/gzip"
    if head[257:262] == b"ustar":
        return declared if declared in TAR_TYPES else "application/x-tar"
    if head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<"):
        return "application/xml"
    return declared


def unpack(path: Path, content_type: str, tree: UploadTree) -> None:
    """Unpack the archive at ``path`` (the request body) of media type ``content_type`` into ``tree``."""
    with path.open("rb") as fp:
        magic = fp.read(4)
    if content_type in ZIP_TYPES:
        if not magic.startswith(b"PK"):
            raise UploadError(f"body is not a zip archive (Content-Type {content_type})")
        unpack_zip(path, tree)
    elif content_type in TGZ_TYPES:
        if not magic.startswith(b"\x1f\x8b"):
            raise UploadError(f"body is not gzip data (Content-Type {content_type})")
        unpack_tar(path, tree, gzipped=True)
    elif content_type in TAR_TYPES:
        unpack_tar(path, tree, gzipped=False)
    else:
        raise UploadError(f"not an archive type: {content_type}")


def _zip_directory_extent(fp: IO[bytes], size: int) -> tuple[int, int]:
    """(entries, central-directory size [bytes]) from the end record, zip64 included."""
    tail_len = min(size, 22 + 0xFFFF)
    fp.seek(size - tail_len)
    tail = fp.read(tail_len)
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or len(tail) - at < 22:
        raise UploadError("body is not a zip archive (no end-of-central-directory record)")
    fields = struct.unpack("<4s4H2LH", tail[at : at + 22])
    entries, cd_size = fields[4], fields[5]
    if (entries == 0xFFFF or cd_size == 0xFFFFFFFF) and at >= 20 and tail[at - 20 : at - 16] == b"PK\x06\x07":
        record_offset = struct.unpack("<4sLQL", tail[at - 20 : at])[2]
        if record_offset + 56 > size:
            raise UploadError("corrupt zip64 end record")
        fp.seek(record_offset)
        record = fp.read(56)
        if record[:4] != b"PK\x06\x06":
            raise UploadError("corrupt zip64 end record")
        values = struct.unpack("<4sQHHLLQQQQ", record)
        entries, cd_size = values[7], values[8]
    return entries, cd_size


def _zip_kind(info: zipfile.ZipInfo) -> str | None:
    """What a zip entry is when it is not a plain file or folder (``symbolic link``...), else None."""
    mode = info.external_attr >> 16
    kind = stat.S_IFMT(mode)
    if kind in (0, stat.S_IFREG, stat.S_IFDIR):
        return None
    return "a symbolic link" if kind == stat.S_IFLNK else "a special file"


def unpack_zip(path: Path, tree: UploadTree) -> None:
    limits = tree.limits
    size = path.stat().st_size
    with path.open("rb") as fp:
        entries, cd_size = _zip_directory_extent(fp, size)
    if entries > limits.max_files or cd_size > limits.max_files * CENTRAL_ENTRY_MAX:
        raise UploadTooLarge(f"zip archive has more than {limits.max_files} entries")
    try:
        with zipfile.ZipFile(path) as archive:
            infos = archive.infolist()
            for info in infos:
                tree.count_entry(info.filename)
            for info in infos:
                _unpack_zip_entry(archive, info, tree, size)
    except (zipfile.BadZipFile, zlib.error, EOFError, NotImplementedError, RuntimeError, ValueError) as err:
        raise UploadError(f"corrupt or unsupported zip archive: {err}") from None


def _unpack_zip_entry(archive: zipfile.ZipFile, info: zipfile.ZipInfo, tree: UploadTree, archive_size: int) -> None:
    kind = _zip_kind(info)
    if kind is not None:
        raise UploadError(f"archive entry {info.filename!r} is {kind}; links and special files are refused")
    if info.flag_bits & 0x1:
        raise UploadError(f"archive entry {info.filename!r} is encrypted")
    if info.compress_type not in ZIP_METHODS:
        # zipfile decompresses a bzip2 or LZMA member without an output bound: a few compressed
        # bytes become gigabytes in one read, before any size limit can see them
        method = ZIP_METHOD_NAMES.get(info.compress_type, f"method {info.compress_type}")
        raise UploadError(
            f"archive entry {info.filename!r} is compressed with {method}; only stored and deflated "
            "entries are accepted (zip's default, as zip -r and every archiver write)"
        )
    if info.is_dir():
        tree.add_dir(info.filename)
        return
    ratio = tree.limits.max_ratio

    def chunks() -> Iterator[bytes]:
        produced = 0
        with archive.open(info) as member:
            while chunk := member.read(CHUNK):
                produced += len(chunk)
                if produced > RATIO_FLOOR and produced > ratio * max(info.compress_size, 1):
                    raise UploadTooLarge(
                        f"archive entry {info.filename!r} unpacks more than {ratio:g} times its compressed size"
                    )
                total = tree.unpacked_bytes + produced
                if total > RATIO_FLOOR and total > ratio * archive_size:
                    raise UploadTooLarge(f"archive unpacks to more than {ratio:g} times its size (a zip bomb?)")
                yield chunk

    tree.add_file(info.filename, chunks())


class _WatchedStream:
    """Reads decompressed tar data while bounding its total size and its ratio to the bytes consumed."""

    def __init__(self, inner: IO[bytes], raw: IO[bytes], limit: int, ratio: float) -> None:
        self.inner, self.raw, self.limit, self.ratio = inner, raw, limit, ratio
        self.produced = 0

    def read(self, size: int = -1) -> bytes:
        data = self.inner.read(CHUNK if size is None or size < 0 else min(size, 4 * CHUNK))
        self.produced += len(data)
        if self.produced > self.limit:
            raise UploadTooLarge(f"archive unpacks to more than the limit of {self.limit} bytes")
        consumed = max(self.raw.tell(), 1)
        if self.produced > RATIO_FLOOR and self.produced > self.ratio * consumed:
            raise UploadTooLarge(f"archive unpacks to more than {self.ratio:g} times its size (a gzip bomb?)")
        return data


def unpack_tar(path: Path, tree: UploadTree, gzipped: bool) -> None:
    limits = tree.limits
    stream_limit = limits.max_unpacked_bytes + (limits.max_files + 2) * TAR_OVERHEAD
    try:
        with path.open("rb") as raw:
            inner: IO[bytes] = gzip.GzipFile(fileobj=raw, mode="rb") if gzipped else raw  # type: ignore[assignment]
            ratio = limits.max_ratio if gzipped else float("inf")
            watched = _WatchedStream(inner, raw, stream_limit, ratio)
            with tarfile.open(fileobj=watched, mode="r|") as archive:  # type: ignore[call-overload]
                for member in archive:
                    _unpack_tar_member(archive, member, tree)
    except (tarfile.TarError, zlib.error, EOFError, gzip.BadGzipFile) as err:
        raise UploadError(f"corrupt or unsupported tar archive: {err}") from None
    except RecursionError:  # tarfile reads chained GNU long-name and pax headers recursively
        raise UploadError("corrupt tar archive: extended headers chained too deeply") from None


def _unpack_tar_member(archive: tarfile.TarFile, member: tarfile.TarInfo, tree: UploadTree) -> None:
    tree.count_entry(member.name)
    if member.issym() or member.islnk():
        raise UploadError(f"archive entry {member.name!r} is a link; links are refused")
    if member.isdir():
        tree.add_dir(member.name)
        return
    if not member.isreg() or member.issparse():
        raise UploadError(f"archive entry {member.name!r} is a special file; only files and folders are accepted")
    remaining = tree.limits.max_unpacked_bytes - tree.unpacked_bytes
    if member.size > remaining:
        raise UploadTooLarge(
            f"archive entry {member.name!r} of {member.size} bytes exceeds the unpacked-size limit of "
            f"{tree.limits.max_unpacked_bytes} bytes"
        )
    source = archive.extractfile(member)
    if source is None:
        raise UploadError(f"archive entry {member.name!r} cannot be read")

    def chunks() -> Iterator[bytes]:
        while chunk := source.read(CHUNK):
            yield chunk

    tree.add_file(member.name, chunks())
