"""The files of one xacro expansion: read through the sandbox and the size limit, parsed by the
hardened parser, legacy tags rewritten to ``xacro:``, and every element tagged with the file and
line it was read from."""

from __future__ import annotations

import errno
import hashlib
import xml.dom
import xml.dom.minidom
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import xacro
from lxml import etree

from geomcheck.errors import InputError, LimitExceeded, SandboxViolation
from geomcheck.load.bundle import Bundle
from geomcheck.load.legacy import (
    UNBOUND_PREFIX_NOTE,
    LegacyUse,
    declare_xacro_namespace,
    enclosing_macro,
    legacy_tag,
    namespace_problem,
)
from geomcheck.load.xmlsafe import decode_text, parse_bytes, read_file_bytes
from geomcheck.thresholds import LoadLimits

ORIGIN_KEY = "geomcheck.origin"


class _OriginHandler:
    """Carries an element's origin over to its copies (xacro clones macro bodies and blocks)."""

    def handle(self, operation: int, key: str, data: Any, src: Any, dst: Any) -> None:
        if dst is not None and operation in (
            xml.dom.UserDataHandler.NODE_CLONED,
            xml.dom.UserDataHandler.NODE_IMPORTED,
        ):
            dst.setUserData(key, data, self)


_ORIGIN_HANDLER = _OriginHandler()


class MissingInclude(FileNotFoundError):
    """An include that does not exist (an ``IOError`` so ``optional="true"`` includes work)."""

    def __str__(self) -> str:  # xacro appends str(exc) to its own message
        return ""


def dom_elements(node: xml.dom.minidom.Node | None) -> Iterator[xml.dom.minidom.Element]:
    """Elements under ``node`` (itself included) in document order."""
    stack = [node] if node is not None else []
    while stack:
        current = stack.pop()
        if current.nodeType == xml.dom.Node.ELEMENT_NODE:
            yield current  # type: ignore[misc]
        stack.extend(reversed(current.childNodes))


class XacroFiles:
    """The files an expansion reads, with the display name and the origin of each element."""

    def __init__(self, bundle: Bundle, limits: LoadLimits) -> None:
        self.bundle = bundle
        self.limits = limits
        self.sources: dict[str, str] = {}
        self.displayed: dict[str, str] = {}  # display path of each path asked about
        self.legacy: dict[str, LegacyUse] = {}
        self.files_read: dict[str, str | None] = {}
        self.original_parse: Callable[..., Any] = xacro.parse

    def display(self, path: str | Path) -> str:
        key = str(path)
        shown = self.displayed.get(key)
        if shown is None:
            shown = self.displayed[key] = self.bundle.display(Path(path))
        return shown

    def current_file(self) -> str:
        stack = xacro.filestack or []
        return self.display(stack[-1]) if stack and stack[-1] else self.display(self.bundle.root_file)

    def read(self, path: Path) -> tuple[bytes, str]:
        """Bytes and display name of ``path``, checked against the sandbox and the size limit."""
        display = self.display(path)
        resolved = self.bundle.check_access(path)
        if not resolved.is_file():
            self.files_read.setdefault(str(resolved), None)
            raise MissingInclude(errno.ENOENT, "No such file or directory", display)
        data = read_file_bytes(resolved, display, self.limits)
        self.files_read[str(resolved)] = hashlib.sha256(data).hexdigest()
        self.sources.setdefault(display, decode_text(data))
        return data, display

    def parse(self, inp: Any, filename: str | None = None) -> xml.dom.minidom.Document:
        """Replacement of ``xacro.parse``: hardened, sandboxed, legacy-aware, origin-tagging."""
        if inp is not None or filename is None:
            return self.original_parse(inp, filename)
        if len(xacro.filestack or []) > self.limits.max_include_depth + 1:
            raise LimitExceeded(
                f"xacro includes nest deeper than the limit of {self.limits.max_include_depth} levels "
                f"(recursive include of {self.display(filename)}?)"
            )
        path = Path(filename).absolute()
        try:
            data, display = self.read(path)
        except SandboxViolation:
            xacro.filestack.pop()  # the includer is the file in error
            raise
        except MissingInclude as missing:
            xacro.filestack.pop()  # as xacro does: the includer is the file in error
            raise xacro.XacroException(f"No such file or directory: {self.display(path)}", exc=missing) from None
        first_read = display not in self.legacy
        root, data = self.parse_lxml(data, display)
        try:
            doc = xml.dom.minidom.parseString(data)
        except Exception as err:  # expat disagrees with lxml: report it as malformed
            raise InputError(f"{display}: GC101 malformed-xml: {err}") from None
        self.prepare(doc, root, display, first_read)
        return doc

    def parse_lxml(self, data: bytes, display: str) -> tuple[etree._Element, bytes]:
        try:
            return parse_bytes(data, display, self.limits), data
        except InputError as err:
            if "Namespace prefix xacro" not in str(err):
                raise
            fixed = declare_xacro_namespace(data)
            if fixed is None:
                raise
            root = parse_bytes(fixed, display, self.limits)
            self.legacy_use(display).namespace_note = UNBOUND_PREFIX_NOTE
            return root, fixed

    def legacy_use(self, display: str) -> LegacyUse:
        return self.legacy.setdefault(display, LegacyUse(display, self.bundle.identity(display)))

    def prepare(self, doc: xml.dom.minidom.Document, root: etree._Element, display: str, first_read: bool) -> None:
        """Rewrite legacy tags to ``xacro:`` and tag every other element with its origin.

        Legacy tags are counted on the ``first_read`` of a file only (files are often included
        several times)."""
        use = self.legacy_use(display)
        parsed = [e for e in root.iter() if isinstance(e.tag, str)]
        built = list(dom_elements(doc.documentElement))
        if len(parsed) != len(built):  # cannot happen for documents both parsers accept
            return
        uses_xacro = False
        for lx, dom in zip(parsed, built, strict=True):
            tag = legacy_tag(lx)
            if tag is not None:
                dom.tagName = dom.nodeName = f"xacro:{tag}"
                uses_xacro = True
                if first_read:  # a file included several times is counted once
                    use.add(tag, lx.sourceline, enclosing_macro(lx))
            elif dom.tagName.startswith("xacro:"):
                uses_xacro = True
            else:
                dom.setUserData(ORIGIN_KEY, (display, lx.sourceline), _ORIGIN_HANDLER)
        # a plain URDF that merely declares the prefix (often with a wrong URI) is not legacy
        note = namespace_problem(root) if uses_xacro else None
        if note is not None:
            use.namespace_note = note
        if use.tags and "xacro" not in root.nsmap and use.namespace_note is None:
            use.namespace_note = "no xmlns:xacro declaration"


__all__ = ["ORIGIN_KEY", "MissingInclude", "XacroFiles", "dom_elements"]
