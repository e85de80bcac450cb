"""Each finding's fix, from what its rule already put in the finding's ``data``.

* GC103 (safe): the file's legacy xacro syntax written in today's (``xacro:`` prefixes, the
  namespace declared; :mod:`geomcheck.patch.modernise`), the expansion unchanged;
* GC105/GC106 (safe): the misspelt element or attribute renamed to its one did-you-mean;
* GC120 (safe): the joint axis normalised to unit length;
* GC201/GC202 (safe): the mesh filename that exists (other letter case, or the same file
  name in another folder of the bundle);
* GC301-GC304, GC306 (unsafe): the collision element replaced by the fitted primitive
  (``data["suggested"]``), or for GC304 turned onto the mesh's axis;
* GC414 (unsafe): an SRDF pair's ``reason`` set to the class the collision matrix finds;
* GC505 (unsafe): the tensor the link's geometry implies for its stated mass and centre
  of mass (``data["implied_inertia"]``).

These are URDF's (and xacro's); a finding on an MJCF or SDFormat description (its
``syntax``) gets its fix in that format's syntax: :mod:`geomcheck.fixes.derive_mjcf`,
:mod:`geomcheck.fixes.derive_sdf`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from geomcheck.fixes.derive_mjcf import DERIVERS as MJCF_DERIVERS
from geomcheck.fixes.derive_mjcf import SYNTAX as MJCF
from geomcheck.fixes.derive_sdf import DERIVERS as SDF_DERIVERS
from geomcheck.fixes.derive_sdf import SYNTAX as SDF
from geomcheck.fixes.model import (
    Applicability,
    Change,
    ModerniseXacro,
    RenameAttribute,
    RenameElement,
    ReplaceElement,
    SetAttribute,
    SuggestedFix,
)
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


def _primitive_xml(kind: str, geometry: Mapping[str, Any]) -> str:
    return f"<{kind}" + "".join(f' {k}="{v}"' for k, v in primitive_values(kind, geometry).items()) + "/>"


def _fitted_primitive(d: Diagnostic) -> SuggestedFix | None:
    found = fitted(d)
    if found is None:
        return None
    kind, geometry, origin, current = found
    changes: list[Change] = [
        SetAttribute(("origin",), "xyz", vector(origin["xyz"])),
        SetAttribute(("origin",), "rpy", vector(origin["rpy"])),
    ]
    if kind == current:
        changes.extend(SetAttribute(("geometry", kind), key, _attribute(value)) for key, value in geometry.items())
    else:
        changes.append(ReplaceElement(("geometry", current), _primitive_xml(kind, geometry)))
    title = fitted_title(kind, current)
    return SuggestedFix(Applicability.UNSAFE, title, "collision", tuple(changes))


def _attribute(value: Any) -> str:
    return vector(value) if isinstance(value, list | tuple) else number(float(value))


def _turned_cylinder(d: Diagnostic) -> SuggestedFix | None:
    if (found := turned(d)) is None:
        return None
    title, alternative = found
    return SuggestedFix(
        Applicability.UNSAFE, title, "collision", (SetAttribute(("origin",), "rpy", vector(alternative["rpy"])),)
    )


def _renamed_element(d: Diagnostic) -> SuggestedFix | None:
    suggestion, tag = d.data.get("suggestion"), d.data.get("element")
    if not isinstance(suggestion, str) or not isinstance(tag, str) or not suggestion:
        return None
    return SuggestedFix(
        Applicability.SAFE, f"rename <{tag}> to <{suggestion}>", tag, (RenameElement((), suggestion),), True
    )


def _renamed_attribute(d: Diagnostic) -> SuggestedFix | None:
    attributes, suggestions, element = d.data.get("attributes"), d.data.get("suggestions"), d.data.get("element")
    if not isinstance(attributes, list) or not isinstance(suggestions, Mapping) or not isinstance(element, str):
        return None
    if not attributes or any(a not in suggestions for a in attributes):
        return None
    changes = tuple(RenameAttribute((), a, str(suggestions[a])) for a in attributes)
    title = ", ".join(f"{a} -> {suggestions[a]}" for a in attributes)
    return SuggestedFix(Applicability.SAFE, f"rename attribute {title}", element, changes, True)


def _unit_axis(d: Diagnostic) -> SuggestedFix | None:
    axis, norm = d.data.get("axis"), d.data.get("norm")
    if not isinstance(axis, list) or not isinstance(norm, int | float) or not norm > 0.0 or not math.isfinite(norm):
        return None
    unit = [float(v) / float(norm) for v in axis]
    return SuggestedFix(
        Applicability.SAFE,
        "normalise the axis to unit length",
        "joint",
        (SetAttribute(("axis",), "xyz", vector(unit)),),
    )


def _mesh_path(d: Diagnostic) -> SuggestedFix | None:
    if (found := mesh_replacement(d)) is None:
        return None
    kind, fixed, title = found
    return SuggestedFix(
        Applicability.SAFE,
        f"{title}: use {fixed}",
        kind,
        (SetAttribute(("geometry", "mesh"), "filename", fixed),),
        True,
    )


def _implied_inertia(d: Diagnostic) -> SuggestedFix | None:
    implied = d.data.get("implied_inertia")
    if not isinstance(implied, Mapping) or any(k not in implied for k in INERTIA_KEYS):
        return None
    changes = tuple(SetAttribute(("inertia",), k, number(float(implied[k]))) for k in INERTIA_KEYS)
    return SuggestedFix(
        Applicability.UNSAFE,
        "use the tensor of the link's geometry (uniform density, convex hull) for its mass and centre of mass",
        "inertial",
        changes,
    )


def _srdf_reason(d: Diagnostic) -> SuggestedFix | None:
    found = d.data.get("class")
    if found not in ("adjacent", "default", "always", "never"):
        return None
    reason = str(found).capitalize()
    return SuggestedFix(
        Applicability.UNSAFE,
        f"disable the pair as {reason}, the class the collision matrix finds",
        "disable_collisions",
        (SetAttribute((), "reason", reason),),
        True,
    )


def _modernised_xacro(d: Diagnostic) -> SuggestedFix | None:
    file = d.data.get("file")
    if not isinstance(file, str):
        return None
    return SuggestedFix(
        Applicability.SAFE,
        f"write {file} in today's xacro syntax (xacro: prefixes, the namespace declared); the expansion is unchanged",
        "robot",
        (ModerniseXacro(file),),
        True,
    )


DERIVERS = {
    "GC103": _modernised_xacro,
    "GC105": _renamed_element,
    "GC106": _renamed_attribute,
    "GC120": _unit_axis,
    "GC201": _mesh_path,
    "GC202": _mesh_path,
    "GC301": _fitted_primitive,
    "GC302": _fitted_primitive,
    "GC303": _fitted_primitive,
    "GC304": _turned_cylinder,
    "GC306": _fitted_primitive,
    "GC414": _srdf_reason,
    "GC505": _implied_inertia,
}
FORMAT_DERIVERS = {"urdf": DERIVERS, MJCF: MJCF_DERIVERS, SDF: SDF_DERIVERS}
FIXABLE_CODES = tuple(sorted(DERIVERS))
APPLICABILITY = {
    **dict.fromkeys(("GC103", "GC105", "GC106", "GC120", "GC201", "GC202"), Applicability.SAFE),
    **dict.fromkeys(("GC301", "GC302", "GC303", "GC304", "GC306", "GC414", "GC505"), Applicability.UNSAFE),
}


def rule_fix_note(code: str) -> str | None:
    """What the rules reference says of ``code``'s automatic fix, ``None`` for rules without one."""
    applicability = APPLICABILITY.get(code)
    if applicability is None:
        return None
    command = "geomcheck fix" if applicability is Applicability.SAFE else "geomcheck fix --unsafe-fixes"
    return (
        f"{applicability.value.capitalize()} fix: `{command}` applies it when the finding carries the values "
        "to write (docs/fix.md); reports mark such findings [*]."
    )


def suggested_fix(d: Diagnostic) -> SuggestedFix | None:
    """The fix of ``d`` in the syntax of its description's format (``d.syntax``, URDF when it
    has none), or ``None`` when its rule has none there or its data does not give one."""
    derive = FORMAT_DERIVERS.get(getattr(d, "syntax", "urdf"), {}).get(d.code)
    if derive is None:
        return None
    try:
        return derive(d)
    except (KeyError, TypeError, ValueError):  # data from an older report without the fields
        return None
