"""Link fits kept in the cache: records decode to exactly what was stored, a warm check reads
every fit, and an edit fits again only the links it touched."""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from geomcheck.cache import Store, using_store
from geomcheck.cache.records import decode_record, encode_record
from geomcheck.geometry.fit_cache import NAMESPACE
from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions, Selection
from geomcheck.pipeline import run_check

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base"
BASE_BOX = '<box size="0.192 0.164 0.013" />'


@dataclass(frozen=True)
class Inner:
    points: np.ndarray
    weight: np.float64


@dataclass(frozen=True)
class Outer:
    inner: Inner | None
    table: dict[Any, Any]
    parts: tuple[Any, ...]


def test_a_record_decodes_to_the_same_values_dtypes_and_shapes() -> None:
    points = np.arange(12, dtype=np.float64).reshape(4, 3) / 7.0
    value = Outer(
        inner=Inner(points, np.float64(0.1)),
        table={("x", 1): -0.0, "inf": math.inf, "n": [np.int64(3), np.bool_(True), None]},
        parts=(np.zeros((0, 3), dtype=np.int64), np.array([1, 2], dtype=np.int32), "text", 2**40),
    )
    back = decode_record(encode_record(value), [Outer, Inner])
    assert type(back) is Outer and type(back.inner) is Inner
    assert back.inner.points.dtype == np.float64 and back.inner.points.shape == (4, 3)
    assert back.inner.points.tobytes() == points.tobytes()
    assert type(back.inner.weight) is np.float64 and back.inner.weight == 0.1
    assert back.table == {("x", 1): 0.0, "inf": math.inf, "n": [3, True, None]}
    assert math.copysign(1.0, back.table[("x", 1)]) == -1.0
    assert [type(v) for v in back.table["n"][:2]] == [np.int64, np.bool_]
    empty, small, text, big = back.parts
    assert empty.shape == (0, 3) and empty.dtype == np.int64
    assert small.dtype == np.int32 and small.tolist() == [1, 2]
    assert (text, big) == ("text", 2**40)


def test_a_record_of_an_unknown_class_or_objects_is_refused() -> None:
    payload = encode_record(Inner(np.ones(3), np.float64(1.0)))
    with pytest.raises(ValueError, match="not a stored class"):
        decode_record(payload, [Outer])
    with pytest.raises(TypeError, match="object array"):
        encode_record(Inner(np.array([object()]), np.float64(1.0)))
    with pytest.raises(TypeError, match="cannot store a set"):
        encode_record({"s": {1, 2}})


def fit_report(root: Path, store: Store | None) -> Any:
    options = CheckOptions(selection=Selection(select=("GC3",)))
    with using_store(store):
        report = run_check(make_bundle(root, display_root=root.parents[1]), options)
    return report.diagnostics, report.sections["links"]


def entries(store: Store) -> set[str]:
    folder = store.root / NAMESPACE
    return {p.name for p in folder.rglob("*") if p.is_file()} if folder.is_dir() else set()


def test_a_warm_check_reads_every_fit_and_an_edit_fits_one_link_again(tmp_path: Path) -> None:
    shutil.copytree(EXAMPLE, tmp_path / "pr2_base")
    root = tmp_path / "pr2_base" / "robots" / "pr2_base.urdf.xacro"
    store = Store(tmp_path / "cache")
    uncached = fit_report(root, None)
    assert fit_report(root, store) == uncached
    stored = entries(store)
    fitted = [entry["link"] for entry in uncached[1] if entry["union"] is not None]
    # links drawn alike share one fit: the base, the laser, the four casters, the eight wheels
    assert len(fitted) == 14 and len(stored) == 4
    hits = store.hits
    assert fit_report(root, store) == uncached
    assert store.hits > hits and entries(store) == stored

    base = tmp_path / "pr2_base" / "urdf" / "base.urdf.xacro"
    base.write_text(base.read_text().replace(BASE_BOX, '<box size="0.150 0.164 0.013" />'))
    edited = fit_report(root, None)
    assert edited != uncached
    assert fit_report(root, store) == edited
    assert len(entries(store) - stored) == 1  # the edited casters' one fit; the others were read
