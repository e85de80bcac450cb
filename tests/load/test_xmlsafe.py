"""Hardened XML: malformed input, entity bombs, size and depth limits (GC101)."""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from geomcheck.errors import InputError, LimitExceeded
from geomcheck.load.xmlsafe import parse_bytes, read_file_bytes, unsupported_version
from geomcheck.thresholds import LoadLimits

BILLION_LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
]>
<robot name="&lol3;"/>
"""


def test_malformed_xml_is_gc101_with_file_line_and_column() -> None:
    data = b'<?xml version="1.0"?>\n<robot name="r">\n  <link name="a">\n</robot>\n'
    with pytest.raises(InputError) as info:
        parse_bytes(data, "robots/r.urdf")
    message = str(info.value)
    assert message.startswith("robots/r.urdf:4:9: GC101 malformed-xml: ")
    assert "mismatch" in message
    assert "\n" not in message
    diagnostic = info.value.diagnostic
    assert diagnostic is not None
    assert (diagnostic.code, diagnostic.name, diagnostic.severity.value) == ("GC101", "malformed-xml", "error")
    assert (diagnostic.location.file, diagnostic.location.line, diagnostic.location.column) == ("robots/r.urdf", 4, 9)


def test_well_formed_xml_parses() -> None:
    root = parse_bytes(b'<robot name="r"><link name="a"/></robot>', "r.urdf")
    assert root.tag == "robot"
    assert root[0].get("name") == "a"


def test_billion_laughs_is_refused_before_parsing() -> None:
    started = time.perf_counter()
    with pytest.raises(InputError) as info:
        parse_bytes(BILLION_LAUGHS, "lol.urdf")
    assert time.perf_counter() - started < 0.5
    assert (
        str(info.value) == "lol.urdf:3:2: GC101 malformed-xml: DOCTYPE declares entities; entity expansion is refused"
    )
    assert info.value.diagnostic is not None and info.value.diagnostic.location.line == 3


def test_doctype_without_entities_is_accepted() -> None:
    root = parse_bytes(b'<?xml version="1.0"?>\n<!DOCTYPE robot>\n<robot name="r"/>', "r.urdf")
    assert root.get("name") == "r"


def test_external_entity_is_not_resolved() -> None:
    data = b'<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n<robot name="&x;"/>'
    with pytest.raises(InputError, match="GC101"):
        parse_bytes(data, "xxe.urdf")


def test_depth_limit() -> None:
    deep = b"<robot>" + b"<a>" * 40 + b"</a>" * 40 + b"</robot>"
    with pytest.raises(LimitExceeded) as info:
        parse_bytes(deep, "deep.urdf", LoadLimits(max_xml_depth=30))
    assert "nest deeper than the limit of 30 levels" in str(info.value)
    assert info.value.diagnostic is not None and info.value.diagnostic.code == "GC101"
    assert parse_bytes(deep, "deep.urdf", LoadLimits(max_xml_depth=64)).tag == "robot"


def test_size_is_checked_before_reading(tmp_path: Path) -> None:
    big = tmp_path / "big.urdf"
    with big.open("wb") as handle:
        handle.write(b"<robot>")
        handle.truncate(200 * 1024 * 1024)  # sparse: nothing is written
    started = time.perf_counter()
    with pytest.raises(LimitExceeded) as info:
        read_file_bytes(big, "big.urdf")
    assert time.perf_counter() - started < 0.5
    assert str(info.value) == ("big.urdf: file of 209715200 bytes exceeds the limit of 52428800 bytes (max_file_bytes)")


def test_missing_file_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match=r"no such file: nothing\.urdf"):
        read_file_bytes(tmp_path / "nothing.urdf", "nothing.urdf")


@pytest.mark.parametrize("version", ["0.0", "2.0", "1"])
def test_a_declaration_of_a_version_xml_does_not_have_is_read_as_1_0(version: str) -> None:
    """libxml2 refuses 'Unsupported version'; TinyXML2 (urdfdom, Gazebo, MuJoCo) and expat
    (xacro) read the file, and so does geomcheck, GC131 reporting the declaration."""
    data = f'<?xml version="{version}" ?>\n<robot name="r">\n  <link name="a"/>\n</robot>\n'.encode()
    assert unsupported_version(data) == version
    root = parse_bytes(data, "r.urdf")
    assert (root.tag, root[0].get("name"), root[0].sourceline) == ("robot", "a", 3)


@pytest.mark.parametrize(
    "data",
    [
        b'<?xml version="1.0"?><robot/>',
        b"<?xml version='1.1'?><robot/>",
        b"<robot/>",
        b'\xef\xbb\xbf<?xml version="1.0"?><r/>',
    ],
)
def test_xml_1_x_and_no_declaration_are_not_unsupported(data: bytes) -> None:
    assert unsupported_version(data) is None
