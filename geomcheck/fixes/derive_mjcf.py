"""Each finding's fix written in MJCF (MuJoCo) syntax, from its ``data`` as
:mod:`geomcheck.fixes.derive` derives URDF's.

geomcheck reads an MJCF body as a link whose frame is the body's, and a geom's origin is its
pose in that frame, so a fitted primitive is written on the ``<geom>`` itself: ``type``,
``size`` (half extents of a box, ``radius half-length`` of a cylinder, as MuJoCo's sizes are),
``pos`` and ``quat`` (``w x y z``: a quaternion does not depend on the compiler's ``angle``
unit or ``eulerseq``); any other way the geom states its frame (``fromto``, ``euler``,
``axisangle``, ``xyaxes``, ``zaxes``) and a ``mesh`` MuJoCo would fit the primitive to are
removed. Values written on the geom override those of its default class, which other geoms
share and the fix leaves alone. GC505's tensor is given in the axes MuJoCo compiled for the
body's inertial frame; the planner writes it as the ``<inertial>`` states its tensor
(:mod:`geomcheck.patch.plan_formats`). A missing mesh file stops MuJoCo's compiler, so GC201
and GC202 are never reported on MJCF and have no fix here.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from geomcheck.fixes.model import Applicability, Change, RemoveAttribute, SetAttribute, SetInertia, SuggestedFix
from geomcheck.fixes.values import (
    INERTIA_KEYS,
    Diagnostic,
    fitted,
    fitted_title,
    number,
    quaternion,
    rotation_rpy,
    turned,
    vector,
)

SYNTAX = "mjcf"
# the attributes besides ``quat`` that state a geom's orientation (MuJoCo takes one of them)
ORIENTATIONS = ("euler", "axisangle", "xyaxes", "zaxes")


def size_text(kind: str, geometry: Mapping[str, Any]) -> str:
    """MuJoCo's ``size`` of a URDF-sized primitive: half extents, ``radius half-length``, radius."""
    if kind == "box":
        return vector([0.5 * float(v) for v in geometry["size"]])
    if kind == "cylinder":
        return vector([float(geometry["radius"]), 0.5 * float(geometry["length"])])
    return number(float(geometry["radius"]))


def quat_text(rpy: Any) -> str:
    return vector(quaternion(rotation_rpy(rpy)))


def _fitted_geom(d: Diagnostic) -> SuggestedFix | None:
    found = fitted(d)
    if found is None:
        return None
    kind, geometry, origin, current = found
    changes: list[Change] = [
        SetAttribute((), "type", kind),
        SetAttribute((), "size", size_text(kind, geometry)),
        SetAttribute((), "pos", vector(origin["xyz"])),
        SetAttribute((), "quat", quat_text(origin["rpy"])),
        RemoveAttribute((), "fromto"),
        *(RemoveAttribute((), a) for a in ORIENTATIONS),
        RemoveAttribute((), "mesh"),
    ]
    title = fitted_title(kind, current)
    return SuggestedFix(Applicability.UNSAFE, title, "geom", tuple(changes), syntax=SYNTAX)


def _turned_geom(d: Diagnostic) -> SuggestedFix | None:
    if (found := turned(d)) is None:
        return None
    title, alternative = found
    return SuggestedFix(
        Applicability.UNSAFE,
        title,
        "geom",
        (SetAttribute((), "quat", quat_text(alternative["rpy"])), *(RemoveAttribute((), a) for a in ORIENTATIONS)),
        syntax=SYNTAX,
    )


def _implied_inertia(d: Diagnostic) -> SuggestedFix | None:
    implied = d.data.get("implied_inertia")
    if not isinstance(implied, Mapping) or any(k not in implied for k in INERTIA_KEYS):
        return None
    ixx, ixy, ixz, iyy, iyz, izz = (float(implied[k]) for k in INERTIA_KEYS)
    return SuggestedFix(
        Applicability.UNSAFE,
        "use the tensor of the body's geometry (uniform density, convex hull) for its mass and centre of mass",
        "inertial",
        (SetInertia((ixx, ixy, ixz, iyy, iyz, izz)),),
        syntax=SYNTAX,
    )


DERIVERS = {
    "GC301": _fitted_geom,
    "GC302": _fitted_geom,
    "GC303": _fitted_geom,
    "GC304": _turned_geom,
    "GC306": _fitted_geom,
    "GC505": _implied_inertia,
}
