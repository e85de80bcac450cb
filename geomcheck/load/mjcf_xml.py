"""The XML of an MJCF description read alongside MuJoCo's compiler: the elements of bodies,
geoms, joints and excludes with the file each was read from, ``<include>`` files spliced in
MuJoCo's order, so findings point at the ``file:line`` the author wrote."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from lxml import etree

from geomcheck.errors import InputError
from geomcheck.load.xmlsafe import decode_text, parse_bytes, read_file_bytes

if TYPE_CHECKING:
    from geomcheck.load.bundle import Bundle
    from geomcheck.thresholds import LoadLimits


@dataclass
class XmlBody:
    element: etree._Element | None
    file: str
    geoms: list[tuple[etree._Element, str]] = field(default_factory=list)
    joints: list[tuple[etree._Element, str]] = field(default_factory=list)


@dataclass
class XmlModel:
    """The MJCF elements as MuJoCo orders them: bodies depth first (the world body first)."""

    bodies: list[XmlBody]
    excludes: list[tuple[etree._Element, str]]
    compiler: dict[str, str]
    sources: dict[str, str]  # display path -> text of every file read, root first
    files: list[tuple[etree._Element, str, Path]]  # elements naming a file, with their own file's folder


class XmlReader:
    """Reads the root file and its ``<include>`` files (relative to the root file's folder, as
    MuJoCo resolves them), each once, through the bundle's sandbox and limits."""

    def __init__(self, bundle: Bundle, limits: LoadLimits) -> None:
        self.bundle = bundle
        self.limits = limits
        self.sources: dict[str, str] = {}
        self.files: list[tuple[etree._Element, str, Path]] = []
        self.depth = 0

    def parse(self, path: Path, data: bytes | None = None) -> tuple[etree._Element, str]:
        display = self.bundle.display(path)
        path = self.bundle.check_access(path)
        if data is None:
            data = read_file_bytes(path, display, self.limits)
        self.sources.setdefault(display, decode_text(data))
        return parse_bytes(data, display, self.limits), display

    def children(self, element: etree._Element, file: str) -> Iterator[tuple[etree._Element, str]]:
        """Child elements of ``element`` with ``<include>`` replaced by the included file's children."""
        for child in element:
            if not isinstance(child.tag, str):
                continue  # comments, processing instructions
            if child.tag == "include" and child.get("file"):
                if self.depth > self.limits.max_xml_depth:
                    raise InputError(f"{file}:{child.sourceline}: <include> nested deeper than {self.depth} files")
                self.depth += 1
                included, display = self.parse(self.bundle.root_file.parent / child.get("file", ""))
                yield from self.children(included, display)
                self.depth -= 1
                continue
            yield child, file


def read_xml(bundle: Bundle, limits: LoadLimits, data: bytes) -> XmlModel:
    """The body, geom, joint and exclude elements of the MJCF bundle in MuJoCo's order."""
    reader = XmlReader(bundle, limits)
    root, root_display = reader.parse(bundle.root_file, data)
    bodies = [XmlBody(None, root_display)]
    excludes: list[tuple[etree._Element, str]] = []
    compiler: dict[str, str] = {}
    files: list[tuple[etree._Element, str, Path]] = []

    def visit(element: etree._Element, file: str, body: XmlBody, in_world: bool) -> None:
        for child, child_file in reader.children(element, file):
            tag = child.tag
            if child.get("file") is not None:
                files.append((child, tag, (bundle.root_file.parent)))
            if tag == "compiler":
                compiler.update({k: v for k, v in child.attrib.items()})
            elif tag == "worldbody":
                visit(child, child_file, bodies[0], True)
            elif tag == "exclude":
                excludes.append((child, child_file))
            elif in_world and tag == "body":
                inner = XmlBody(child, child_file)
                bodies.append(inner)
                visit(child, child_file, inner, True)
            elif in_world and tag == "frame":
                visit(child, child_file, body, True)
            elif in_world and tag == "geom":
                body.geoms.append((child, child_file))
            elif in_world and tag in ("joint", "freejoint"):
                body.joints.append((child, child_file))
            elif not in_world:
                visit(child, child_file, body, False)

    visit(root, root_display, bodies[0], False)
    return XmlModel(bodies, excludes, compiler, reader.sources, files)


__all__ = ["XmlBody", "XmlModel", "XmlReader", "read_xml"]
