"""Planning an MJCF or SDFormat fix: the checks and conversions that depend on how the format
states a value, before :class:`geomcheck.patch.planner.Planner` turns the changes into edits.

Every format:

- a file outside the folder fixes write (an ``<include>``d file elsewhere, a model folder found
  on the model path) refuses the fix, naming the file: it is read, never written.

MJCF (:mod:`geomcheck.fixes.derive_mjcf`):

- a geom whose ``pos``/``quat`` are not in its body's frame refuses the fix: one inside a
  ``<frame>`` or ``<replicate>`` (or ``<attach>``ed), and every geom when the compiler fuses
  static bodies (``fusestatic``: a fused body's geoms are placed in its parent's frame);
- a capsule geom (its own ``type``, or its default class's: :func:`geom_type`) keeps its type
  when the fitted primitive is a cylinder longer than its diameter: the capsule that cylinder
  encloses, which geomcheck reads as exactly that cylinder, is written (MuJoCo collides
  capsules better than cylinders); a ``type`` its class already gives is not written again;
- GC304's turn of a geom written with ``fromto`` is refused (its frame comes from the two
  points);
- ``pos`` ``0 0 0`` and ``quat`` ``1 0 0 0`` are not added to a geom that has neither and no
  class: they are MuJoCo's defaults;
- the inertia (:class:`SetInertia`, in MuJoCo's compiled inertial axes) is written as the
  ``<inertial>`` states it: ``fullinertia`` in the body's axes, or ``diaginertia`` alone when
  the tensor is diagonal in the element's own axes, else ``diaginertia`` with the ``quat`` of
  the tensor's principal axes (other orientation attributes removed). A body whose inertia
  MuJoCo infers from its geoms (no ``<inertial>``, or ``inertiafromgeom="true"``) refuses
  it: there is no value to change.

SDFormat (:mod:`geomcheck.fixes.derive_sdf`):

- the ``<pose>`` (:class:`SetPose`) is written in the link's frame: a pose ``relative_to``
  another frame is given ``relative_to`` the link (SDFormat 1.7 and later), ``degrees`` and
  ``rotation_format`` are removed (radians, roll pitch yaw); a 1.5/1.6 pose naming a ``frame``
  refuses the fix;
- a mesh ``<uri>`` is written in the form the file writes it: as resolved when it is written
  so, ``model://NAME/...`` for a model URI geomcheck reads as ``package://NAME/...``;
  otherwise the fix is refused.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import replace

import numpy as np

from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError
from geomcheck.fixes.derive_mjcf import ORIENTATIONS
from geomcheck.fixes.model import (
    Change,
    Refused,
    RemoveAttribute,
    SetAttribute,
    SetInertia,
    SetPose,
    SetText,
    SuggestedFix,
    place,
)
from geomcheck.fixes.values import SIGNIFICANT_DIGITS, number, quaternion, vector
from geomcheck.load import LoadedDescription
from geomcheck.model import Link, Mesh
from geomcheck.patch.apply import fix_tree, source_path, writable_path
from geomcheck.patch.xacro_values import same_number
from geomcheck.patch.xmltext import Element, SourceText

Texts = Callable[[str], SourceText]
BODY_FRAMES = ("body", "worldbody")  # MJCF elements whose geoms are placed in the body's frame
MODEL_SCHEME, PACKAGE_SCHEME = "model://", "package://"


def as_written(loaded: LoadedDescription) -> dict[str, str]:
    """The text of each source file as it is on disk, where the loader kept another text of
    the same length: the SDFormat reader blanks out an ``<?xml?>`` declaration written after
    a licence comment (every line and column kept), and fixes must write the file around it."""
    out = {}
    for file, text in loaded.document.sources.items():
        try:
            written = source_path(loaded.bundle, file).read_bytes().decode("utf-8", errors="replace")
        except (InputError, OSError):
            continue
        if written != text and len(written) == len(text):
            out[file] = written
    return out


def refusal(loaded: LoadedDescription, d: Diagnostic, fix: SuggestedFix) -> Refused | None:
    """Why ``fix`` cannot be written whatever the element says, before it is looked for:
    MuJoCo infers the inertia of a body from its geoms (it may have no ``<inertial>``)."""
    if fix.syntax != "mjcf" or fix.element != "inertial":
        return None
    link = _link(loaded, d.link)
    inertial = link.inertial if link is not None else None
    if inertial is not None and not inertial.from_geometry:
        return None
    where = inertial.location if inertial is not None else None
    places = [place(where.file, where.line)] if where is not None and where.line is not None else []
    return Refused(
        "MuJoCo infers this body's inertia from its geoms (no <inertial>, or compiler inertiafromgeom): "
        "there is no written tensor to change; write an <inertial> or fix the geoms",
        *places,
    )


def adapt(
    loaded: LoadedDescription, texts: Texts, d: Diagnostic, fix: SuggestedFix, file: str, element: Element
) -> tuple[Change, ...]:
    """``fix``'s changes to ``element`` (of ``file``) as the planner makes them;
    :class:`Refused` when they cannot be written safely."""
    try:
        writable_path(loaded.bundle, file, fix_tree(loaded.bundle))
    except InputError as err:
        raise Refused(f"{err}", file) from None
    if fix.syntax == "mjcf":
        if fix.element == "inertial":
            return _mjcf_inertial(loaded, d, fix, file, element)
        return _mjcf_geom(loaded, texts, fix, file, element)
    if fix.syntax == "sdf":
        return _sdf(loaded, d, fix, file, element)
    return fix.changes


# MJCF -------------------------------------------------------------------------------------


def _fuses_static(loaded: LoadedDescription, texts: Texts) -> str | None:
    """The place of a ``<compiler fusestatic="true">``, if a source has one."""
    for file in loaded.document.sources:
        for e in texts(file).elements:
            fuse = e.attribute("fusestatic") if e.name == "compiler" else None
            if fuse is not None and fuse.value.strip().lower() == "true":
                return place(file, e.first_line)
    return None


def _mjcf_geom(
    loaded: LoadedDescription, texts: Texts, fix: SuggestedFix, file: str, element: Element
) -> tuple[Change, ...]:
    here = place(file, element.first_line)
    _refuse_outside_body_frame(file, element, here)
    fused = _fuses_static(loaded, texts)
    if fused is not None:
        raise Refused(
            f"the compiler fuses static bodies (fusestatic at {fused}): a geom's frame may be its parent body's",
            here,
            fused,
        )
    changes = list(fix.changes)
    settings = {c.attribute: c for c in changes if isinstance(c, SetAttribute)}
    if "size" not in settings and element.attribute("fromto") is not None:
        raise Refused(f"the <geom> at {here} is written with fromto: turn it by hand", here)
    current = geom_type(loaded, texts, element)
    wanted = _capsule_kept(changes, settings, current)
    if wanted is not None and element.attribute("type") is None and current == wanted.value:
        changes.remove(wanted)  # the type its class gives it
    if element.attribute("class") is None and not any(a.attribute("childclass") for a in element.ancestors()):
        changes = _without_defaults(changes, element)
    return tuple(changes)


def _refuse_outside_body_frame(file: str, element: Element, here: str) -> None:
    """:class:`Refused` when the geom's ``pos`` and ``quat`` are not in its body's frame (it is
    inside a ``<frame>``, a ``<replicate>``...)."""
    holder = next((a for a in element.ancestors() if a.name not in BODY_FRAMES), None)
    parent = element.parent
    if parent is not None and parent.name not in BODY_FRAMES:
        holder = parent
    if holder is not None and holder.name != "mujoco":
        where = place(file, holder.first_line)
        raise Refused(
            f"the <geom> at {here} is inside the <{holder.name}> at {where}: its pos and quat are not in its body's "
            "frame; write the fitted primitive by hand",
            here,
            where,
        )


def _capsule_kept(
    changes: list[Change], settings: Mapping[str, SetAttribute], current: str | None
) -> SetAttribute | None:
    """The ``type`` the fix sets, a capsule kept in ``changes`` (in place) when the fitted
    cylinder is longer than its diameter: the capsule it encloses is read as exactly it."""
    wanted = settings.get("type")
    if current == "capsule" and wanted is not None and wanted.value == "cylinder":
        radius, half = (float(v) for v in settings["size"].value.split())
        if half > radius:  # the capsule this cylinder encloses is read as exactly this cylinder
            capsule = SetAttribute((), "type", "capsule")
            changes[changes.index(wanted)] = wanted = capsule
            changes[changes.index(settings["size"])] = SetAttribute((), "size", vector([radius, half - radius]))
    return wanted


def _without_defaults(changes: list[Change], element: Element) -> list[Change]:
    """``changes`` without the ``pos`` ``0 0 0`` and ``quat`` ``1 0 0 0`` a geom of no class that
    has neither would be given: MuJoCo's defaults."""
    unwritten = {"pos": "0 0 0", "quat": "1 0 0 0"}
    if element.attribute("fromto") is not None:  # it places the geom: pos and quat replace it
        unwritten.clear()
    elif any(element.attribute(a) is not None for a in ORIENTATIONS):
        unwritten.pop("quat")
    return [
        c
        for c in changes
        if not (
            isinstance(c, SetAttribute)
            and c.attribute in unwritten
            and element.attribute(c.attribute) is None
            and _same(c.value, unwritten[c.attribute])
        )
    ]


