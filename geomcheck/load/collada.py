"""COLLADA (``.dae``) triangles read with lxml and numpy, bit for bit as trimesh reads them.

trimesh loads a COLLADA file through pycollada and then flattens its scene
(:func:`geomcheck.load.meshes.geometry_only`); importing the two costs more than half a second
and pycollada's parse is slow. :func:`read_collada` gives the same vertices and faces without
either: the document is parsed as hostile input (:mod:`geomcheck.load.collada_xml`), its
geometries loaded and welded as trimesh welds them (:mod:`geomcheck.load.collada_geometry`),
its other libraries checked to load whole (:mod:`geomcheck.load.collada_assets`), and the
default visual scene walked as trimesh walks it:

- each ``<node>``'s transforms (``<matrix>``, ``<translate>``, ``<rotate>``, ``<scale>``) are
  composed in float32 in document order as pycollada composes them, and a malformed one is
  dropped as pycollada drops it;
- a node's matrix is ``np.dot(parent, node)`` in float64 from the identity down, as in
  trimesh's ``_parse_node``, and a geometry instance takes its parent node's;
- that matrix goes through trimesh's scene graph, which replaces a rotation part off by less than
  1e-5 by the nearest rotation (``fix_rigid``, an SVD);
- each triangle primitive of each instance becomes one welded mesh whose vertices are moved
  by ``trimesh.transformations.transform_points`` (left as they are when the matrix is within
  1e-8 of the identity), and the meshes are concatenated in scene order.

What pycollada drops without failing and the reader can tell exactly (a malformed transform,
an instance of a geometry that is not there) is dropped alike. Where the document holds
anything else the reader does not reproduce (``<lookat>``, instanced nodes, controllers,
animations, triangle strips, a geometry or material pycollada would drop or fail on, a
number it cannot read, more instanced vertices than :data:`MAX_INSTANCED_VERTICES`), it
returns ``None`` and the file is read through trimesh: the fast path never changes a result.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from lxml import etree

from geomcheck.load.collada_assets import material_ids
from geomcheck.load.collada_geometry import Geometry, Triangles, load_geometries, welded
from geomcheck.load.collada_xml import Dae, Unsupported, numbers, parse

# welded vertices summed over every geometry instance: a document instancing a large geometry
# many times is left to trimesh rather than multiplied here [vertices]
MAX_INSTANCED_VERTICES = 20_000_000
IDENTITY_TOLERANCE = 1e-8  # transform_points leaves points as they are within this of the identity [matrix entries]
# trimesh's scene graph (repair_rigid) replaces a rotation whose R R^T is off the identity by more
# than the first and less than the second by the nearest rotation (SVD) [matrix entries]
RIGID_EXACT = 1e-13
RIGID_REPAIR = 1e-5
BASE_FRAME = "world"  # the root of trimesh's scene graph: a geometry of this id would be the root itself
TRANSFORM_VALUES = {"translate": 3, "rotate": 4, "scale": 3, "matrix": 16}  # numbers of each transform
EYE = np.eye(4)  # trimesh's root matrix, float64
EYE.flags.writeable = False


@dataclass(frozen=True)
class Instance:
    """An ``<instance_geometry>``: the geometry and the material symbols bound to it."""

    geometry: Geometry
    symbols: frozenset[str | None]


@dataclass
class Node:
    """A ``<node>``: its composed transform (4, 4) float32 and its nodes and instances in order."""

    matrix: np.ndarray
    children: list[Node | Instance] = field(default_factory=list)


def _rotation(x: np.float32, y: np.float32, z: np.float32, angle: np.float32) -> np.ndarray:
    """pycollada's rotation of ``angle`` degrees about (x, y, z) (not normalised), its float32
    arithmetic unchanged: (4, 4) float32."""
    radians = angle * np.pi / 180.0
    c, s = np.cos(radians), np.sin(radians)
    t = 1 - c
    return np.array(
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0],
            [0, 0, 0, 1],
        ],
        dtype=np.float32,
    )


def _transform(kind: str, element: etree._Element) -> np.ndarray | None:
    """The (4, 4) float32 matrix of a ``<translate>``, ``<rotate>``, ``<scale>`` or ``<matrix>``
    as pycollada builds it; ``None`` when pycollada drops it (unreadable or miscounted numbers)."""
    if element.text is None:
        raise Unsupported("a transform without text")  # pycollada fails on it
    values = numbers(element.text, np.float32)
    if values is None or len(values) != TRANSFORM_VALUES[kind]:
        return None
    if kind == "matrix":
        return values.reshape(4, 4)
    if kind == "rotate":
        return _rotation(values[0], values[1], values[2], values[3])
    matrix = np.identity(4, dtype=np.float32)
    if kind == "translate":
        matrix[:3, 3] = [values[0], values[1], values[2]]
    else:
        matrix[0, 0], matrix[1, 1], matrix[2, 2] = values[0], values[1], values[2]
    return matrix


def _composed(transforms: list[np.ndarray]) -> np.ndarray:
    """A node's transforms composed as pycollada composes them: (4, 4) float32."""
    if len(transforms) == 1:
        return transforms[0].copy()
    matrix = np.identity(4, dtype=np.float32)
    for transform in transforms:  # float32 products, as many as pycollada makes
        matrix = np.dot(matrix, transform)
    return matrix


