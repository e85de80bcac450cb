"""Hardened XML reading: no entities, no network, no DTD or external subset loading, size and depth limits.

Every XML file geomcheck reads (root documents, xacro includes, package manifests) goes
through :func:`read_file_bytes` and :func:`parse_bytes`. Malformed or hostile input becomes an
:class:`InputError` whose message is one line ``file:line:col: GC101 malformed-xml: reason``
and whose ``diagnostic`` is the GC101 finding at that location.
"""

from __future__ import annotations

import re
from pathlib import Path

from lxml import etree

from geomcheck.errors import InputError, LimitExceeded
from geomcheck.load.regular import read_regular_file
from geomcheck.model import SourceLocation
from geomcheck.rules.structure import MALFORMED_XML
from geomcheck.thresholds import LoadLimits

# A DOCTYPE with an internal subset that declares entities: the shape of every XML bomb.
_ENTITY_DECL = re.compile(rb"<!ENTITY", re.IGNORECASE)
_DOCTYPE = re.compile(rb"<!DOCTYPE", re.IGNORECASE)
# the version of an XML declaration at the start of a file (after a byte-order mark and blanks)
_DECLARED_VERSION = re.compile(rb"^(?:\xef\xbb\xbf)?\s*<\?xml\s+version\s*=\s*([\"'])([^\"']*)\1")
_XML_VERSION = re.compile(rb"1\.[0-9]+")


def malformed(display: str, reason: str, line: int | None = None, column: int | None = None) -> InputError:
    """An :class:`InputError` carrying the GC101 diagnostic at ``display:line:column``."""
    location = SourceLocation(display, line, column if line is not None else None)
    reason = " ".join(reason.split())
    diagnostic = MALFORMED_XML.diagnose(f"{display} is not well-formed XML: {reason}", location=location)
    return InputError(f"{location}: {MALFORMED_XML.code} {MALFORMED_XML.name}: {reason}", diagnostic)


class _NoExternalResources(etree.Resolver):  # type: ignore[misc]
    """Answers every external resource (a DOCTYPE's SYSTEM or PUBLIC identifier, an external
    entity) with an empty document. libxml2 opens the external subset's file even with
    ``load_dtd=False``: a FIFO or ``/dev/stdin`` there would block the parse, and whether the
    file exists would leak through the answer."""

    def resolve(self, system_url: str | None, public_id: str | None, context: object) -> object:
        return self.resolve_string("", context)


def _parser() -> etree.XMLParser:
    parser = etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_blank_text=False,
        collect_ids=False,
    )
    parser.resolvers.add(_NoExternalResources())
    return parser


def _line_col(data: bytes, offset: int) -> tuple[int, int]:
    line = data.count(b"\n", 0, offset) + 1
    return line, offset - (data.rfind(b"\n", 0, offset) + 1) + 1


def refuse_entities(data: bytes, display: str) -> None:
    """Raise GC101 when ``data`` has a DOCTYPE declaring entities (before parsing anything)."""
    doctype = _DOCTYPE.search(data)
    if doctype is None:
        return
    entity = _ENTITY_DECL.search(data, doctype.end())
    if entity is not None:
        line, col = _line_col(data, entity.start())
        raise malformed(display, "DOCTYPE declares entities; entity expansion is refused", line, col)


def check_depth(root: etree._Element, display: str, max_depth: int) -> None:
    """Raise :class:`LimitExceeded` (GC101) when elements nest deeper than ``max_depth`` levels."""
    deep = root.xpath(f"(//*[count(ancestor::*) >= {int(max_depth)}])[1]")
    if deep:
        element = deep[0]
        location = SourceLocation(display, element.sourceline)
        reason = f"elements nest deeper than the limit of {max_depth} levels"
        diagnostic = MALFORMED_XML.diagnose(f"{display}: {reason}", location=location)
        raise LimitExceeded(f"{location}: {MALFORMED_XML.code} {MALFORMED_XML.name}: {reason}", diagnostic)


def unsupported_version(data: bytes) -> str | None:
    """The version the file's XML declaration names when XML has no such version (``0.0``, as
    old exporters wrote), else ``None``."""
    found = _DECLARED_VERSION.match(data)
    if found is None or _XML_VERSION.fullmatch(found.group(2)):
        return None
    return found.group(2).decode("utf-8", errors="replace")


