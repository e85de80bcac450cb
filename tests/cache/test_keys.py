"""Cache keys: the libraries' versions read off the installed distributions' folders are the
versions ``importlib.metadata`` gives; a key part's canonical form is plain JSON data, the same
for a value however its types are spelt."""

from __future__ import annotations

import enum
from importlib import metadata
from pathlib import PurePosixPath

import pytest

from geomcheck.cache.keys import RESULT_LIBRARIES, canonical, digest_key, library_versions
from geomcheck.model import Box, Mesh, Pose, Shape


def test_library_versions_are_those_importlib_metadata_gives() -> None:
    names = (*RESULT_LIBRARIES, "PyYAML", "no-such-distribution-of-geomcheck")
    expected = {}
    for name in names:
        try:
            expected[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            expected[name] = "absent"
    assert library_versions(names) == expected
    assert expected["numpy"] != "absent" and expected["no-such-distribution-of-geomcheck"] == "absent"


class Side(enum.IntEnum):
    LEFT = 1


class Label(str):
    pass


def test_canonical_data_of_dataclasses_enums_subclasses_paths_and_bytes() -> None:
    shape = Shape("collision", 2, Box((0.1, 0.2, 0.3)), Pose((0.0, 0.0, 0.5), (0.0, 0.0, 1.5)))
    key = (shape, Mesh("package://p/m.stl"), Side.LEFT, Label("x"), PurePosixPath("a/b"), b"ab", {3, 1}, {"k": [True]})
    assert canonical(key) == [
        {
            "kind": "collision",
            "index": 2,
            "geometry": {"size": [0.1, 0.2, 0.3], "ellipsoid": False},
            "origin": {"xyz": [0.0, 0.0, 0.5], "rpy": [0.0, 0.0, 1.5]},
            "name": None,
            "location": None,
        },
        {"filename": "package://p/m.stl", "scale": [1.0, 1.0, 1.0]},
        1,
        "x",
        "a/b",
        "fb8e20fc2e4c3f248c60c39bd652f3c1347298bb977b8b4d5903b85055620603",  # sha256 of b"ab"
        [1, 3],
        {"k": [True]},
    ]
    # an IntEnum and its value, a str subclass and a str give one key
    assert digest_key(Side.LEFT, Label("x")) == digest_key(1, "x")


def test_canonical_refuses_what_only_repr_could_spell() -> None:
    with pytest.raises(TypeError, match="cannot put a object in a cache key"):
        canonical((1, object()))
