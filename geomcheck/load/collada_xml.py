"""The XML side of the COLLADA reader (:mod:`geomcheck.load.collada`): the document parsed as
hostile input, its elements looked up as pycollada looks them up, its numbers parsed as
pycollada parses them.

pycollada names every element it reads in the namespace of the root element (whatever that
namespace is), reads number lists with ``numpy.fromstring(text, dtype, sep=" ")`` (float32 for
coordinates and transforms, int32 for indices) and fails, or drops the element, where numpy
cannot read a list to its end. The reader makes the same calls, so that every number it
reads is the one trimesh reads, bit for bit.
"""

from __future__ import annotations

import numpy as np
from lxml import etree

from geomcheck.errors import GeomcheckError
from geomcheck.load.xmlsafe import parse_bytes
from geomcheck.thresholds import LoadLimits

# pycollada opens a zip archive holding a .dae too: a file with an end-of-central-directory record
# where Python's zipfile looks for one (its last 22 bytes and the longest archive comment) is left
# to trimesh
ZIP_END_RECORD = b"PK\x05\x06"
ZIP_TAIL_BYTES = 22 + 0xFFFF
# the hardened parser's limits, with the size limit of a mesh file rather than of a description
LIMITS = LoadLimits(max_file_bytes=LoadLimits.max_mesh_bytes)


class Unsupported(Exception):
    """The document holds something the reader does not reproduce bit for bit, or something
    on which pycollada or trimesh fail or drop part of the scene: the caller reads the file
    through trimesh instead."""


class Dae:
    """A parsed COLLADA document, its elements named as pycollada names them."""

    def __init__(self, root: etree._Element) -> None:
        if not isinstance(root.tag, str) or "}" not in root.tag:
            # pycollada would look every element up in a namespace named after the root tag: none found
            raise Unsupported("the root element has no namespace")
        self.root = root
        self.namespace = root.tag.split("}")[0].lstrip("{")  # pycollada's own derivation
        self._paths: dict[str, str] = {}

    def tag(self, name: str) -> str:
        """The qualified tag of the COLLADA element ``name``."""
        return f"{{{self.namespace}}}{name}"

    def _path(self, path: str) -> str:
        qualified = self._paths.get(path)
        if qualified is None:
            qualified = "/".join(self.tag(step) for step in path.split("/"))
            self._paths[path] = qualified
        return qualified

    def find(self, node: etree._Element, path: str) -> etree._Element | None:
        """The first element at ``path`` (names separated by ``/``) below ``node``, or ``None``."""
        found: etree._Element | None = node.find(self._path(path))
        return found

    def findall(self, node: etree._Element, path: str) -> list[etree._Element]:
        """Every element at ``path`` below ``node``, in document order."""
        found: list[etree._Element] = node.findall(self._path(path))
        return found

    def local(self, node: etree._Element) -> str | None:
        """The name of ``node`` when it is a COLLADA element (in the document's namespace),
        else ``None`` (comments, processing instructions, foreign elements)."""
        tag = node.tag
        prefix = f"{{{self.namespace}}}"
        return tag[len(prefix) :] if isinstance(tag, str) and tag.startswith(prefix) else None

    def is_a(self, node: etree._Element, name: str) -> bool:
        """Whether ``node`` is the COLLADA element ``name`` (comments and processing
        instructions are no element)."""
        return bool(node.tag == self.tag(name))


def parse(data: bytes) -> Dae:
    """The COLLADA document ``data`` parsed with the hardened parser (no entities, no network,
    size and depth limits); :class:`Unsupported` where it cannot or should not be."""
    if ZIP_END_RECORD in data[-ZIP_TAIL_BYTES:]:
        raise Unsupported("a zip archive")
    try:
        root = parse_bytes(data, "COLLADA document", LIMITS)
    except GeomcheckError as err:
        raise Unsupported(str(err)) from None
    if root.getroottree().docinfo.doctype:
        # pycollada's parser expands the entities a document type declares, the hardened parser
        # refuses them: any declaration is left to trimesh
        raise Unsupported("a document type declaration")
    return Dae(root)


def numbers(text: str, dtype: type[np.floating] | type[np.integer]) -> np.ndarray | None:
    """The whitespace-separated numbers of ``text`` as pycollada reads them, flat (k,) of
    ``dtype``; ``None`` where numpy cannot read the text to its end (pycollada's
    ``DaeMalformedError``)."""
    try:
        return np.fromstring(text, dtype=dtype, sep=" ")
    except ValueError:
        return None


def guarded_numbers(text: str | None, dtype: type[np.floating] | type[np.integer]) -> np.ndarray:
    """The numbers of a ``<float_array>``, ``<p>`` or ``<vcount>`` as pycollada reads them:
    none for an empty or blank text (which numpy would read as one number), else
    :func:`numbers`; :class:`Unsupported` where those cannot be read."""
    if text is None or text.isspace():
        return np.array([], dtype=dtype)
    values = numbers(text, dtype)
    if values is None:
        raise Unsupported("a malformed number list")
    return values


__all__ = ["Dae", "Unsupported", "guarded_numbers", "numbers", "parse"]
