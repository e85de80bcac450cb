"""The geometries of a COLLADA document as pycollada loads them and as trimesh makes meshes of them.

pycollada reads each ``<source>`` as float32 (NaN read as 0), shaped by the number of
``<param>`` of its accessor (the accessor's stride, offset and count are not read), each
primitive's ``<input>`` through ``<vertices>`` with their offsets into the rows of ``<p>``,
``<triangles>`` from their first ``<p>``, ``<polylist>`` and ``<polygons>`` fan-triangulated
(corners 0, i, i+1), and ``<lines>`` (which it checks, and trimesh then ignores). trimesh
makes one mesh per triangle primitive and geometry instance of the corners gathered triangle
by triangle, converted to float64 and welded as ``Trimesh.merge_vertices`` welds them: corners
whose position rounds alike to 1e-8, whose first texture coordinates (when a material is
bound to the primitive) round alike to 1e-4 and whose normals round alike to 1e-2 become one
vertex, in order of first appearance.

Whatever pycollada would drop or fail on (a source of names, an index past its source, a
comment among a mesh's children, triangle strips and fans, which the reader does not mirror)
raises :class:`~geomcheck.load.collada_xml.Unsupported`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from lxml import etree

from geomcheck.load.collada_xml import Dae, Unsupported, guarded_numbers, numbers
from geomcheck.load.stl import weld_indices

# trimesh's merge_vertices rounds positions, texture coordinates and normals to these many digits
DIGITS_VERTEX = 8  # trimesh's tol.merge = 1e-8 [file units]
DIGITS_UV = 4  # [texture units]
DIGITS_NORMAL = 2  # [unit vector components]
# weld keys are rounded to int64: larger scaled values would overflow the cast [scaled units]
KEY_LIMIT = 2.0**62
# the sources an input's values must fit, as pycollada checks them: semantic, components, every
# input of the semantic (else the first only)
TRIANGLE_CHECKS = (("VERTEX", 3, False), ("NORMAL", 3, False), ("TEXCOORD", 2, True))
TANGENT_CHECKS = (("TEXTANGENT", 3, True), ("TEXBINORMAL", 3, True))
CORNERS = {"triangles": 3, "lines": 2}  # index rows per primitive
Input = tuple[int, np.ndarray]  # offset into an index row, the source's values (k, components) float32
Inputs = dict[str | None, list[Input]]  # by semantic, each in pycollada's order
Scope = dict[str | None, "np.ndarray | dict[str, np.ndarray]"]  # sources and <vertices> by id


@dataclass(frozen=True, eq=False)
class Triangles:
    """One ``<triangles>``, ``<polylist>`` or ``<polygons>`` with at least one triangle: its
    ``material`` symbol, its ``inputs`` and ``index`` (m, 3, n) int32: triangle, corner,
    input offset."""

    material: str | None
    inputs: Inputs
    index: np.ndarray

    def corners(self, semantic: str) -> np.ndarray | None:
        """The values of the first input of ``semantic`` at every corner, triangle by
        triangle ((3m, components) float32), or ``None`` when there is no such input."""
        found = self.inputs.get(semantic)
        if not found:
            return None
        offset, values = found[0]
        corners: np.ndarray = values[self.index[:, :, offset]].reshape(-1, values.shape[1])
        return corners


@dataclass(frozen=True)
class Geometry:
    """A ``<geometry>``: its id (empty when it has none) and its triangle primitives in order."""

    id: str
    primitives: tuple[Triangles, ...]


def _source(dae: Dae, node: etree._Element) -> np.ndarray:
    """A ``<source>``'s values as pycollada reads them: (k, components) float32."""
    array = dae.find(node, "float_array")
    if array is None:
        raise Unsupported("a source that is not a float array")
    data = guarded_numbers(array.text, np.float32)
    data[np.isnan(data)] = 0
    names = [param.get("name") for param in dae.findall(node, "technique_common/accessor/param")]
    if not names:
        raise Unsupported("a source without accessor")
    if names == ["S", "T", "P"]:  # pycollada drops the third texture coordinate
        if data.size % 3:
            raise Unsupported("S, T, P texture coordinates that are not whole")
        data, names = data.reshape(-1, 3)[:, :2].reshape(-1), ["S", "T"]
    if data.size % len(names):
        raise Unsupported("a source that is not whole rows")
    return data.reshape(-1, len(names))


def _vertices(dae: Dae, node: etree._Element, scope: Scope) -> None:
    """Record a ``<vertices>`` in ``scope``: its inputs' sources by semantic."""
    inputs: dict[str, np.ndarray] = {}
    for element in dae.findall(node, "input"):
        semantic, source = element.get("semantic"), element.get("source")
        if not semantic or not source or not source.startswith("#"):
            raise Unsupported("a <vertices> input pycollada refuses")
        values = scope.get(source[1:])
        if not isinstance(values, np.ndarray):
            raise Unsupported("a <vertices> input without its source")
        inputs[semantic] = values
    identifier = node.get("id")
    if not identifier or "POSITION" not in inputs:
        raise Unsupported("a <vertices> without id or position")
    scope[identifier] = inputs


