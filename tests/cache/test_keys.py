"""Cache keys: the libraries' versions read off the installed distributions' folders are the
versions ``importlib.metadata`` gives."""

from __future__ import annotations

from importlib import metadata

from geomcheck.cache.keys import RESULT_LIBRARIES, library_versions


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