def version_as_1_0(data: bytes) -> bytes:
    """``data`` with its declaration's version read as ``1.0``, as TinyXML2 (urdfdom, Gazebo,
    MuJoCo) and expat (xacro) read a declaration of any version; other bytes unchanged."""
    found = _DECLARED_VERSION.match(data)
    assert found is not None
    return data[: found.start(2)] + b"1.0" + data[found.end(2) :]


def parse_bytes(data: bytes, display_name: str, limits: LoadLimits | None = None) -> etree._Element:
    """The root element of the XML document ``data``, parsed with the hardened parser.

    Raises :class:`InputError` (GC101, with line and column) on malformed XML or entity
    declarations and :class:`LimitExceeded` when ``limits`` are exceeded.
    """
    limits = limits or LoadLimits()
    if len(data) > limits.max_file_bytes:
        raise LimitExceeded(f"{display_name}: {len(data)} bytes exceeds the limit of {limits.max_file_bytes} bytes")
    refuse_entities(data, display_name)
    if unsupported_version(data) is not None:  # GC131 reports it; libxml2 alone refuses the file
        data = version_as_1_0(data)
    try:
        root = etree.fromstring(data, _parser())
    except etree.XMLSyntaxError as err:
        line, col = err.position if err.position else (None, None)
        message = err.msg or str(err)
        message = re.sub(r"\s*\(<string>, line \d+\)$", "", message)
        message = re.sub(r", line \d+, column \d+$", "", message)
        raise malformed(display_name, message, line, col if col else None) from None  # 1-based already
    if root is None:
        raise malformed(display_name, "document is empty", 1, 1)
    check_depth(root, display_name, limits.max_xml_depth)
    return root


def late_declaration_removed(data: bytes) -> bytes | None:
    """``data`` with its ``<?xml ...?>`` declaration blanked out when only comments and blank
    space stand before it (a licence comment written above the declaration: libxml2 rejects the
    file, TinyXML2 and so Gazebo read it), ``None`` when the declaration is not late. The
    declaration is replaced by spaces so that every line and column stays where it was."""
    start = data.find(b"<?xml")
    if start <= 0:
        return None
    before = data[:start]
    rest = before.strip()
    while rest.startswith(b"<!--"):
        end = rest.find(b"-->")
        if end < 0:
            return None
        rest = rest[end + 3 :].strip()
    if rest:
        return None
    end = data.find(b"?>", start)
    if end < 0:
        return None
    return data[:start] + b" " * (end + 2 - start) + data[end + 2 :]


def as_tinyxml_reads(data: bytes) -> tuple[bytes, tuple[str, ...]]:
    """``data`` as TinyXML2 (urdfdom, Gazebo, MuJoCo, PyBullet) reads it, and what it took
    (``late-declaration``, ``trailing-nul``; none: ``data`` unchanged): reading stops at the
    first NUL byte, so NULs after the last element end the text (one amid it is left for the
    parser to refuse), and a declaration after blank space or comments is accepted
    (:func:`late_declaration_removed`). Lines and columns stay where they were."""
    issues = []
    nul = data.find(b"\x00")
    if nul >= 0 and not data[nul:].strip(b"\x00 \t\r\n"):
        data = data[:nul]
        issues.append("trailing-nul")
    late = late_declaration_removed(data)
    if late is not None:
        data = late
        issues.append("late-declaration")
    return data, tuple(issues)


def read_file_bytes(path: Path, display_name: str, limits: LoadLimits | None = None) -> bytes:
    """The bytes of ``path`` after checking its size against the limit, before reading it.

    Raises :class:`InputError` when the file is missing, unreadable or not a regular file (a
    FIFO or a device is never opened: :func:`geomcheck.load.regular.read_regular_file`) and
    :class:`LimitExceeded` when it is larger than ``limits.max_file_bytes``.
    """
    limits = limits or LoadLimits()
    return read_regular_file(path, display_name, limits.max_file_bytes, "max_file_bytes")


def decode_text(data: bytes) -> str:
    """``data`` as text for excerpts and line searches (UTF-8, undecodable bytes replaced)."""
    return data.decode("utf-8", errors="replace")
