"""The geometry of an SDFormat ``<visual>`` or ``<collision>``, read shape by shape.

Box, cylinder, sphere and mesh map exactly (``<uri>`` and ``<scale>``; ``model://NAME`` is
``package://NAME``); a capsule is a :class:`Capsule` and a cone (1.11) a :class:`Cone`, each
measured as the cylinder that encloses it, and an ellipsoid the enclosing cylinder (two equal
radii) or box marked ``ellipsoid``, measured and collided as itself. A plane, a missing or
empty ``<geometry>`` and ``<empty/>`` are no robot part; a ``<submesh>``, height map, image or
polyline, and a tag that is no SDFormat shape, are named by their tag: geomcheck does not
measure them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

from geomcheck.errors import InputError
from geomcheck.load.sdf_frames import number, numbers, vec3
from geomcheck.load.sdf_read import ModelScope, relative_uri
from geomcheck.model import Box, Capsule, Cone, Cylinder, Geometry, Mesh, Sphere

if TYPE_CHECKING:
    from lxml import etree

    from geomcheck.load.bundle import Bundle

EQUAL_RADII_RTOL = 1e-6  # ellipsoid radii this close (relative) are equal: the ellipsoid is round about the third [1]
# shapes geomcheck does not measure: the element is left out of every check, and the report says so
UNMEASURED_GEOMETRY = ("heightmap", "image", "polyline")
SKIPPED_GEOMETRY = ("plane", "empty")  # no robot part: a ground plane, an element without geometry

Bound = tuple[float, str]  # the largest magnitude of a number and the name of its limit


def _box(shape: etree._Element, where: str, length: Bound) -> Geometry:
    return Box(vec3(numbers(shape.findtext("size") or "1 1 1", (3,), where, "<size>", length)))


def _sphere(shape: etree._Element, where: str, length: Bound) -> Geometry:
    return Sphere(number(shape, "radius", 1.0, where, length))


def _cylinder(shape: etree._Element, where: str, length: Bound) -> Geometry:
    return Cylinder(number(shape, "radius", 1.0, where, length), number(shape, "length", 1.0, where, length))


def _capsule(shape: etree._Element, where: str, length: Bound) -> Geometry:
    radius = number(shape, "radius", 0.5, where, length)
    height = number(shape, "length", 1.0, where, length)
    return Capsule(radius, height + 2.0 * radius)  # measured as its enclosing cylinder


def _cone(shape: etree._Element, where: str, length: Bound) -> Geometry:  # SDFormat 1.11
    return Cone(number(shape, "radius", 1.0, where, length), number(shape, "length", 1.0, where, length))


def _ellipsoid(shape: etree._Element, where: str, length: Bound) -> Geometry:
    a, b, c = numbers(shape.findtext("radii") or "1 1 1", (3,), where, "<radii>", length)
    if math.isclose(a, b, rel_tol=EQUAL_RADII_RTOL):
        return Cylinder(a, 2.0 * c, ellipsoid=True)
    return Box((2.0 * a, 2.0 * b, 2.0 * c), ellipsoid=True)


# the primitive shapes, each read from its element with its lengths held to the length limit
PRIMITIVES: Mapping[str, Callable[[etree._Element, str, Bound], Geometry]] = {
    "box": _box,
    "sphere": _sphere,
    "cylinder": _cylinder,
    "capsule": _capsule,
    "cone": _cone,
    "ellipsoid": _ellipsoid,
}


def _mesh(shape: etree._Element, where: str, scope: ModelScope, bundle: Bundle, scale: Bound) -> Geometry | str:
    if shape.find("submesh") is not None:
        return "submesh"  # one named part of a mesh file: geomcheck reads whole files
    uri = (shape.findtext("uri") or "").strip()
    if not uri:
        raise InputError(f"{where}: <mesh> has no <uri>")
    factors = numbers(shape.findtext("scale") or "1 1 1", (3,), where, "<scale>", scale)
    return Mesh(relative_uri(uri, scope, bundle), vec3(factors))


def geometry_of(
    scope: ModelScope, element: etree._Element, bundle: Bundle, length: Bound, scale: Bound
) -> Geometry | str | None:
    """The geometry of ``element``; ``None`` for none (libsdformat reads a missing or empty
    ``<geometry>`` as an empty one) or a plane; the tag of a shape geomcheck does not measure."""
    holder = element.find("geometry")
    shape = None if holder is None else next((c for c in holder if isinstance(c.tag, str)), None)
    if shape is None or shape.tag in SKIPPED_GEOMETRY:
        return None
    where = scope.where(shape)
    primitive = PRIMITIVES.get(shape.tag)
    if primitive is not None:
        return primitive(shape, where, length)
    if shape.tag == "mesh":
        return _mesh(shape, where, scope, bundle, scale)
    return shape.tag  # not measured (a polyline, a height map), or no SDFormat shape at all


__all__ = ["EQUAL_RADII_RTOL", "PRIMITIVES", "SKIPPED_GEOMETRY", "UNMEASURED_GEOMETRY", "geometry_of"]
