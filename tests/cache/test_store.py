"""The on-disk store: verified entries, atomic writes under concurrent processes, LRU cap."""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from geomcheck.cache import Store, active_store, open_store, using_store
from geomcheck.cache.keys import digest_key
from geomcheck.cache.store import (
    CACHE_DIR_ENV,
    CACHE_MAX_ENV,
    HEADER_MAGIC,
    TEMP_PREFIX,
    decode_json,
    default_cache_dir,
    default_max_bytes,
    encode_json,
)
from geomcheck.errors import UsageError

KEY = digest_key("test", 1)


def counting(calls: list[int], value: object):  # type: ignore[no-untyped-def]
    def compute() -> object:
        calls.append(1)
        return value

    return compute


def test_bytes_round_trip_and_counts(tmp_path: Path) -> None:
    store = Store(tmp_path)
    assert store.get_bytes("stage", KEY) is None
    store.put_bytes("stage", KEY, b"payload \x00\xff")
    assert store.get_bytes("stage", KEY) == b"payload \x00\xff"
    assert (store.hits, store.misses) == (1, 1)
    path = store.path("stage", KEY)
    assert path == tmp_path / "stage" / KEY[:2] / KEY
    assert path.read_bytes().startswith(HEADER_MAGIC)
    assert not [p for p in path.parent.iterdir() if p.name.startswith(TEMP_PREFIX)]


def test_get_or_compute_computes_once(tmp_path: Path) -> None:
    calls: list[int] = []
    for _ in range(3):
        value = Store(tmp_path).get_or_compute(
            "stage", {"mesh": "abc", "scale": [1, 1, 1]}, counting(calls, {"volume": 0.25}), encode_json, decode_json
        )
        assert value == {"volume": 0.25}
    assert len(calls) == 1