MJCF_DEFAULT_TYPE = "sphere"  # a geom's type when neither it nor a default class states one


def geom_type(loaded: LoadedDescription, texts: Texts, element: Element) -> str | None:
    """The type of an MJCF ``<geom>``: its own ``type``, else the one its default class (its
    ``class``, else the nearest ``childclass`` above it, else ``main``) or a class that class
    is nested in gives, else MuJoCo's sphere; ``None`` when the class is not found."""
    written = element.attribute("type")
    if written is not None:
        return written.value.strip()
    default = _default_class(loaded, texts, _class_name(element))
    if default is None:
        return None
    node: Element | None = default
    while node is not None and node.name == "default":
        geom = node.child("geom")
        stated = geom.attribute("type") if geom is not None else None
        if stated is not None:
            return stated.value.strip()
        node = node.parent
    return MJCF_DEFAULT_TYPE


def _class_name(element: Element) -> str:
    """The default class of a geom: its ``class``, else the nearest ``childclass`` above it, else ``main``."""
    named = element.attribute("class")
    if named is None:
        named = next((a.attribute("childclass") for a in element.ancestors() if a.attribute("childclass")), None)
    return named.value.strip() if named is not None else "main"


def _default_class(loaded: LoadedDescription, texts: Texts, name: str) -> Element | None:
    """The ``<default>`` of class ``name`` (``main``: the unnamed one under ``<mujoco>``), the
    first in the sources."""
    for file in loaded.document.sources:
        for e in texts(file).elements:
            if e.name != "default":
                continue
            label = e.attribute("class")
            top = e.parent is not None and e.parent.name == "mujoco"
            if (label is not None and label.value.strip() == name) or (label is None and top and name == "main"):
                return e
    return None


