"""Frozen dataclasses of numbers and numpy arrays as cache payloads, without pickles.

A record is JSON (fields by name, tuples, dicts with any keys, numpy scalars with their
dtype) plus the arrays it holds, packed per dtype into one flat array each and stored as an
``.npz``: a result of a few dozen small arrays decodes with one archive read per dtype.
Only the classes the caller names are rebuilt; anything else (an unknown class, an object
array) is a :class:`TypeError` on encoding, so such a result is simply not cached. Floats
keep their exact value (JSON's shortest round-trip form), arrays their dtype and shape.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

from geomcheck.cache.store import decode_arrays, encode_arrays

if TYPE_CHECKING:
    import numpy as np

RECORD = "record"  # the JSON part, as bytes (uint8) [name in the archive]
ARRAYS = "arrays:"  # prefix of the packed arrays, one per dtype [name in the archive]


def class_name(cls: type) -> str:
    return f"{cls.__module__}:{cls.__qualname__}"


def encode_record(value: Any) -> bytes:
    """``value`` (plain data, numpy arrays and scalars, dataclasses of them) as bytes."""
    import numpy as np

    packed: dict[str, list[np.ndarray]] = {}
    sizes: dict[str, int] = {}

    def array(a: np.ndarray) -> dict[str, Any]:
        if a.dtype.hasobject:
            raise TypeError("cannot store an object array")
        dtype = a.dtype.str
        offset = sizes.get(dtype, 0)
        packed.setdefault(dtype, []).append(a.ravel())
        sizes[dtype] = offset + a.size
        return {"~a": [dtype, offset, list(a.shape)]}

    def enc(v: Any) -> Any:
        if v is None or isinstance(v, bool | str) or type(v) in (int, float):
            return v
        if isinstance(v, np.ndarray):
            return array(v)
        if isinstance(v, np.generic):
            return {"~n": [v.dtype.str, v.item()]}
        if isinstance(v, tuple):
            return {"~t": [enc(x) for x in v]}
        if isinstance(v, list):
            return [enc(x) for x in v]
        if isinstance(v, dict):
            return {"~d": [[enc(k), enc(x)] for k, x in v.items()]}
        if dataclasses.is_dataclass(v) and not isinstance(v, type):
            fields = {f.name: enc(getattr(v, f.name)) for f in dataclasses.fields(v)}
            return {"~c": class_name(type(v)), "f": fields}
        raise TypeError(f"cannot store a {type(v).__name__}")

    record = json.dumps(enc(value), separators=(",", ":"), ensure_ascii=False).encode("utf-8")
    arrays = {RECORD: np.frombuffer(record, dtype=np.uint8)}
    for dtype, parts in packed.items():
        arrays[ARRAYS + dtype] = np.concatenate(parts) if parts else np.zeros(0, dtype=dtype)
    return encode_arrays(arrays)


def decode_record(payload: bytes, classes: Iterable[type]) -> Any:
    """The value :func:`encode_record` stored; its dataclasses must be among ``classes``
    (:class:`ValueError` otherwise, or for a payload that is not a record)."""
    import numpy as np

    known: dict[Any, Any] = {class_name(cls): cls for cls in classes}
    arrays = decode_arrays(payload)
    data = json.loads(arrays.pop(RECORD).tobytes())

    def array(dtype: str, offset: int, shape: list[int]) -> np.ndarray:
        flat = arrays[ARRAYS + dtype]
        size = int(np.prod(shape, dtype=np.int64))
        if flat.dtype.str != dtype or offset < 0 or offset + size > flat.size:
            raise ValueError("array outside the packed data")
        return flat[offset : offset + size].reshape(shape)

    def dec(v: Any) -> Any:
        if isinstance(v, list):
            return [dec(x) for x in v]
        if not isinstance(v, dict):
            return v
        if "~a" in v:
            return array(*v["~a"])
        if "~n" in v:
            dtype, item = v["~n"]
            return np.dtype(dtype).type(item)
        if "~t" in v:
            return tuple(dec(x) for x in v["~t"])
        if "~d" in v:
            return {dec(k): dec(x) for k, x in v["~d"]}
        cls = known.get(v.get("~c"))
        if cls is None:
            raise ValueError(f"not a stored class: {v.get('~c')!r}")
        fields = v["f"]
        if set(fields) != {f.name for f in dataclasses.fields(cls)}:
            raise ValueError(f"fields of {cls.__name__} differ")
        obj = object.__new__(cls)
        for name, x in fields.items():
            object.__setattr__(obj, name, dec(x))  # as stored: no __init__ (frozen classes)
        return obj

    return dec(data)


__all__ = ["decode_record", "encode_record"]
