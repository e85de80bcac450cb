"""Stored reports compressed once, spliced into gzip'd answers.

A report is stored once and served many times (the result cache answers every identical
submission with it), and compressing a 1.7 MB report costs 70 ms at gzip's level 9. The
report is compressed once into raw DEFLATE blocks that end on a byte boundary (a sync
flush) and kept in a small LRU; an answer is then the gzip header, the check's own fields
compressed on their own, the stored blocks, the closing brace and the trailer (CRC-32 and
length of the whole). DEFLATE blocks never refer to data before their stream's start, so
the pieces join into one valid stream (RFC 1951, 1952).
"""

from __future__ import annotations

import struct
import threading
import zlib
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass

LEVEL = 6  # of the stored blocks: compressed once, served many times [zlib level]
HEAD_LEVEL = 1  # of the small per-answer pieces [zlib level]
MAX_ENTRIES = 32  # reports kept compressed in memory [count]
GZIP_HEADER = b"\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\xff"  # deflate, no name, no mtime, unknown OS


@dataclass(frozen=True)
class Compressed:
    """A report's text as raw DEFLATE blocks ending on a sync flush, with the text's CRC-32 and
    length, and the GF(2) operator that appends ``size`` zero bytes to a CRC (32 columns), so
    the CRC of anything + the text costs 32 steps."""

    blocks: bytes
    crc32: int
    size: int
    shift: tuple[int, ...]


def compress_piece(data: bytes, level: int = LEVEL) -> bytes:
    """``data`` as raw DEFLATE blocks, not final, ending on a byte boundary."""
    compressor = zlib.compressobj(level, zlib.DEFLATED, -zlib.MAX_WBITS)
    return compressor.compress(data) + compressor.flush(zlib.Z_SYNC_FLUSH)


def gzip_around(head: bytes, middle: Compressed, tail: bytes) -> bytes:
    """One gzip member whose content is ``head`` + the middle's text + ``tail``."""
    closing = zlib.compressobj(HEAD_LEVEL, zlib.DEFLATED, -zlib.MAX_WBITS)
    last = closing.compress(tail) + closing.flush(zlib.Z_FINISH)
    crc = zlib.crc32(tail, _crc_concat(zlib.crc32(head), middle))
    size = (len(head) + middle.size + len(tail)) & 0xFFFFFFFF
    return b"".join((GZIP_HEADER, compress_piece(head, HEAD_LEVEL), middle.blocks, last, struct.pack("<II", crc, size)))


def _crc_concat(crc_head: int, middle: Compressed) -> int:
    """CRC-32 of head + middle's text from their CRCs (zlib's crc32_combine, which Python does not expose)."""
    return _gf2_times(middle.shift, crc_head) ^ middle.crc32


def _gf2_times(matrix: Sequence[int], vector: int) -> int:
    total = 0
    i = 0
    while vector:
        if vector & 1:
            total ^= matrix[i]
        vector >>= 1
        i += 1
    return total


def _gf2_square(matrix: list[int]) -> list[int]:
    return [_gf2_times(matrix, row) for row in matrix]


def _zeros_operator(length: int) -> list[int]:
    """The operator taking crc(A) to crc(A + ``length`` zero bytes) without the final xor,
    as in zlib's crc32_combine: composed from squarings, O(log length) matrix products."""
    result = [1 << i for i in range(32)]  # identity
    odd = [0xEDB88320] + [1 << i for i in range(31)]  # one zero bit
    even = _gf2_square(odd)  # two zero bits
    odd = _gf2_square(even)  # four zero bits
    while length:
        even = _gf2_square(odd)  # a byte, then 4, 16... bytes
        if length & 1:
            result = [_gf2_times(even, column) for column in result]
        length >>= 1
        if not length:
            break
        odd = _gf2_square(even)
        if length & 1:
            result = [_gf2_times(odd, column) for column in result]
        length >>= 1
    return result


def _crc32_combine(crc1: int, crc2: int, length2: int) -> int:
    """zlib's crc32_combine: the CRC-32 of A + B from crc(A), crc(B) and len(B)."""
    return _gf2_times(_zeros_operator(length2), crc1) ^ crc2


class CompressedReports:
    """The last :data:`MAX_ENTRIES` reports compressed, by the id of the check that holds the text
    (a stored report never changes, so the id is a safe key)."""

    def __init__(self, max_entries: int = MAX_ENTRIES) -> None:
        self.max_entries = max_entries
        self._entries: OrderedDict[str, Compressed] = OrderedDict()
        self._lock = threading.Lock()

    def get(self, holder: str) -> Compressed | None:
        with self._lock:
            found = self._entries.get(holder)
            if found is not None:
                self._entries.move_to_end(holder)
            return found

    def put(self, holder: str, text: bytes) -> Compressed:
        entry = Compressed(compress_piece(text), zlib.crc32(text), len(text), tuple(_zeros_operator(len(text))))
        with self._lock:
            self._entries[holder] = entry
            self._entries.move_to_end(holder)
            while len(self._entries) > self.max_entries:
                self._entries.popitem(last=False)
        return entry
