"""Numbers as fixes write them, and what derivers of every format read from a finding."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:  # numpy is imported by the functions that compute: `geomcheck rule` reads this module
    import numpy as np

INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
SIGNIFICANT_DIGITS = 6  # numbers written by fixes: lengths to 1 um at 1 m, tensors to 1 ppm


class Diagnostic(Protocol):
    """What a fix is derived from: a finding's rule, the part it concerns, its ``data`` and
    the format of its description (:class:`geomcheck.diagnostics.Diagnostic` is one; named
    structurally so that deriving a fix does not import the findings that ask for it)."""

    @property
    def code(self) -> str: ...
    @property
    def about(self) -> str: ...
    @property
    def data(self) -> Mapping[str, Any]: ...


def number(value: float) -> str:
    """``value`` as a fix writes it: 6 significant digits, no ``-0`` or ``+``."""
    text = f"{value:.{SIGNIFICANT_DIGITS}g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}e{int(exponent)}"
    return "0" if text in ("-0", "0") else text


def vector(values: Sequence[float] | np.ndarray) -> str:
    return " ".join(number(float(v)) for v in values)


def shape_kind(d: Diagnostic) -> str | None:
    """``collision`` or ``visual`` from ``about`` (``collision[0]``)."""
    kind = d.about.split("[", 1)[0]
    return kind if kind in ("collision", "visual") else None


def fitted(d: Diagnostic) -> tuple[str, Mapping[str, Any], Mapping[str, Any], str] | None:
    """``(type, geometry, origin, current type)`` of the primitive a GC3xx finding suggests
    for its collision element, ``None`` when it suggests none (or no one right answer)."""
    suggested = d.data.get("suggested")
    current = d.data.get("element")
    if not isinstance(suggested, Mapping) or not isinstance(current, str) or shape_kind(d) != "collision":
        return None
    if d.code == "GC303" and d.data.get("disjoint") and d.data.get("multi"):
        return None  # the help says to move it onto its part or remove it: no one right answer
    return str(suggested["type"]), suggested["geometry"], suggested["origin"], current


def rotation_rpy(rpy: Sequence[float]) -> np.ndarray:
    """URDF's (and SDFormat's) fixed-axis roll, pitch, yaw as a rotation matrix: Rz Ry Rx."""
    import numpy as np

    r, p, y = (float(v) for v in rpy)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def quaternion(rotation: np.ndarray) -> np.ndarray:
    """The unit quaternion ``(w, x, y, z)`` of a rotation matrix, ``w >= 0`` (MuJoCo's order)."""
    import numpy as np

    m = np.asarray(rotation, dtype=float)
    trace = float(np.trace(m))
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(max(1.0 + m[i, i] - m[j, j] - m[k, k], 0.0))
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    out = np.array(q) / np.linalg.norm(q)
    return -out if out[0] < 0.0 else out


def primitive_values(kind: str, geometry: Mapping[str, Any]) -> dict[str, str]:
    """The numbers of a fitted primitive as URDF and SDFormat write them, by name: a box's
    ``size`` (full extents), a cylinder's ``radius`` and ``length``, a sphere's ``radius`` [m]."""
    if kind == "box":
        return {"size": vector(geometry["size"])}
    if kind == "cylinder":
        return {"radius": number(float(geometry["radius"])), "length": number(float(geometry["length"]))}
    return {"radius": number(float(geometry["radius"]))}


def fitted_title(kind: str, current: str) -> str:
    """The title of a fix that writes the fitted ``kind`` over the element's ``current`` type."""
    return f"use the fitted {kind}" if kind == current else f"replace the {current} by the fitted {kind}"


def turned(d: Diagnostic) -> tuple[str, Mapping[str, Any]] | None:
    """``(title, alternative)`` of a finding whose cylinder lies on the wrong mesh axis: the
    alternative's ``rpy`` turns it onto the right one; ``None`` when the finding has none."""
    alternative = d.data.get("axis_alternative")
    if not isinstance(alternative, Mapping) or shape_kind(d) != "collision":
        return None
    return f"turn the cylinder onto the mesh's {alternative.get('axis_name', '')} axis".replace("  ", " "), alternative


def mesh_replacement(d: Diagnostic) -> tuple[str, str, str] | None:
    """``(kind, filename, title)`` of a GC201/GC202 finding whose mesh exists under another
    name (other letter case, another folder of the bundle), ``None`` otherwise."""
    kind = shape_kind(d)
    if kind is None:
        return None
    existing, alternative = d.data.get("existing_filename"), d.data.get("alternative")
    if d.code == "GC201" and isinstance(existing, str) and existing:
        return kind, existing, "the file exists with other letter case"
    if isinstance(alternative, str) and alternative and not d.data.get("generated_from"):
        return kind, alternative, "a file of that name exists in another folder"
    return None