@pytest.mark.parametrize(
    "damage",
    [
        pytest.param(lambda raw: raw[:-3] + b"xyz", id="flipped-payload-bytes"),
        pytest.param(lambda raw: raw[: len(raw) // 2], id="truncated"),
        pytest.param(lambda raw: b"not a cache entry", id="foreign-file"),
        pytest.param(lambda raw: b"", id="empty"),
    ],
)
def test_corrupt_entry_is_recomputed_with_a_debug_line(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, damage: object
) -> None:
    store = Store(tmp_path)
    calls: list[int] = []
    parts = ["corrupt", 1]
    store.get_or_compute("stage", parts, counting(calls, [1, 2, 3]), encode_json, decode_json)
    path = store.path("stage", digest_key("stage", parts))
    path.write_bytes(damage(path.read_bytes()))  # type: ignore[operator]
    with caplog.at_level(logging.DEBUG, logger="geomcheck.cache"):
        value = store.get_or_compute("stage", parts, counting(calls, [1, 2, 3]), encode_json, decode_json)
    assert value == [1, 2, 3]
    assert len(calls) == 2
    lines = [r.getMessage() for r in caplog.records if r.name == "geomcheck.cache"]
    assert len(lines) == 1
    assert str(path) in lines[0] and "recomputing" in lines[0]
    # the recomputed result replaced the damaged entry
    assert Store(tmp_path).get_or_compute("stage", parts, counting(calls, None), encode_json, decode_json) == [1, 2, 3]
    assert len(calls) == 2


def test_payload_that_verifies_but_does_not_decode_is_recomputed(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    store = Store(tmp_path)
    key = digest_key("stage", "k")
    store.put_bytes("stage", key, b"{not json")  # a consistent entry written by something else
    calls: list[int] = []
    with caplog.at_level(logging.DEBUG, logger="geomcheck.cache"):
        assert store.get_or_compute("stage", "k", counting(calls, 7), encode_json, decode_json) == 7
    assert calls == [1]
    assert any("undecodable (JSONDecodeError" in r.getMessage() for r in caplog.records)
    assert store.get_bytes("stage", key) == b"7"


def test_arrays_round_trip_without_pickles(tmp_path: Path) -> None:
    store = Store(tmp_path)
    hull = np.arange(12, dtype=np.float64).reshape(4, 3) / 7
    faces = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int32)
    store.put_arrays("mesh", KEY, {"hull": hull, "faces": faces})
    back = store.get_arrays("mesh", KEY)
    assert back is not None
    np.testing.assert_array_equal(back["hull"], hull)
    assert back["faces"].dtype == np.int32 and back["faces"].tolist() == [[0, 1, 2], [0, 2, 3]]
    with pytest.raises(ValueError, match="allow_pickle=False"):
        store.put_arrays("mesh", KEY, {"objects": np.array([object()])})
    store.put_bytes("mesh", KEY, b"PK not an npz")
    assert store.get_arrays("mesh", KEY) is None
    assert not store.path("mesh", KEY).exists()


def test_names_cannot_leave_the_store(tmp_path: Path) -> None:
    store = Store(tmp_path)
    with pytest.raises(ValueError, match="namespace"):
        store.path("../up", KEY)
    with pytest.raises(ValueError, match="hex digest"):
        store.path("stage", "../../etc/passwd")


def _age(path: Path, seconds_ago: float) -> None:
    moment = time.time() - seconds_ago
    os.utime(path, (moment, moment))


def test_least_recently_used_entries_are_evicted(tmp_path: Path) -> None:
    payload = b"x" * 1000
    store = Store(tmp_path, max_bytes=10**9)
    keys = [digest_key("lru", i) for i in range(6)]
    for age, key in zip((600, 500, 400, 300, 200, 100), keys, strict=True):
        store.put_bytes("lru", key, payload)
        _age(store.path("lru", key), age)
    assert store.get_bytes("lru", keys[0]) == payload  # the oldest is used again: now the most recent
    entry = store.path("lru", keys[0]).stat().st_size
    capped = Store(tmp_path, max_bytes=4 * entry)
    assert capped.evict() == 3  # down to 90% of the cap: three entries
    left = [k for k in keys if capped.path("lru", k).exists()]
    assert left == [keys[0], keys[4], keys[5]]
    assert capped.size() == 3 * entry
    assert capped.evict() == 0  # under the cap: nothing to do


def test_writes_past_a_sixteenth_of_the_cap_trigger_eviction(tmp_path: Path) -> None:
    entry_bytes = 1000
    store = Store(tmp_path, max_bytes=8 * 1100)
    for i in range(30):
        store.put_bytes("many", digest_key("many", i), b"y" * entry_bytes)
    assert store.size() <= store.max_bytes


def test_stale_temporary_files_are_removed(tmp_path: Path) -> None:
    store = Store(tmp_path)
    store.put_bytes("stage", KEY, b"1")
    stale = store.path("stage", KEY).parent / f"{TEMP_PREFIX}dead"
    fresh = store.path("stage", KEY).parent / f"{TEMP_PREFIX}writing"
    stale.write_bytes(b"half")
    fresh.write_bytes(b"half")
    _age(stale, 7200)
    assert store.evict() == 1
    assert not stale.exists() and fresh.exists() and store.get_bytes("stage", KEY) == b"1"


HAMMER = """
import sys
from pathlib import Path
from geomcheck.cache.keys import digest_key
from geomcheck.cache.store import Store

root, worker, rounds = Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
store = Store(root)
for i in range(rounds):
    shared = digest_key("shared", i % 5)
    store.put_bytes("race", shared, (f"shared {i % 5} " * 2000).encode())
    store.put_bytes("race", digest_key("own", worker, i), f"worker {worker} round {i}".encode())
    got = store.get_bytes("race", shared)
    if got is not None and got != (f"shared {i % 5} " * 2000).encode():
        sys.exit(f"worker {worker} read a wrong entry in round {i}")
"""


def test_concurrent_processes_never_see_half_an_entry(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    rounds = 40
    workers = [
        subprocess.Popen([sys.executable, "-c", HAMMER, str(tmp_path), str(w), str(rounds)], stderr=subprocess.PIPE)
        for w in range(3)
    ]
    errors = [p.communicate(timeout=120)[1].decode() for p in workers]
    assert [p.returncode for p in workers] == [0, 0, 0], errors
    store = Store(tmp_path)
    with caplog.at_level(logging.DEBUG, logger="geomcheck.cache"):
        for i in range(5):
            assert store.get_bytes("race", digest_key("shared", i)) == (f"shared {i} " * 2000).encode()
        for w in range(3):
            for i in range(rounds):
                assert store.get_bytes("race", digest_key("own", w, i)) == f"worker {w} round {i}".encode()
    assert not caplog.records  # no entry was corrupt
    assert not [p for p, _ in store.entries() if p.name.startswith(TEMP_PREFIX)]


def test_location_and_cap_from_the_environment(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(CACHE_DIR_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_dir() == tmp_path / "xdg" / "geomcheck"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/ignored")  # the XDG spec: relative paths are invalid
    assert default_cache_dir() == Path.home() / ".cache" / "geomcheck"
    monkeypatch.setenv(CACHE_DIR_ENV, str(tmp_path / "explicit"))
    assert default_cache_dir() == tmp_path / "explicit"
    monkeypatch.setenv(CACHE_MAX_ENV, "2.5")
    assert default_max_bytes() == int(2.5 * 1024 * 1024)
    assert open_store().max_bytes == int(2.5 * 1024 * 1024)
    monkeypatch.setenv(CACHE_MAX_ENV, "lots")
    with pytest.raises(UsageError, match="GEOMCHECK_CACHE_MAX_MB must be a number of mebibytes, got 'lots'"):
        default_max_bytes()


def test_unwritable_store_only_costs_time(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    store = Store(blocker / "cache")
    calls: list[int] = []
    assert store.get_or_compute("stage", 1, counting(calls, 5), encode_json, decode_json) == 5
    assert store.get_or_compute("stage", 1, counting(calls, 5), encode_json, decode_json) == 5
    assert len(calls) == 2


def test_active_store_is_scoped(tmp_path: Path) -> None:
    assert active_store() is None
    store = Store(tmp_path)
    with using_store(store):
        assert active_store() is store
        with using_store(None):
            assert active_store() is None
        assert active_store() is store
    assert active_store() is None


def test_a_stage_caches_arrays_through_the_active_store(tmp_path: Path) -> None:
    from geomcheck.cache import cached_arrays

    calls: list[int] = []

    def analyse() -> dict[str, np.ndarray]:
        calls.append(1)
        return {"hull": np.eye(3) * 0.5, "aabb": np.array([[-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]])}

    key = {"mesh_sha256": "ab" * 32, "scale": (0.001, 0.001, 0.001)}
    assert cached_arrays("mesh-analysis", key, analyse)["aabb"][1].tolist() == [1.0, 2.0, 3.0]  # no store: computed
    store = Store(tmp_path)
    with using_store(store):
        first = cached_arrays("mesh-analysis", key, analyse)
        again = cached_arrays("mesh-analysis", key, analyse)
        other_scale = cached_arrays("mesh-analysis", {**key, "scale": (1.0, 1.0, 1.0)}, analyse)
    assert len(calls) == 3  # uncached, first, other scale
    np.testing.assert_array_equal(again["hull"], first["hull"])
    assert again["aabb"].tolist() == [[-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]] == other_scale["aabb"].tolist()
    assert (store.hits, store.misses) == (1, 2)


def _hostile_entry(tmp_path: Path, kind: str) -> tuple[Store, list[int], object]:
    """A store whose entry for ``["hostile", 1]`` was replaced by ``kind`` of file."""
    store = Store(tmp_path, max_bytes=64 * 1024)
    parts = ["hostile", 1]
    path = store.path("stage", digest_key("stage", parts))
    path.parent.mkdir(parents=True)
    if kind == "other-key":  # a valid entry, made for another key, copied under this one
        store.put_json("stage", digest_key("stage", ["other", 2]), ["the other result"])
        path.write_bytes(store.path("stage", digest_key("stage", ["other", 2])).read_bytes())
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "dev-zero":
        path.symlink_to("/dev/zero")
    elif kind == "link-to-valid":  # a link to a valid entry of this very key elsewhere
        elsewhere = Store(tmp_path / "elsewhere")
        elsewhere.put_json("stage", digest_key("stage", parts), ["linked"])
        path.symlink_to(elsewhere.path("stage", digest_key("stage", parts)))
    else:  # a regular file over the size cap
        path.write_bytes(b"x" * (128 * 1024))
    return store, [], parts


@pytest.mark.parametrize("kind", ["other-key", "fifo", "dev-zero", "link-to-valid", "oversized"])
def test_a_hostile_entry_is_never_used_and_never_blocks(tmp_path: Path, kind: str) -> None:
    import resource
    import signal

    store, calls, parts = _hostile_entry(tmp_path, kind)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # [KiB]
    previous = signal.signal(signal.SIGALRM, signal.default_int_handler)
    signal.alarm(10)  # a FIFO used to block the read for ever
    try:
        value = store.get_or_compute("stage", parts, counting(calls, ["computed"]), encode_json, decode_json)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert (value, len(calls)) == (["computed"], 1)  # recomputed, not taken from the file found
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - peak < 100 * 1024
    path = store.path("stage", digest_key("stage", parts))
    assert path.is_file() and not path.is_symlink()  # replaced by a sound entry
    assert Store(tmp_path, max_bytes=64 * 1024).get_json("stage", digest_key("stage", parts)) == ["computed"]