def _same(a: str, b: str) -> bool:
    x, y = a.split(), b.split()
    return len(x) == len(y) and all(same_number(p, q) for p, q in zip(x, y, strict=True))


def _link(loaded: LoadedDescription, name: str | None) -> Link | None:
    return next((link for link in loaded.robot.links if link.name == name), None)


def _mjcf_inertial(
    loaded: LoadedDescription, d: Diagnostic, fix: SuggestedFix, file: str, element: Element
) -> tuple[Change, ...]:
    refused = refusal(loaded, d, fix)
    link = _link(loaded, d.link)
    inertial = link.inertial if link is not None else None
    if refused is not None or inertial is None:
        raise refused or Refused(f"no inertial for {d.link}", file)
    (change,) = (c for c in fix.changes if isinstance(c, SetInertia))
    ixx, ixy, ixz, iyy, iyz, izz = change.tensor
    tensor = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    axes = inertial.origin.rotation()  # MuJoCo's compiled inertial frame in the body's axes
    in_body = _quantised(axes @ tensor @ axes.T)
    if element.attribute("fullinertia") is not None:
        values = [in_body[0, 0], in_body[1, 1], in_body[2, 2], in_body[0, 1], in_body[0, 2], in_body[1, 2]]
        return (SetAttribute((), "fullinertia", vector(values)),)
    if _diagonal(tensor):  # diagonal in the axes the element states: only the moments change
        return (SetAttribute((), "diaginertia", moments_text(np.diag(tensor))),)
    moments, principal = np.linalg.eigh(in_body)
    if np.linalg.det(principal) < 0.0:
        principal[:, 2] *= -1.0
    return (
        SetAttribute((), "diaginertia", moments_text(moments)),
        SetAttribute((), "quat", vector(quaternion(principal))),
        *(RemoveAttribute((), a) for a in ORIENTATIONS),
    )


