"""The length unit a mesh file declares, read as the ROS consumers read it.

Only COLLADA declares one: ``<COLLADA><asset><unit meter="0.0254"/>`` says one file unit is
0.0254 m. RViz (``getMeshUnitRescale`` in its mesh loader) reads the ``meter``
attribute of the first ``<unit>`` of the first ``<asset>`` under ``<COLLADA>`` and scales the
vertices by it; Gazebo's COLLADA loader does the same (``mesh->Scale(meter)``). geomcheck
applies it likewise, so a mesh is measured at the size those tools show.

``<up_axis>`` is read by nobody in ROS: assimp turns a Z_UP or X_UP file to Y-up in the
scene's root transform, and RViz, MoveIt's geometric_shapes and coal/hpp-fcl (pinocchio) all
drop that root transform; Gazebo's own COLLADA loader never reads the element. The vertices
are therefore used as written, and geomcheck does the same; exporters write Z-up coordinates
under a Y_UP declaration often enough that applying it would lay such parts on their side.
(Dropping assimp's root transform
also drops its unit scale: MoveIt and pinocchio read a COLLADA file in its own units.)

STL, OBJ, PLY and OFF carry no unit; glTF is in metres by specification (its Y-up is, as
COLLADA's up axis, not applied by RViz, which drops the root transform of every assimp scene).
"""

from __future__ import annotations

import io
import math

from lxml import etree

from geomcheck.load.xmlsafe import refuse_entities

METRE = 1.0  # the unit of a file that declares none [m per file unit]


class DeclaredUnitError(ValueError):
    """A COLLADA ``<unit meter>`` that is not a positive finite length."""


def _local(tag: object) -> str:
    """An element's name without its namespace (COLLADA files declare one)."""
    return etree.QName(tag).localname if isinstance(tag, str) else ""


def collada_unit(data: bytes) -> float:
    """Metres per file unit that the COLLADA document ``data`` declares (1.0 when it declares
    none or its ``meter`` is not a number, as RViz reads it). Reads no further than the
    document's ``<asset>``. :class:`DeclaredUnitError` when the declared unit is zero,
    negative or not finite: the tools that apply it collapse or mirror the mesh."""
    refuse_entities(data, "COLLADA document")
    events = etree.iterparse(
        io.BytesIO(data),
        events=("start", "end"),
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        huge_tree=False,
        remove_comments=True,
    )
    depth = 0
    in_asset = False
    try:
        for event, element in events:
            if event == "end":
                depth -= 1
                if in_asset and depth == 1:
                    return METRE  # the first <asset> ended without a <unit meter>
                continue
            depth += 1
            name = _local(element.tag)
            if depth == 1 and name != "COLLADA":
                return METRE
            if depth == 2:
                in_asset = name == "asset"
            elif in_asset and depth == 3 and name == "unit":
                text = element.get("meter")
                if text is None:
                    return METRE
                return _checked(text)
    except etree.XMLSyntaxError:
        return METRE  # the mesh reader reports what is wrong with the file
    return METRE


def _checked(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        return METRE  # RViz and Gazebo keep their default when the attribute is not a number
    if not (math.isfinite(value) and value > 0.0):
        raise DeclaredUnitError(f'its <unit meter="{text}"> is not a positive length')
    return value


__all__ = ["METRE", "DeclaredUnitError", "collada_unit"]
