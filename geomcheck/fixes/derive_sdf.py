"""Each finding's fix written in SDFormat syntax, from its ``data`` as
:mod:`geomcheck.fixes.derive` derives URDF's.

SDFormat writes values as element text: a fitted primitive is the collision's ``<pose>`` (in
the link's frame; the planner states ``relative_to`` when the pose named another frame) and
its ``<geometry>``: ``<box><size>`` (full extents), ``<cylinder><radius><length>``,
``<sphere><radius>``. GC505's tensor is the ``<inertial><inertia>``'s ``<ixx>`` ... ``<izz>``,
in the axes of the inertial's pose, as the finding computes it. A mesh path is the
``<mesh><uri>``; the planner writes it in the URI's own form (``model://``) or refuses.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from geomcheck.fixes.model import Applicability, Change, ReplaceElement, SetPose, SetText, SuggestedFix
from geomcheck.fixes.values import (
    INERTIA_KEYS,
    Diagnostic,
    fitted,
    fitted_title,
    mesh_replacement,
    number,
    primitive_values,
    turned,
    vector,
)

SYNTAX = "sdf"
ANY_SHAPE = "*"  # the one shape element of a <geometry>, whatever its tag


def shape_xml(kind: str, geometry: Mapping[str, Any]) -> str:
    return f"<{kind}>" + "".join(f"<{k}>{v}</{k}>" for k, v in primitive_values(kind, geometry).items()) + f"</{kind}>"


def _fitted_collision(d: Diagnostic) -> SuggestedFix | None:
    found = fitted(d)
    if found is None:
        return None
    kind, geometry, origin, current = found
    changes: list[Change] = [SetPose(vector(origin["xyz"]), vector(origin["rpy"]))]
    if kind == current:
        changes.extend(
            SetText(("geometry", kind, key), value) for key, value in primitive_values(kind, geometry).items()
        )
    else:
        changes.append(ReplaceElement(("geometry", ANY_SHAPE), shape_xml(kind, geometry)))
    title = fitted_title(kind, current)
    return SuggestedFix(Applicability.UNSAFE, title, "collision", tuple(changes), syntax=SYNTAX)


def _turned_collision(d: Diagnostic) -> SuggestedFix | None:
    if (found := turned(d)) is None:
        return None
    title, alternative = found
    return SuggestedFix(
        Applicability.UNSAFE, title, "collision", (SetPose(None, vector(alternative["rpy"])),), syntax=SYNTAX
    )


def _mesh_uri(d: Diagnostic) -> SuggestedFix | None:
    if (found := mesh_replacement(d)) is None:
        return None
    kind, fixed, title = found
    return SuggestedFix(
        Applicability.SAFE, f"{title}: use {fixed}", kind, (SetText(("geometry", "mesh", "uri"), fixed),), True, SYNTAX
    )


def _implied_inertia(d: Diagnostic) -> SuggestedFix | None:
    implied = d.data.get("implied_inertia")
    if not isinstance(implied, Mapping) or any(k not in implied for k in INERTIA_KEYS):
        return None
    changes = tuple(SetText(("inertia", k), number(float(implied[k]))) for k in INERTIA_KEYS)
    return SuggestedFix(
        Applicability.UNSAFE,
        "use the tensor of the link's geometry (uniform density, convex hull) for its mass and centre of mass",
        "inertial",
        changes,
        syntax=SYNTAX,
    )


DERIVERS = {
    "GC201": _mesh_uri,
    "GC202": _mesh_uri,
    "GC301": _fitted_collision,
    "GC302": _fitted_collision,
    "GC303": _fitted_collision,
    "GC304": _turned_collision,
    "GC306": _fitted_collision,
    "GC505": _implied_inertia,
}
