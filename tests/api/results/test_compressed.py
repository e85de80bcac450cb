"""Reports compressed once and spliced into gzip'd answers."""

from __future__ import annotations

import gzip
import random
import zlib

import pytest
from apitools import TWO_LINKS, post_xml
from fastapi.testclient import TestClient

from api.results.compressed import CompressedReports, _crc32_combine, gzip_around


@pytest.mark.parametrize("sizes", [(0, 0), (1, 0), (0, 1), (7, 13), (1000, 70001), (65536, 3)])
def test_crc32_combine_equals_the_crc_of_the_whole(sizes: tuple[int, int]) -> None:
    rng = random.Random(sum(sizes))
    a, b = rng.randbytes(sizes[0]), rng.randbytes(sizes[1])
    assert _crc32_combine(zlib.crc32(a), zlib.crc32(b), len(b)) == zlib.crc32(a + b)


def test_spliced_gzip_is_one_valid_member() -> None:
    rng = random.Random(7)
    text = b'{"diagnostics":[' + b",".join(b'{"code":"GC%03d"}' % rng.randrange(1000) for _ in range(20000)) + b"]}"
    reports = CompressedReports()
    entry = reports.put("a", text)
    body = gzip_around(b'{"id":"x","report":', entry, b"}")
    assert gzip.decompress(body) == b'{"id":"x","report":' + text + b"}"
    assert len(body) < len(text) / 5
    # zlib's own gzip reader checks the CRC and length of the single member
    reader = zlib.decompressobj(16 + zlib.MAX_WBITS)
    assert reader.decompress(body) == b'{"id":"x","report":' + text + b"}" and reader.eof and not reader.unused_data


def test_the_lru_keeps_the_newest_entries() -> None:
    reports = CompressedReports(max_entries=2)
    for name in ("a", "b", "c"):
        reports.put(name, name.encode())
    assert reports.get("a") is None and reports.get("b") is not None and reports.get("c") is not None
    reports.get("b")
    reports.put("d", b"d")
    assert reports.get("c") is None and reports.get("b") is not None


def test_answers_read_the_same_gzipped_or_not(client: TestClient) -> None:
    zipped = post_xml(client, TWO_LINKS)
    assert zipped.headers["content-encoding"] == "gzip"
    plain = client.post(
        "/v1/checks",
        content=TWO_LINKS,
        headers={"content-type": "application/xml", "accept-encoding": "identity"},
    )
    assert "content-encoding" not in plain.headers
    a, b = zipped.json(), plain.json()
    assert b["cached_from"] == a["id"] and a["report"] == b["report"]
    again = post_xml(client, TWO_LINKS)  # from the compressed copy kept in memory
    assert again.headers["content-encoding"] == "gzip" and again.json()["report"] == a["report"]