def _quantum(tensor: np.ndarray) -> float:
    """The last digit fixes write of a tensor: the 6th significant digit of its largest entry."""
    largest = float(np.abs(tensor).max())
    return 10.0 ** (math.floor(math.log10(largest)) - (SIGNIFICANT_DIGITS - 1)) if largest > 0.0 else 0.0


def _quantised(tensor: np.ndarray) -> np.ndarray:
    """``tensor`` to the precision fixes write: turned into other axes, round-off becomes 0."""
    quantum = _quantum(tensor)
    return np.round(tensor / quantum) * quantum + 0.0 if quantum > 0.0 else tensor


def _diagonal(tensor: np.ndarray) -> bool:
    """Whether the products of inertia vanish at the precision fixes write."""
    return bool(np.all(np.abs(tensor[~np.eye(3, dtype=bool)]) < 0.5 * _quantum(tensor)))


def moments_text(moments: np.ndarray) -> str:
    """Principal moments as written, each no more than the sum of the other two once rounded
    (MuJoCo's compiler refuses a tensor that breaks the triangle inequality)."""
    texts = [number(float(v)) for v in moments]
    values = [float(t) for t in texts]
    for k in range(3):
        others = values[(k + 1) % 3] + values[(k + 2) % 3]
        if values[k] > others:
            value = others
            text = f"{value:.{SIGNIFICANT_DIGITS + 6}g}"
            while float(text) > others:
                value = float(np.nextafter(value, 0.0))
                text = repr(value)
            texts[k], values[k] = text, float(text)
    return " ".join(texts)


# SDFormat ---------------------------------------------------------------------------------


def _sdf(
    loaded: LoadedDescription, d: Diagnostic, fix: SuggestedFix, file: str, element: Element
) -> tuple[Change, ...]:
    out: list[Change] = []
    for change in fix.changes:
        if isinstance(change, SetPose):
            out.extend(_sdf_pose(file, element, change))
        elif isinstance(change, SetText) and change.path == ("geometry", "mesh", "uri"):
            out.append(_sdf_uri(loaded, d, file, element, change))
        elif isinstance(change, SetText) and _unwritten_default(element, change):
            continue
        elif isinstance(change, SetText) and change.path[0] == "geometry" and len(change.path) == 3:
            _same_shape(file, element, change.path[1])
            out.append(change)
        else:
            out.append(change)
    return tuple(out)


def _same_shape(file: str, element: Element, kind: str) -> None:
    """:class:`Refused` when the ``<geometry>`` holds another shape than the ``kind`` geomcheck read."""
    holder = element.child("geometry")
    shape = holder.children[0] if holder is not None and holder.children else None
    if shape is not None and shape.name != kind:
        here = place(file, shape.first_line)
        raise Refused(
            f"the <{shape.name}> at {here} is read as the {kind} enclosing it: write the fitted {kind} by hand",
            here,
        )