def _inputs(dae: Dae, node: etree._Element, scope: Scope) -> Inputs:
    """A primitive's inputs as pycollada collects them: an input naming a ``<vertices>``
    stands for that element's inputs (``POSITION`` as ``VERTEX``), at its own offset."""
    declared = []
    for element in dae.findall(node, "input"):
        offset = element.get("offset")
        try:
            declared.append((int(offset or ""), element.get("semantic"), element.get("source")))
        except ValueError:
            raise Unsupported("an input without a whole offset") from None
    inputs: Inputs = {}
    for offset, semantic, source in declared:
        if offset < 0 or source is None:
            raise Unsupported("a negative offset or an input without source")
        found = scope.get(source[1:])
        if semantic == "VERTEX" and isinstance(found, dict):
            for inner, values in found.items():
                inputs.setdefault("VERTEX" if inner == "POSITION" else inner, []).append((offset, values))
        elif isinstance(found, np.ndarray) and source.startswith("#"):
            inputs.setdefault(semantic, []).append((offset, found))
        elif not isinstance(found, dict):
            raise Unsupported("an input without its source")
        # another input naming a <vertices>: pycollada skips it
    return inputs


def _width(inputs: Inputs) -> int:
    """Indices per corner (the largest input offset plus one); :class:`Unsupported` without a
    ``VERTEX`` input."""
    if not inputs.get("VERTEX"):
        raise Unsupported("a primitive without positions")
    return 1 + max(offset for found in inputs.values() for offset, _ in found)


def _check_sources(inputs: Inputs, index: np.ndarray, checks: tuple[tuple[str, int, bool], ...]) -> None:
    """pycollada's checks of a non-empty primitive: each checked input's source has as many
    components as its semantic needs and a value for the largest index into it."""
    for semantic, components, every in checks:
        found = inputs.get(semantic, [])
        for offset, values in found if every else found[:1]:
            if values.shape[1] != components or len(values) <= index[..., offset].max():
                raise Unsupported(f"a {semantic} source that does not fit its indices")


def _triangle_set(inputs: Inputs, index: np.ndarray, material: str | None) -> Triangles | None:
    """A triangle primitive of ``index`` (m, 3, n) int32 and ``inputs``, checked as pycollada
    and trimesh read it; ``None`` when it has no triangle (trimesh skips it)."""
    if not len(index):
        return None
    if index.min() < 0:
        raise Unsupported("a negative index")
    _check_sources(inputs, index, TRIANGLE_CHECKS + TANGENT_CHECKS)
    colors = inputs.get("COLOR")
    if colors and len(colors[0][1]) <= index[:, :, colors[0][0]].max():
        raise Unsupported("a color index past its source")  # trimesh gathers the first color set
    return Triangles(material, inputs, index)


def _triangles(dae: Dae, node: etree._Element, scope: Scope) -> Triangles | None:
    """A ``<triangles>``: the rows of its first ``<p>``."""
    rows = dae.findall(node, "p")
    if not rows:
        raise Unsupported("triangles without <p>")
    inputs = _inputs(dae, node, scope)
    index = guarded_numbers(rows[0].text, np.int32)
    width = _width(inputs)
    if index.size % (CORNERS["triangles"] * width):
        raise Unsupported("an index that is not whole triangles")
    return _triangle_set(inputs, index.reshape(-1, CORNERS["triangles"], width), node.get("material"))