def _repaired(matrix: np.ndarray) -> np.ndarray:
    """``trimesh.transformations.fix_rigid(matrix, 1e-5)`` as trimesh's scene graph applies it
    to every geometry's transform, its arithmetic unchanged: (4, 4) float64."""
    rotation = matrix[:3, :3]
    check = np.abs(np.dot(rotation, rotation.T) - EYE[:3, :3]).max()
    if not RIGID_EXACT < check < RIGID_REPAIR:
        return matrix
    u, _, v = np.linalg.svd(rotation)
    repaired = np.eye(4)
    repaired[:3, :3] = np.dot(u, v)
    repaired[:3, 3] = matrix[:3, 3]
    if not np.allclose(repaired, matrix, atol=RIGID_REPAIR):
        raise Unsupported("a transform trimesh's repair fails on")  # an assertion in trimesh
    return repaired


def _moved(points: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """``trimesh.transformations.transform_points(points, matrix)``, its arithmetic unchanged:
    ``points`` (n, 3) float64 moved by ``matrix`` (4, 4) float64, C-contiguous."""
    if np.abs(matrix - EYE).max() < IDENTITY_TOLERANCE:
        return points.copy()
    stack = np.column_stack((points, np.ones(len(points))))
    return np.ascontiguousarray(np.dot(matrix, stack.T).T[:, :3])


class _Scene:
    """The default visual scene of a document, walked as trimesh walks it."""

    def __init__(self, dae: Dae) -> None:
        self.dae = dae
        self.materials = material_ids(dae)
        self.geometries = load_geometries(dae)
        self.meshes: dict[tuple[Triangles, bool], tuple[np.ndarray, np.ndarray]] = {}
        self.parts: list[tuple[np.ndarray, np.ndarray]] = []  # vertices moved into the scene, faces
        self.instanced = 0  # welded vertices placed so far

    def _instance(self, element: etree._Element) -> Instance | None:
        """An ``<instance_geometry>``, or ``None`` where pycollada drops it (a reference it
        cannot resolve to a geometry)."""
        url = element.get("url")
        if url is None:
            raise Unsupported("an instance without url")
        geometry = self.geometries.get(url[1:]) if url.startswith("#") else None
        if geometry is None:
            return None
        symbols = set()
        for bound in self.dae.findall(element, "bind_material/technique_common/instance_material"):
            target = bound.get("target")
            if target is None or not target.startswith("#") or target[1:] not in self.materials:
                raise Unsupported("a material binding pycollada drops the instance for")
            symbols.add(bound.get("symbol"))
        return Instance(geometry, frozenset(symbols))

    def node(self, element: etree._Element) -> Node:
        """A ``<node>`` as pycollada loads it: its transforms composed, its children in order
        (cameras, lights, extras and unknown elements, which trimesh makes nothing of, left out)."""
        transforms = []
        node = Node(np.identity(4, dtype=np.float32))
        for child in element:
            kind = self.dae.local(child)
            if kind == "node":
                node.children.append(self.node(child))
            elif kind in TRANSFORM_VALUES:
                matrix = _transform(kind, child)
                if matrix is not None:
                    transforms.append(matrix)
            elif kind == "instance_geometry":
                instance = self._instance(child)
                if instance is not None:
                    node.children.append(instance)
            elif kind in ("instance_camera", "instance_light") and child.get("url") is None:
                raise Unsupported("an instance without url")
            elif kind in ("lookat", "instance_controller", "instance_node"):
                raise Unsupported(f"a <{kind}>")
        if transforms:
            node.matrix = _composed(transforms)
        return node

    def _place(self, instance: Instance, matrix: np.ndarray) -> None:
        """Add the meshes of ``instance``'s triangle primitives, moved by ``matrix``."""
        if instance.geometry.primitives and instance.geometry.id == BASE_FRAME:
            raise Unsupported("a geometry named as trimesh's root frame")
        for triangles in instance.geometry.primitives:
            textured = triangles.material in instance.symbols and "TEXCOORD" in triangles.inputs
            key = (triangles, textured)
            if key not in self.meshes:  # welding does not depend on the instance's place
                self.meshes[key] = welded(triangles, textured)
            vertices, faces = self.meshes[key]
            self.instanced += len(vertices)
            if self.instanced > MAX_INSTANCED_VERTICES:
                raise Unsupported("too many instanced vertices")
            self.parts.append((_moved(vertices, _repaired(matrix)), faces))

    def walk(self, node: Node, parent: np.ndarray) -> None:
        """Place the instances below ``node``, whose parent's matrix is ``parent`` (4, 4) float64."""
        if not node.children:
            return
        matrix = np.dot(parent, node.matrix)  # trimesh's float64 product, the same for every child
        for child in node.children:
            if isinstance(child, Node):
                self.walk(child, matrix)
            else:
                self._place(child, matrix)

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """The default scene's meshes concatenated: vertices (n, 3) float64, faces (m, 3) int64."""
        scenes = {}
        for scene in self.dae.findall(self.dae.root, "library_visual_scenes/visual_scene"):
            # pycollada loads every scene: what fails in one fails the whole document
            scenes[scene.get("id")] = [self.node(child) for child in self.dae.findall(scene, "node")]
        default = self.dae.find(self.dae.root, "scene/instance_visual_scene")
        url = default.get("url") if default is not None else None
        if url is None or not url.startswith("#") or url[1:] not in scenes:
            raise Unsupported("no default scene")  # trimesh fails on a document without one
        for node in scenes[url[1:]]:
            self.walk(node, EYE)
        if not self.parts:
            return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
        counts = np.array([len(vertices) for vertices, _ in self.parts], dtype=np.int64)
        offsets = np.cumsum(counts) - counts
        vertices = np.vstack([vertices for vertices, _ in self.parts])
        faces = np.vstack([faces + offset for (_, faces), offset in zip(self.parts, offsets, strict=True)])
        return vertices, faces


def read_collada(data: bytes) -> tuple[np.ndarray, np.ndarray] | None:
    """The triangles trimesh reads from the COLLADA document ``data``, flattened as
    :func:`geomcheck.load.meshes.geometry_only` flattens them: vertices (n, 3) float64 [file
    units, the declared ``<unit>`` not applied] and faces (m, 3) int64, both empty when the
    default scene places no triangle; ``None`` when the document uses something this reader
    does not reproduce bit for bit (the caller reads it through trimesh)."""
    try:
        return _Scene(parse(data)).triangles()
    except Unsupported:
        return None
    except MemoryError:
        raise
    except Exception:  # a case the checks above missed: never decide here what trimesh would make of it
        return None


__all__ = ["read_collada"]
