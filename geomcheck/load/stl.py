"""Binary STL read with numpy: triangles straight from the file's bytes, corners welded.

A binary STL is an 80-byte header, a little-endian ``uint32`` triangle count and 50 bytes
per triangle (normal, three corners as ``float32``, an attribute word). Reading it with one
``frombuffer`` costs a copy of the file; welding the repeated corners (every corner is
written once per triangle) makes the vertex array about six times smaller than the file.
"""

from __future__ import annotations

import numpy as np

HEADER_BYTES = 80
RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
# the constants of splitmix64's finaliser (Steele, Lea and Flood 2014): a bijection of 64-bit
# words whose every output bit depends on every input bit
MIX_SHIFTS = (np.uint64(30), np.uint64(27), np.uint64(31))
MIX_MULTIPLIERS = (np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB))


def binary_triangle_count(data: bytes) -> int | None:
    """Triangles in ``data`` when it is a well-formed binary STL (its size matches the count
    in its header), else ``None`` (ASCII STL, or a truncated or padded file)."""
    if len(data) < HEADER_BYTES + 4:
        return None
    count = int(np.frombuffer(data, dtype="<u4", count=1, offset=HEADER_BYTES)[0])
    return count if len(data) == HEADER_BYTES + 4 + count * RECORD.itemsize else None


def _mix(words: np.ndarray) -> np.ndarray:
    """splitmix64's finaliser of ``words`` (uint64), in place."""
    with np.errstate(over="ignore"):
        words ^= words >> MIX_SHIFTS[0]
        words *= MIX_MULTIPLIERS[0]
        words ^= words >> MIX_SHIFTS[1]
        words *= MIX_MULTIPLIERS[1]
        words ^= words >> MIX_SHIFTS[2]
    return words


def _row_hash(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bit patterns (n, c) of ``rows`` (n, c) of 4- or 8-byte items, and a 64-bit hash of each row (n,).

    Each column is mixed into the key through a bijection whose every output bit depends on
    every input bit: a linear combination (the columns' bits times odd constants, XORed) let
    a mirrored vertex's two sign bits cancel, and a symmetric part's rows shared a fourth as
    many keys as vertices, each shared key then sending the weld to its slow exact sort."""
    bits = rows.view(np.uint32 if rows.dtype.itemsize == 4 else np.uint64).reshape(len(rows), -1)
    key = np.zeros(len(rows), dtype=np.uint64)
    for column in range(bits.shape[1]):
        key ^= bits[:, column].astype(np.uint64)
        _mix(key)
    return bits, key


def first_indices(rows: np.ndarray) -> np.ndarray:
    """Indices (k,) of the first occurrence of each distinct row of ``rows`` (n, 3) (equal
    bit patterns), ascending: ``rows[first_indices(rows)]`` is the rows without repeats."""
    rows = np.ascontiguousarray(rows)
    if len(rows) == 0:
        return np.zeros(0, dtype=np.int64)
    bits, key = _row_hash(rows)
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    starts = np.ones(len(order), dtype=bool)
    starts[1:] = sorted_key[1:] != sorted_key[:-1]
    group = np.cumsum(starts) - 1
    if not np.array_equal(bits[order], bits[order[starts]][group]):
        _, first = np.unique(bits, axis=0, return_index=True)
        return np.sort(first)
    return np.sort(order[starts])


def weld_indices(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bitwise-equal rows of ``rows`` (n, c) grouped: ``(first (k,), index (n,))`` where
    ``rows[first]`` are the distinct rows in order of first appearance and
    ``rows[first][index] == rows``.

    Rows are grouped by a 64-bit hash of their bit patterns (one sort of n integers instead
    of a lexicographic sort of n rows); the grouping is then verified, and should two rows
    ever share a hash without being equal, the rows are sorted lexicographically instead.
    """
    rows = np.ascontiguousarray(rows)
    if len(rows) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    bits, key = _row_hash(rows)
    _, first, index = np.unique(key, return_index=True, return_inverse=True)
    if not np.array_equal(bits[first[index]], bits):
        _, first, index = np.unique(bits, axis=0, return_index=True, return_inverse=True)
    # renumber in order of first appearance: the same file always gives the same arrays
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return first[order], rank[index.reshape(-1)]


def weld(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bitwise-equal rows of ``corners`` (n, 3) merged: ``(vertices (k, 3), index (n,))`` with
    ``vertices[index] == corners``, vertices in order of first appearance."""
    first, index = weld_indices(corners)
    return np.asarray(corners)[first], index


def read_binary_stl(data: bytes) -> tuple[np.ndarray, np.ndarray] | None:
    """``(vertices (k, 3) float64, faces (m, 3) int64)`` of a binary STL, corners welded;
    ``None`` when ``data`` is not a well-formed binary STL."""
    count = binary_triangle_count(data)
    if count is None:
        return None
    records = np.frombuffer(data, dtype=RECORD, count=count, offset=HEADER_BYTES + 4)
    vertices, index = weld(records["corners"].reshape(-1, 3))
    return vertices.astype(np.float64), index.reshape(-1, 3).astype(np.int64)


__all__ = ["binary_triangle_count", "first_indices", "read_binary_stl", "weld", "weld_indices"]
