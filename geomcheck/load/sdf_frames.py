"""SDFormat's pose and frame semantics: where every frame of a model is at the zero configuration,
and which link each frame is attached to, as libsdformat's FrameSemantics computes them.

A pose is read from ``<pose>`` (``x y z roll pitch yaw``, fixed-axis roll-pitch-yaw as URDF's;
``degrees="true"`` and ``rotation_format="quat_xyzw"`` from SDFormat 1.9). The frame it is
relative to is ``@relative_to`` when written (1.7+, a name of the same model, or of a nested
one as ``inner::frame`` from 1.8), otherwise the default of its element:

- a link, a nested model and a ``<frame>`` without ``@attached_to``: the model frame
  (``__model__``); a ``<frame>``: its ``@attached_to`` frame;
- a joint: its child link (or child frame);
- a collision, visual or inertial: its link;
- a nested model's pose places its ``placement_frame`` (the model frame when absent).

Before 1.7 there is no ``@relative_to``: every pose takes these defaults. The 1.5/1.6
``<pose frame="...">`` attribute had no defined meaning (libsdformat did not apply it), so a
non-empty one is refused rather than guessed. A joint axis is expressed in the joint frame, in
the frame ``//axis/xyz/@expressed_in`` names (1.7+), or in the model frame when
``use_parent_model_frame`` is true (1.5/1.6; SDFormat 1.4 and earlier always meant the model
frame, which libsdformat's 1.4 to 1.5 conversion writes as ``use_parent_model_frame``).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from geomcheck.errors import InputError
from geomcheck.load.sdf_read import FIRST_FRAME_SEMANTICS, ModelScope
from geomcheck.thresholds import LoadLimits

if TYPE_CHECKING:
    from lxml import etree

MODEL_FRAME = "__model__"
WORLD = "world"
NESTED_SCOPES = (1, 8)
MAX_LENGTH_M = LoadLimits().max_length_m  # the version from which a frame may be named as ``inner::frame``


def numbers(
    text: str | None, count: tuple[int, ...], where: str, what: str, bound: tuple[float, str] | None = None
) -> list[float]:
    """The numbers of ``text``; :class:`InputError` unless there are as many as one of ``count``
    and (with ``bound``: the largest magnitude and the name of the limit) none is larger: geometry
    built from 1e308 is not finite, so such a number never reaches it."""
    parts = (text or "").split()
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise InputError(f"{where}: {what} {text!r} is not a list of numbers") from None
    if len(values) not in count:
        wanted = " or ".join(str(c) for c in count)
        raise InputError(f"{where}: {what} {text!r} has {len(values)} numbers, not {wanted}")
    if not all(math.isfinite(v) for v in values):
        raise InputError(f"{where}: {what} {text!r} is not finite")
    if bound is not None:
        within(values, bound, where, f"{what} {text!r}")
    return values


def number(
    element: etree._Element, tag: str, default: float, where: str, bound: tuple[float, str] | None = None
) -> float:
    """The number of child ``tag`` of ``element``, ``default`` when absent (``bound`` as :func:`numbers`)."""
    text = element.findtext(tag)
    if text is None or not text.strip():
        return default
    return numbers(text, (1,), where, f"<{tag}>", bound)[0]


def vec3(values: list[float] | np.ndarray) -> tuple[float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]))


def within(values: list[float], bound: tuple[float, str], where: str, what: str) -> None:
    """:class:`InputError` when a magnitude of ``values`` exceeds ``bound`` (value, limit name)."""
    if any(abs(v) > bound[0] for v in values):
        raise InputError(f"{where}: {what} is beyond the limit of {bound[0]:g} ({bound[1]})")


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """``Rz(yaw) @ Ry(pitch) @ Rx(roll)``, SDFormat's (and URDF's) Euler convention, (3, 3)."""
    cr, sr, cp, sp, cy, sy = (
        math.cos(roll),
        math.sin(roll),
        math.cos(pitch),
        math.sin(pitch),
        math.cos(yaw),
        math.sin(yaw),
    )
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def quaternion_matrix(x: float, y: float, z: float, w: float, where: str) -> np.ndarray:
    """Rotation of the quaternion ``(x, y, z, w)`` (normalised as libsdformat does), (3, 3)."""
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if norm == 0.0:
        raise InputError(f"{where}: <pose> quaternion is zero")
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def pose_matrix(element: etree._Element | None, where: str, max_length: float = MAX_LENGTH_M) -> np.ndarray:
    """The (4, 4) transform a ``<pose>`` element writes (identity when absent or empty); a
    translation beyond ``max_length`` [m] is an :class:`InputError`."""
    out = np.eye(4)
    if element is None or not (element.text or "").strip():
        return out
    rotation_format = (element.get("rotation_format") or "euler_rpy").strip()
    if rotation_format == "quat_xyzw":
        v = numbers(element.text, (7,), where, "<pose>")
        out[:3, :3] = quaternion_matrix(v[3], v[4], v[5], v[6], where)
    elif rotation_format == "euler_rpy":
        v = numbers(element.text, (6,), where, "<pose>")
        angles = v[3:6]
        if (element.get("degrees") or "").strip().lower() in ("true", "1"):
            angles = [math.radians(a) for a in angles]
        out[:3, :3] = rpy_matrix(*angles)
    else:
        raise InputError(f'{where}: <pose rotation_format="{rotation_format}">: valid choices are euler_rpy, quat_xyzw')
    within(v[:3], (max_length, "max_length_m"), where, f"<pose> {element.text.strip()!r}")
    out[:3, 3] = v[:3]
    return out


def inverse(transform: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = transform[:3, :3].T
    out[:3, 3] = -transform[:3, :3].T @ transform[:3, 3]
    return out


def pose_child(element: etree._Element) -> etree._Element | None:
    return next((c for c in element if c.tag == "pose"), None)


class Frames:
    """The frames of one scope tree: poses in each model's frame, in the root model's frame,
    and the link each frame is attached to. Every pose is computed once; a loop of
    ``relative_to`` or ``attached_to`` references is an :class:`InputError`."""

    def __init__(self, root: ModelScope, limits: LoadLimits | None = None) -> None:
        self.root = root
        self.max_length = (limits or LoadLimits()).max_length_m
        self._poses: dict[tuple[int, str], np.ndarray] = {}
        self._visiting: set[tuple[int, str]] = set()
        self._in_root: dict[int, np.ndarray] = {}
        self._declared: dict[int, dict[str, tuple[str, etree._Element | ModelScope]]] = {}

    # -- declarations ------------------------------------------------------------------------

    def declared(self, scope: ModelScope, name: str) -> tuple[str, etree._Element | ModelScope] | None:
        """The kind (link, joint, frame, model) and element of frame ``name`` of ``scope`` (the
        first of that name, in that order; looked up in an index of the scope built once)."""
        index = self._declared.get(id(scope))
        if index is None:
            index = self._declared[id(scope)] = {}
            for kind, elements in (("link", scope.links), ("joint", scope.joints), ("frame", scope.frames)):
                for element in elements:
                    index.setdefault(element.get("name") or "", (kind, element))
            for model in scope.models:
                index.setdefault(model.name, ("model", model))
        return index.get(name)

    def names(self, scope: ModelScope) -> str:
        found = [e.get("name") or "" for e in (*scope.links, *scope.joints, *scope.frames)]
        found += [m.name for m in scope.models]
        return ", ".join([MODEL_FRAME, *found])

    def relative_to(self, scope: ModelScope, pose: etree._Element | None) -> str | None:
        """The frame a ``<pose>`` names, ``None`` for its element's default."""
        if pose is None:
            return None
        if scope.version < FIRST_FRAME_SEMANTICS:
            frame = (pose.get("frame") or "").strip()
            if frame:
                raise InputError(
                    f'{scope.where(pose)}: <pose frame="{frame}">: SDFormat {scope.version[0]}.{scope.version[1]} '
                    "gives this attribute no meaning (libsdformat ignores it); write the pose relative to the "
                    "default frame, or use SDFormat 1.7's relative_to"
                )
            return None
        return (pose.get("relative_to") or "").strip() or None

    # -- poses --------------------------------------------------------------------------------

    def pose(self, scope: ModelScope, name: str, where: str) -> np.ndarray:
        """Pose (4, 4) of frame ``name`` of ``scope`` in the model frame of ``scope``.

        A chain of frames each placed relative to the next is followed in a loop, not by
        recursion: a legal chain of any length resolves (900 frames used to exceed Python's
        recursion limit); only nested models (``inner::frame``, placement frames) recurse, as
        deep as the models nest."""
        steps: list[tuple[tuple[int, str], np.ndarray]] = []  # frames met, each with its pose in the next
        try:
            while True:
                if name == MODEL_FRAME:
                    base = np.eye(4)
                    break
                if name == WORLD and self.declared(scope, WORLD) is None:  # a joint whose child is the world
                    base = inverse(self.in_root(scope)) @ self.world_in_root()
                    break
                head, sep, rest = name.partition("::")
                if sep and self.declared(scope, name) is None:  # a partially flattened model names ``M1::L1`` as is
                    nested = next((m for m in scope.models if m.name == head), None)
                    if nested is None:
                        raise InputError(f"{where}: '{name}' names no nested model '{head}' in model '{scope.label}'")
                    base = self.pose(scope, head, where) @ self.pose(nested, rest, where)
                    break
                key = (id(scope), name)
                cached = self._poses.get(key)
                if cached is not None:
                    base = cached
                    break
                found = self.declared(scope, name)
                if found is None:
                    raise InputError(
                        f"{where}: '{name}' is no frame of model '{scope.label}' (its frames: {self.names(scope)})"
                    )
                if key in self._visiting:
                    raise InputError(
                        f"{where}: the poses of model '{scope.label}' refer to each other in a loop through '{name}'"
                    )
                self._visiting.add(key)
                kind, element = found
                local, name, where = self.step(scope, kind, element)
                steps.append((key, local))
        finally:
            for key, _ in steps:
                self._visiting.discard(key)
        for key, local in reversed(steps):
            base = base @ local
            self._poses[key] = base
        return base

    def step(self, scope: ModelScope, kind: str, element: etree._Element | ModelScope) -> tuple[np.ndarray, str, str]:
        """One frame of a chain: its pose in the frame it is placed relative to, that frame's
        name, and where the pose is written (for messages)."""
        if isinstance(element, ModelScope):  # a nested model: its model frame in the frame of ``scope``
            where = scope.where(element.pose if element.pose is not None else element.element)
            local = pose_matrix(element.pose, where, self.max_length)
            if element.placement:
                local = local @ inverse(self.pose(element, element.placement, where))
            return local, self.relative_to(scope, element.pose) or MODEL_FRAME, where
        pose = pose_child(element)
        where = scope.where(pose if pose is not None else element)
        base = self.relative_to(scope, pose)
        if base is None:
            if kind == "joint":
                base = (element.findtext("child") or "").strip()
                if not base:
                    raise InputError(f"{scope.where(element)}: <joint name='{element.get('name')}'> has no <child>")
            elif kind == "frame":
                base = (element.get("attached_to") or "").strip() or MODEL_FRAME
            else:
                base = MODEL_FRAME
        return pose_matrix(pose, where, self.max_length), base, where

    def in_root(self, scope: ModelScope) -> np.ndarray:
        """The model frame of ``scope`` in the root model's frame."""
        key = id(scope)
        if key not in self._in_root:
            if scope.parent is None:
                self._in_root[key] = np.eye(4)
            else:
                where = scope.parent.where(scope.element)
                self._in_root[key] = self.in_root(scope.parent) @ self.pose(scope.parent, scope.name, where)
        return self._in_root[key]

    def world_in_root(self) -> np.ndarray:
        """The world frame in the root model's frame: where the root model's ``<pose>`` puts it."""
        pose = self.root.pose
        where = self.root.where(pose if pose is not None else self.root.element)
        return inverse(pose_matrix(pose, where, self.max_length))

    def root_pose(self, scope: ModelScope, name: str, where: str) -> np.ndarray:
        """Pose (4, 4) of frame ``name`` of ``scope`` in the root model's frame."""
        return self.in_root(scope) @ self.pose(scope, name, where)

    def placed(self, scope: ModelScope, pose: etree._Element | None, default: str, where: str) -> np.ndarray:
        """Where a ``<pose>`` of an element whose default frame is ``default`` puts it, in the
        model frame of ``scope``."""
        base = self.relative_to(scope, pose) or default
        return self.pose(scope, base, where) @ pose_matrix(pose, where, self.max_length)

    # -- attachment ---------------------------------------------------------------------------

    def link_of(self, scope: ModelScope, name: str, where: str) -> str:
        """The full name of the link frame ``name`` of ``scope`` is attached to (``world`` for
        the world frame): a link itself, a joint's child link, a frame's ``attached_to``, a
        model's canonical link (followed in a loop: a chain of any length resolves)."""
        seen: set[tuple[int, str]] = set()
        while True:
            if name == WORLD and self.declared(scope, WORLD) is None:
                return WORLD  # the world frame, unless the model has a link of that name (SDFormat 1.4's rule)
            if (id(scope), name) in seen:
                raise InputError(f"{where}: the frames of model '{scope.label}' are attached to each other in a loop")
            seen.add((id(scope), name))
            if name == MODEL_FRAME:
                return self.canonical(scope, where)
            head, sep, rest = name.partition("::")
            if sep and self.declared(scope, name) is None:
                nested = next((m for m in scope.models if m.name == head), None)
                if nested is None:
                    raise InputError(f"{where}: '{name}' names no nested model '{head}' in model '{scope.label}'")
                scope, name = nested, rest
                continue
            found = self.declared(scope, name)
            if found is None:
                raise InputError(
                    f"{where}: '{name}' is no frame of model '{scope.label}' (its frames: {self.names(scope)})"
                )
            kind, element = found
            if isinstance(element, ModelScope):
                return self.canonical(element, where)
            if kind == "link":
                return scope.prefix + name
            if kind == "joint":
                name = (element.findtext("child") or "").strip()
            else:
                name = (element.get("attached_to") or "").strip() or MODEL_FRAME

    def canonical(self, scope: ModelScope, where: str) -> str:
        """The canonical link of ``scope``: ``@canonical_link``, else its first link, else its
        first nested model's."""
        named = (scope.element.get("canonical_link") or "").strip()
        if named:
            return self.link_of(scope, named, where)
        if scope.links:
            return scope.prefix + (scope.links[0].get("name") or "")
        if scope.models:
            return self.canonical(scope.models[0], where)
        raise InputError(f"{where}: model '{scope.label}' has no link to attach its frame to")