# SDFormat's values of an <inertia> entry that is not written [kg m^2]
INERTIA_DEFAULTS = {"ixx": "1", "iyy": "1", "izz": "1", "ixy": "0", "ixz": "0", "iyz": "0"}


def _unwritten_default(element: Element, change: SetText) -> bool:
    """Whether ``change`` would add an ``<inertia>`` entry with the value SDFormat gives it unwritten."""
    if len(change.path) != 2 or change.path[0] != "inertia" or change.path[1] not in INERTIA_DEFAULTS:
        return False
    tensor = element.child("inertia")
    written = tensor.child(change.path[1]) if tensor is not None else None
    return written is None and _same(change.text, INERTIA_DEFAULTS[change.path[1]])


def _sdf_pose(file: str, element: Element, change: SetPose) -> list[Change]:
    here = place(file, element.first_line)
    pose = element.child("pose")
    link = element.parent
    link_name = link.attribute("name") if link is not None and link.name == "link" else None
    if link_name is None:
        raise Refused(f"the <{element.name}> at {here} is not in a <link name=...>", here)
    frame = pose.attribute("frame") if pose is not None else None
    if frame is not None and frame.value.strip():
        raise Refused(
            f"the <pose> at {here} is in frame {frame.value.strip()!r} (SDFormat 1.5/1.6): set it by hand", here
        )
    relative = pose.attribute("relative_to") if pose is not None else None
    elsewhere = relative is not None and relative.value.strip() not in ("", link_name.value.strip())
    restated = [RemoveAttribute(("pose",), "degrees"), RemoveAttribute(("pose",), "rotation_format")]
    if change.xyz is None and pose is not None:  # GC304: the angles, after the position as written
        if elsewhere or any(pose.attribute(a) is not None for a in ("degrees", "rotation_format")):
            raise Refused(f"the <pose> at {here} is not written as x y z roll pitch yaw in the link's frame", here)
        return [SetText(("pose",), change.rpy, keep_leading=3)]
    text = f"{change.xyz or '0 0 0'} {change.rpy}"
    if pose is None and _same(text, "0 0 0 0 0 0"):
        return []  # SDFormat's default pose
    out: list[Change] = [SetText(("pose",), text), *restated]
    if elsewhere:
        out.append(SetAttribute(("pose",), "relative_to", link_name.value.strip()))
    return out


def _shape(link: Link | None, about: str) -> Mesh | None:
    if link is None:
        return None
    for shape in (*link.visuals, *link.collisions):
        if shape.label == about and isinstance(shape.geometry, Mesh):
            return shape.geometry
    return None


def _sdf_uri(loaded: LoadedDescription, d: Diagnostic, file: str, element: Element, change: SetText) -> SetText:
    here = place(file, element.first_line)
    holder = element.child("geometry")
    mesh = holder.child("mesh") if holder is not None else None
    uri = mesh.child("uri") if mesh is not None else None
    read = _shape(_link(loaded, d.link), d.about)
    if uri is None or read is None:
        raise Refused(f"no <mesh><uri> in the <{element.name}> at {here}", here)
    written = _text(loaded, file, uri).strip()
    fixed = change.text
    if written == read.filename:
        return change
    if (
        written.startswith(MODEL_SCHEME)
        and read.filename == PACKAGE_SCHEME + written[len(MODEL_SCHEME) :]
        and fixed.startswith(PACKAGE_SCHEME)
    ):
        return replace(change, text=MODEL_SCHEME + fixed[len(PACKAGE_SCHEME) :])
    raise Refused(
        f"the <uri> at {here} ({written}) is written otherwise than geomcheck resolves it: set it by hand", here
    )


def _text(loaded: LoadedDescription, file: str, element: Element) -> str:
    source = loaded.document.sources[file]
    if element.end_name is None:
        return ""
    return source[element.open_end : source.rfind("<", 0, element.end_name[0])]
