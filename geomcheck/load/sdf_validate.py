"""What libsdformat refuses in a model, refused in its own words before any pose is computed.

libsdformat (``sdf::Root::Load``, ``gz sdf --check``) refuses a model file for reasons that do
not depend on the frames a loader happens to use: names (duplicates among siblings of one
kind, links, joints, frames and nested models sharing a name from SDFormat 1.7, names that are
reserved), a model without a link, references that name no frame (``attached_to``,
``relative_to``, ``canonical_link``, ``placement_frame``, a joint's parent, child and axis
frame, an axis mimic's leader) or that go round in a loop, a joint between a frame and itself,
a joint whose child is the world, a zero joint axis, and a top-level model placed relative to
anything. Every one is checked here over the whole scope tree, used or not, and refused with an
:class:`InputError` quoting libsdformat's message. Free links and nested models (no joint to
the rest) and kinematic loops are valid SDFormat and are left to the structure checks.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Iterable, Iterator
from typing import TYPE_CHECKING

from geomcheck.errors import InputError
from geomcheck.load.sdf_read import FIRST_FRAME_SEMANTICS, ModelScope

if TYPE_CHECKING:
    from lxml import etree

MODEL_FRAME = "__model__"
WORLD = "world"
ROOT = "__root__"
FIRST_MIMIC = (1, 11)  # the version that brought //axis/mimic
AXES = ("axis", "axis2")
TWO_AXIS_TYPES = ("universal", "revolute2")
NO_AXIS_TYPES = ("fixed", "ball")


def _true(text: str | None) -> bool:
    return (text or "").strip().lower() in ("true", "1")


def _pose(element: etree._Element) -> etree._Element | None:
    return next((c for c in element if c.tag == "pose"), None)


class Validator:
    """The checks of one scope tree; :meth:`run` raises on the first refusal."""

    def __init__(self, root: ModelScope) -> None:
        self.root = root
        self._frames: dict[int, dict[str, str]] = {}  # per scope (by id): the scopes stay as read

    # -- names -------------------------------------------------------------------------------

    def frames_of(self, scope: ModelScope) -> dict[str, str]:
        """The frame names of ``scope`` and their kind (link, joint, frame, model)."""
        known = self._frames.get(id(scope))
        if known is not None:
            return known
        out = self._frames[id(scope)] = {}
        for kind, elements in (("link", scope.links), ("joint", scope.joints), ("frame", scope.frames)):
            for element in elements:
                out.setdefault(element.get("name") or "", kind)
        for model in scope.models:
            out.setdefault(model.name, "model")
        return out

    def resolves(self, scope: ModelScope, name: str) -> bool:
        """Whether ``name`` is a frame of ``scope``: ``__model__``, a sibling, or (SDFormat 1.8)
        ``inner::frame`` of a nested model."""
        if name == MODEL_FRAME:
            return True
        if name in self.frames_of(scope):  # a partially flattened model names ``M1::L1`` as is
            return True
        head, sep, rest = name.partition("::")  # a scoped name, as Gazebo has read them since SDFormat 1.4
        nested = next((m for m in scope.models if m.name == head), None) if sep else None
        return nested is not None and self.resolves(nested, rest)

    def where(self, scope: ModelScope, element: etree._Element) -> str:
        return scope.where(element)

    def refuse(self, scope: ModelScope, element: etree._Element, message: str) -> InputError:
        return InputError(f"{self.where(scope, element)}: {message} (libsdformat refuses the model)")

    def names(self, scope: ModelScope) -> None:
        """Names unique where libsdformat wants them, and none of them reserved."""
        for kind, elements in (("link", scope.links), ("joint", scope.joints), ("frame", scope.frames)):
            self.unique(scope, kind, elements)
        seen_models: set[str] = set()
        for nested in scope.models:
            if nested.name in seen_models:
                raise self.refuse(scope, nested.element, f"model with name[{nested.name}] already exists.")
            seen_models.add(nested.name)
        if scope.version >= FIRST_FRAME_SEMANTICS:
            self.one_namespace(scope)
        for link in scope.links:
            for kind in ("visual", "collision"):
                self.unique(scope, kind, [c for c in link if c.tag == kind])

    def unique(self, scope: ModelScope, kind: str, elements: Iterable[etree._Element]) -> None:
        """The ``<kind>`` ``elements`` of one namespace: no name twice, none reserved."""
        seen: set[str] = set()
        for element in elements:
            name = element.get("name") or ""
            if name in seen:
                raise self.refuse(scope, element, f"{kind} with name[{name}] already exists.")
            seen.add(name)
            self.reserved(scope, element, kind, name)

    def one_namespace(self, scope: ModelScope) -> None:
        """From SDFormat 1.7, links, joints, frames and nested models share one namespace."""
        every = [e.get("name") or "" for e in (*scope.links, *scope.joints, *scope.frames)]
        every += [m.name for m in scope.models]
        shared = [name for name, count in Counter(every).items() if count > 1]
        if shared:
            raise self.refuse(
                scope,
                scope.element,
                f"Non-unique names detected in model with name[{scope.name}]: [{shared[0]}] names two of its "
                "links, joints, frames and nested models, which share one namespace from SDFormat 1.7",
            )

    def reserved(self, scope: ModelScope, element: etree._Element, kind: str, name: str) -> None:
        framed = kind in ("link", "joint", "frame")  # frames share a namespace with the world frame
        if (framed and name == WORLD) or (len(name) > 3 and name.startswith("__") and name.endswith("__")):
            raise self.refuse(scope, element, f"The supplied {kind} name [{name}] is reserved.")

    # -- references --------------------------------------------------------------------------

    def reference(self, scope: ModelScope, element: etree._Element, value: str, attribute: str) -> None:
        if value == ROOT:
            raise self.refuse(
                scope, element, f"'__root__' is reserved; it cannot be used as a value of attribute [{attribute}]"
            )

    def attached(self, scope: ModelScope) -> None:
        """Every ``<frame attached_to>`` names a frame of the model, and no chain of them loops."""
        model = scope.name
        targets: dict[str, str] = {}
        for frame in scope.frames:
            name, target = frame.get("name") or "", (frame.get("attached_to") or "").strip()
            self.reference(scope, frame, target, "attached_to")
            if not target:
                continue
            if target == name:
                raise self.refuse(
                    scope,
                    frame,
                    f"attached_to name[{target}] is identical to frame name[{name}], causing a graph cycle in "
                    f"model with name[{model}].",
                )
            if not self.resolves(scope, target):
                raise self.refuse(
                    scope,
                    frame,
                    f"attached_to name[{target}] specified by frame with name[{name}] does not match a nested "
                    f"model, link, joint, or frame name in model with name[{model}].",
                )
            targets[name] = target
        children = {(j.get("name") or ""): (j.findtext("child") or "").strip() for j in scope.joints}
        links = {link.get("name") or "" for link in scope.links}

        def step(name: str) -> str | None:  # a link ends a chain (before 1.7 a joint may share its name)
            return None if name in links else targets.get(name, children.get(name))

        self.no_loop(scope, (*targets, *children), step, "FrameAttachedToGraph")

    def no_loop(self, scope: ModelScope, starts: Iterable[str], step: Callable[[str], str | None], graph: str) -> None:
        """Raise when following ``step`` (a frame's next frame, ``None`` at the end) from one of
        ``starts`` comes back to a frame already passed on that walk. A walk stops at a frame an
        earlier walk passed (that one ends), so a chain of n frames costs n steps, not n^2."""
        ends: set[str] = set()
        for start in starts:
            walk: set[str] = set()
            name: str | None = start
            while name is not None and name not in ends:
                if name in walk:
                    element = next(
                        (e for e in (*scope.frames, *scope.joints, *scope.links) if e.get("name") == name),
                        scope.element,
                    )
                    raise self.refuse(
                        scope, element, f"{graph} cycle detected, already visited vertex [{scope.name}::{name}]."
                    )
                walk.add(name)
                name = step(name)
            ends |= walk

    def posed(self, scope: ModelScope) -> Iterator[tuple[str, str, etree._Element, str]]:
        """(kind, name, pose element, relative_to) of every pose of ``scope`` that names a frame."""
        for kind, elements in (("link", scope.links), ("joint", scope.joints), ("frame", scope.frames)):
            for element in elements:
                pose = _pose(element)
                if pose is not None and (pose.get("relative_to") or "").strip():
                    yield kind, element.get("name") or "", pose, (pose.get("relative_to") or "").strip()
        for nested in scope.models:
            if nested.pose is not None and (nested.pose.get("relative_to") or "").strip():
                yield "model", nested.name, nested.pose, (nested.pose.get("relative_to") or "").strip()

    def relative(self, scope: ModelScope) -> None:
        """Every ``<pose relative_to>`` names a frame of the model, and no chain of them loops."""
        if scope.version < FIRST_FRAME_SEMANTICS:
            return
        model = scope.name
        bases: dict[str, str] = {}
        for kind, name, pose, target in self.posed(scope):
            self.reference(scope, pose, target, "relative_to")
            if target == name:
                raise self.refuse(
                    scope,
                    pose,
                    f"relative_to name[{target}] is identical to {kind} name[{name}], causing a graph cycle in "
                    f"model with name[{model}].",
                )
            if not self.resolves(scope, target):
                raise self.refuse(
                    scope,
                    pose,
                    f"relative_to name[{target}] specified by {kind} with name[{name}] does not match a nested "
                    f"model, link, joint, or frame name in model with name[{model}].",
                )
            bases[name] = target
        for link in scope.links:  # a link's own elements are placed in the model's frames too
            for element in link:
                pose = _pose(element) if element.tag in ("visual", "collision", "inertial", "sensor") else None
                target = (pose.get("relative_to") or "").strip() if pose is not None else ""
                if pose is None or not target:
                    continue
                self.reference(scope, pose, target, "relative_to")
                if not self.resolves(scope, target):
                    raise self.refuse(
                        scope,
                        pose,
                        f"relative_to name[{target}] specified by {element.tag} with name[{element.get('name')}] "
                        f"does not match a nested model, link, joint, or frame name in model with name[{model}].",
                    )
        defaults = {(f.get("name") or ""): (f.get("attached_to") or "").strip() for f in scope.frames}
        children = {(j.get("name") or ""): (j.findtext("child") or "").strip() for j in scope.joints}

        def base(name: str) -> str | None:
            if name in bases:
                return bases[name]
            return defaults.get(name) or children.get(name) or None

        self.no_loop(scope, bases, base, "PoseRelativeToGraph")

    # -- the model ---------------------------------------------------------------------------

    def model(self, scope: ModelScope) -> None:
        name = scope.name
        static = _true(scope.element.findtext("static"))
        if not static and not scope.links and not scope.models:
            raise self.refuse(scope, scope.element, f"A model must have at least one link. (model [{name}])")
        canonical = (scope.element.get("canonical_link") or "").strip()
        if canonical:
            self.reference(scope, scope.element, canonical, "canonical_link")
            if not self.is_link(scope, canonical):
                raise self.refuse(
                    scope, scope.element, f"canonical_link with name[{canonical}] not found in model with name[{name}]."
                )
        placement = (scope.element.get("placement_frame") or "").strip()
        if placement:
            self.reference(scope, scope.element, placement, "placement_frame")
            if not self.resolves(scope, placement):
                raise self.refuse(scope, scope.element, f"unable to find unique frame with name [{placement}] in graph")

    def is_link(self, scope: ModelScope, name: str) -> bool:
        head, sep, rest = name.partition("::")
        if sep:
            nested = next((m for m in scope.models if m.name == head), None)
            return nested is not None and self.is_link(nested, rest)
        return any((link.get("name") or "") == name for link in scope.links)

    def joints(self, scope: ModelScope) -> None:
        model = scope.name
        for joint in scope.joints:
            name = joint.get("name") or ""
            parent = (joint.findtext("parent") or "").strip()
            child = (joint.findtext("child") or "").strip()
            self.reference(scope, joint, parent, "parent")
            self.reference(scope, joint, child, "child")
            if child == WORLD:
                raise self.refuse(scope, joint, f"Joint with name[{name}] specified invalid child link [world].")
            if parent and parent == name:
                raise self.refuse(
                    scope,
                    joint,
                    f"joint with name[{name}] in model with name[{model}] must not specify its own name as the "
                    "parent frame.",
                )
            if parent and parent == child:
                raise self.refuse(
                    scope,
                    joint,
                    f"Joint with name[{name}] must specify different frame names for parent and child, while "
                    f"[{child}] was specified for both.",
                )
            if child and child != name and not self.resolves(scope, child):
                raise self.refuse(
                    scope,
                    joint,
                    f"Child frame with name[{child}] specified by joint with name[{name}] not found in model with "
                    f"name[{model}].",
                )
            if parent and parent != WORLD and not self.resolves(scope, parent):
                raise self.refuse(
                    scope,
                    joint,
                    f"parent frame with name[{parent}] specified by joint with name[{name}] not found in model "
                    f"with name[{model}].",
                )
            resolved = self.link_of(scope, child)
            if parent != WORLD and resolved is not None and resolved == self.link_of(scope, parent):
                raise self.refuse(
                    scope,
                    joint,
                    f"Joint with name[{name}] specified parent frame [{parent}] and child frame [{child}] that both "
                    f"resolve to [{resolved}], but they should resolve to different values.",
                )
            self.axes(scope, joint)

    def link_of(self, scope: ModelScope, name: str, seen: frozenset[str] = frozenset()) -> str | None:
        """The link frame ``name`` of ``scope`` is attached to (a link, a joint's child, a frame's
        ``attached_to``, a model's canonical link), scoped as ``nested::link``; ``None`` when it
        resolves to none (the checks above name that)."""
        while name not in seen:  # a chain of joints and frames is followed here, not by recursion
            seen = seen | {name}
            if name in ("", MODEL_FRAME):
                return self.canonical_link(scope, seen)
            kinds = self.frames_of(scope)
            head, sep, rest = name.partition("::")
            if name not in kinds and sep:
                return self.link_in(next((m for m in scope.models if m.name == head), None), rest)
            kind = kinds.get(name)
            if kind == "link":
                return name
            if kind == "model":
                return self.link_in(next(m for m in scope.models if m.name == name), "")
            if kind not in ("joint", "frame"):
                return None
            name = self.attached_to(scope, name, kind)
        return None

    def attached_to(self, scope: ModelScope, name: str, kind: str) -> str:
        """The frame joint or frame ``name`` of ``scope`` is attached to: a joint's child, a
        frame's ``attached_to``."""
        if kind == "joint":
            joint = next(j for j in scope.joints if j.get("name") == name)
            return (joint.findtext("child") or "").strip()
        frame = next(f for f in scope.frames if f.get("name") == name)
        return (frame.get("attached_to") or "").strip()

    def canonical_link(self, scope: ModelScope, seen: frozenset[str]) -> str | None:
        """The link the model frame of ``scope`` is attached to: its ``canonical_link``, else its
        first link, else the canonical link of its first nested model that has one."""
        canonical = (scope.element.get("canonical_link") or "").strip()
        if canonical:
            return self.link_of(scope, canonical, seen)
        if scope.links:
            return scope.links[0].get("name") or ""
        return next((f"{m.name}::{found}" for m in scope.models if (found := self.link_of(m, "")) is not None), None)

    def link_in(self, model: ModelScope | None, name: str) -> str | None:
        """:meth:`link_of` ``name`` inside the nested ``model``, scoped by the model's name."""
        found = None if model is None else self.link_of(model, name)
        return None if found is None or model is None else f"{model.name}::{found}"

    def axes(self, scope: ModelScope, joint: etree._Element) -> None:
        name, model = joint.get("name") or "", scope.name
        kind = (joint.get("type") or "").strip()
        if kind in NO_AXIS_TYPES:
            return
        for tag in AXES if kind in TWO_AXIS_TYPES else AXES[:1]:
            axis = joint.find(tag)
            xyz = axis.find("xyz") if axis is not None else None
            if xyz is None:
                continue
            try:
                values = [float(v) for v in (xyz.text or "").split()]
            except ValueError:
                continue  # the loader names the number
            if len(values) == 3 and math.sqrt(sum(v * v for v in values)) == 0.0:
                raise self.refuse(scope, xyz, "The norm of the xyz vector cannot be zero")
            frame = (xyz.get("expressed_in") or "").strip()
            if frame and not self.resolves(scope, frame):  # libsdformat reads it whatever the file's version
                raise self.refuse(
                    scope,
                    xyz,
                    f"axis xyz expressed-in frame with name[{frame}] specified by joint with name[{name}] not "
                    f"found in model with name[{model}]",
                )

    def mimics(self, scope: ModelScope) -> None:
        """An axis ``<mimic>`` (SDFormat 1.11) follows an axis of another joint of the model."""
        if scope.version < FIRST_MIMIC:
            return
        joints = {(j.get("name") or ""): j for j in scope.joints}
        for joint in scope.joints:
            name = joint.get("name") or ""
            for tag in AXES:
                mimic = joint.find(f"{tag}/mimic")
                if mimic is None:
                    continue
                leader, leader_axis = (mimic.get("joint") or "").strip(), (mimic.get("axis") or "axis").strip()
                if leader == name:
                    raise self.refuse(
                        scope, mimic, f"Axis with name [{tag}] in joint with name [{name}] cannot mimic itself."
                    )
                if leader not in joints:
                    raise self.refuse(
                        scope,
                        mimic,
                        f"A joint with name[{leader}] specified by an axis mimic in joint with name[{name}] not found "
                        f"in model with name[{scope.name}].",
                    )
                if leader_axis not in AXES:
                    raise self.refuse(
                        scope,
                        mimic,
                        f"Axis with name [{tag}] in joint with name [{name}] specified an invalid leader axis name "
                        f"[{leader_axis}].",
                    )
                if joints[leader].find(leader_axis) is None:
                    raise self.refuse(
                        scope,
                        mimic,
                        f"Axis with name [{tag}] in joint with name [{name}] specified a leader axis name "
                        f"[{leader_axis}] that is not found in the leader joint with name [{leader}].",
                    )

    def scopes(self, scope: ModelScope) -> Iterable[ModelScope]:
        yield scope
        for nested in scope.models:
            yield from self.scopes(nested)

    def run(self) -> None:
        root = self.root
        pose = root.element.find("pose")
        target = (pose.get("relative_to") or "").strip() if pose is not None else ""
        if target and root.version >= FIRST_FRAME_SEMANTICS:
            raise self.refuse(
                root,
                pose,
                "Attribute //pose[@relative_to] of top level model must be left empty, found "
                f"//pose[@relative_to='{target}'].",
            )
        for scope in self.scopes(root):
            self.model(scope)
            self.names(scope)
            self.attached(scope)
            self.relative(scope)
            self.joints(scope)
            self.mimics(scope)


def validate(root: ModelScope) -> None:
    """Raise :class:`InputError`, in libsdformat's words, for what libsdformat refuses in the
    scope tree ``root`` (see the module docstring)."""
    Validator(root).run()