def _fan(rows: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The triangles of polygons of ``counts`` (p,) corners >= 3 over ``rows`` (r, n), their
    sum: each polygon's corners 0, i, i+1 for i = 1..k-2, in pycollada's order; (t, 3, n)."""
    counts = counts.astype(np.int64)
    per_polygon = counts - 2
    first = np.repeat(np.cumsum(counts) - counts, per_polygon)
    step = np.arange(per_polygon.sum()) - np.repeat(np.cumsum(per_polygon) - per_polygon, per_polygon)
    fanned: np.ndarray = rows[np.stack([first, first + step + 1, first + step + 2], axis=1)]
    return fanned


def _polygon_set(inputs: Inputs, index: np.ndarray, counts: np.ndarray, material: str | None) -> Triangles | None:
    """The fan triangles of polygons of ``counts`` corners over ``index`` (flat int32), as
    pycollada's ``Polylist.triangleset`` makes them."""
    width = _width(inputs)
    if index.size % width:
        raise Unsupported("an index that is not whole corners")
    rows = index.reshape(-1, width)
    if not len(rows) and not len(counts):
        return None
    if not len(counts) or counts.min() < 3 or counts.sum(dtype=np.int64) != len(rows):
        raise Unsupported("polygon sizes that do not match the index")
    return _triangle_set(inputs, _fan(rows, counts), material)


def _polylist(dae: Dae, node: etree._Element, scope: Scope) -> Triangles | None:
    """A ``<polylist>``: its first ``<vcount>`` and ``<p>``."""
    index, counts = dae.find(node, "p"), dae.find(node, "vcount")
    if index is None or counts is None:
        raise Unsupported("a polylist without <p> or <vcount>")
    sizes = guarded_numbers(counts.text, np.int32)
    inputs = _inputs(dae, node, scope)
    return _polygon_set(inputs, guarded_numbers(index.text, np.int32), sizes, node.get("material"))


def _polygons(dae: Dae, node: etree._Element, scope: Scope) -> Triangles | None:
    """A ``<polygons>``: one polygon per ``<p>`` (holes, ``<ph>``, are not read by pycollada)."""
    polygons = []
    for element in dae.findall(node, "p"):
        values = numbers(element.text, np.int32) if element.text is not None else None
        if values is None:
            raise Unsupported("a polygon pycollada cannot read")
        polygons.append(values)
    inputs = _inputs(dae, node, scope)
    width = _width(inputs)
    if any(len(polygon) % width for polygon in polygons):
        raise Unsupported("a polygon that is not whole corners")
    counts = np.array([len(polygon) // width for polygon in polygons], dtype=np.int32)
    index = np.concatenate(polygons) if polygons else np.array([], dtype=np.int32)
    return _polygon_set(inputs, index, counts, node.get("material"))


def _lines(dae: Dae, node: etree._Element, scope: Scope) -> None:
    """Check a ``<lines>`` loads in pycollada (trimesh makes nothing of it)."""
    element = dae.find(node, "p")
    if element is None:
        raise Unsupported("lines without <p>")
    inputs = _inputs(dae, node, scope)
    index = guarded_numbers(element.text, np.int32)
    width = _width(inputs)
    if index.size % (CORNERS["lines"] * width):
        raise Unsupported("an index that is not whole lines")
    if index.size:
        _check_sources(inputs, index.reshape(-1, CORNERS["lines"], width), TRIANGLE_CHECKS)


PRIMITIVES: dict[str, Callable[[Dae, etree._Element, Scope], Triangles | None]] = {
    "triangles": _triangles,
    "polylist": _polylist,
    "polygons": _polygons,
    "lines": _lines,
}


def _geometry(dae: Dae, node: etree._Element, mesh: etree._Element) -> Geometry:
    """A ``<geometry>`` with its ``<mesh>``, loaded whole or :class:`Unsupported`."""
    scope: Scope = {}
    vertices = None
    primitives = []
    for child in mesh:
        if dae.is_a(child, "source"):
            scope[child.get("id")] = _source(dae, child)
        elif dae.is_a(child, "vertices"):
            vertices = child  # the last one counts
        elif any(dae.is_a(child, name) for name in PRIMITIVES):
            primitives.append(child)
        elif not dae.is_a(child, "extra"):
            # triangle strips and fans (not mirrored), or what pycollada drops the geometry for
            # (any other element, a comment, a processing instruction)
            raise Unsupported("a mesh child the reader does not mirror")
    if vertices is not None:
        _vertices(dae, vertices, scope)
    loaded = (PRIMITIVES[str(dae.local(child))](dae, child, scope) for child in primitives)
    return Geometry(node.get("id") or "", tuple(p for p in loaded if p is not None))


def load_geometries(dae: Dae) -> dict[str, Geometry]:
    """The document's ``<mesh>`` geometries by id, as pycollada indexes them (the last of an
    id wins; a geometry of another kind is skipped); :class:`Unsupported` where one would not
    load whole."""
    found = {}
    for node in dae.findall(dae.root, "library_geometries/geometry"):
        mesh = dae.find(node, "mesh")
        if mesh is not None:
            geometry = _geometry(dae, node, mesh)
            found[geometry.id] = geometry
    return found


def welded(triangles: Triangles, textured: bool) -> tuple[np.ndarray, np.ndarray]:
    """The mesh trimesh makes of ``triangles``: vertices (n, 3) float64 [file units] and faces
    (m, 3) int64, corners welded on position, on the first texture coordinates when
    ``textured`` (a material is bound to the primitive) and on the normals."""
    positions = triangles.corners("VERTEX")
    assert positions is not None  # a triangle primitive has positions
    vertices = positions.astype(np.float64)
    columns = [vertices * 10**DIGITS_VERTEX]
    uv = triangles.corners("TEXCOORD") if textured else None
    normals = triangles.corners("NORMAL")
    if uv is not None:
        columns.append(uv.astype(np.float64) * 10**DIGITS_UV)
    if normals is not None:
        columns.append(normals.astype(np.float64) * 10**DIGITS_NORMAL)
    stacked = np.column_stack(columns)
    # trimesh drops corners that are not finite (and the triangles on them) before welding
    if not np.isfinite(stacked).all() or np.abs(stacked).max() >= KEY_LIMIT:
        raise Unsupported("corners that are not finite or beyond the weld's integers")
    first, inverse = weld_indices(stacked.round().astype(np.int64))  # trimesh's unique_rows(keep_order=True)
    return vertices[first], inverse.reshape(-1, 3).astype(np.int64)


__all__ = ["Geometry", "Triangles", "load_geometries", "welded"]
