"""SDFormat (Gazebo) descriptions: one ``<model>`` (SDFormat 1.4 to 1.11), with its nested and
included models, mapped onto :mod:`geomcheck.model`.

Reading and includes are :mod:`geomcheck.load.sdf_read`'s, poses and frames
:mod:`geomcheck.load.sdf_frames`' (libsdformat's semantics). Mapping:

- link -> :class:`Link` named by its scoped name (``create::base`` for link ``base`` of a nested
  or included model ``create``), at its SDF pose: the root link is geomcheck's origin, so every
  link sits where the model frame puts it relative to the root link. A link without
  ``<inertial>`` has no :class:`Inertial` (libsdformat would give it 1 kg and a unit tensor,
  which no author meant); ``<inertial>`` values missing inside one take SDFormat's defaults
  (mass 1, moments 1, products 0). ``<inertial auto="true">`` (1.11) is refused.
- collision / visual -> :class:`Shape` in the link frame. Box, cylinder, sphere and mesh map
  exactly (``<uri>`` and ``<scale>``; ``model://NAME`` is ``package://NAME``); a capsule is a
  :class:`Capsule` and a cone (1.11) a :class:`Cone`, each measured as the cylinder that encloses
  it, and an ellipsoid the enclosing cylinder (two equal radii) or box marked ``ellipsoid``, as
  for MJCF. A plane, a missing or empty ``<geometry>`` and ``<empty/>`` are no robot part and are
  skipped (libsdformat loads them). A ``<submesh>``, height map, image or polyline, and a tag
  that is no SDFormat shape (which libsdformat ignores), load and are listed as skipped:
  geomcheck does not measure them.
- joint -> :class:`Joint` from its parent link (``world`` becomes a link ``world``, made by the
  loader and not counted) to its child link, with the type the author wrote: ``revolute``,
  ``continuous``, ``prismatic``, ``fixed``, and ``ball``, ``screw``, ``gearbox``, which geomcheck
  holds at their reference (:data:`geomcheck.model.SDF_JOINT_TYPES` lists SDFormat's types).
  ``universal`` and ``revolute2`` turn about two axes: the author's joint is the first axis (its
  ``declared_type`` the written one), and a second revolute joint ``<joint>::axis2`` the loader
  makes turns after it. A joint turns about its own frame, whose origin SDFormat places relative
  to the child link: when that origin is off the child link's origin a revolute joint moves an
  intermediate link ``<child>::<joint>`` without geometry at the joint frame (as MJCF's anchors),
  hung by a fixed joint ``<child>_anchor``. Links and joints the loader makes are ``synthetic``
  (a joint's ``author`` names the joint it stands for): they are not counted, and no finding
  names them. Limits are radians or metres; SDFormat's "no limit" (its default, 1e16) and an
  infinite bound are open, and an effort or velocity of -1 (unlimited) none. The axis is
  normalised as libsdformat normalises it.
- checked as libsdformat checks (:mod:`geomcheck.load.sdf_validate`): what it refuses is an
  :class:`InputError` worded as its error; links and nested models without a joint are free
  bodies, which SDFormat allows (GC115 is information on SDF).
- ``<self_collide>``: Gazebo collides two links of one model only when either self-collides (a
  link's ``<self_collide>``, else its model's, else false) and never two links joined by a joint;
  those pairs are the description's collision filter, as an SRDF's disabled pairs are URDF's.
- not read: sensors, plugins, surfaces, ``<static>``. A link that is the child of several joints
  (a kinematic loop, which SDFormat allows and gz-physics dartsim refuses) is GC117: the model is
  a tree. Joint parents and children are resolved in the scope of their model (``create::base``
  from the model that includes ``create``), so a joint written backwards across included models
  is GC117's too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np

from geomcheck.diagnostics import SkippedCheck
from geomcheck.errors import InputError
from geomcheck.load.description import ExpandedDocument, LoadedDescription
from geomcheck.load.sdf_frames import (
    MODEL_FRAME,
    WORLD,
    Frames,
    inverse,
    number,
    numbers,
    pose_child,
    vec3,
    within,
)
from geomcheck.load.sdf_geometry import UNMEASURED_GEOMETRY, geometry_of
from geomcheck.load.sdf_read import FIRST_FRAME_SEMANTICS, ModelScope, SdfReader
from geomcheck.load.sdf_validate import validate
from geomcheck.load.srdf import DisabledPair, Srdf
from geomcheck.model import (
    Inertial,
    Joint,
    Limit,
    Link,
    Mimic,
    Pose,
    Robot,
    Shape,
    SourceLocation,
)
from geomcheck.thresholds import LoadLimits

if TYPE_CHECKING:
    from lxml import etree

    from geomcheck.load.bundle import Bundle

ANCHOR_EPS_M = 1e-12  # a joint frame closer than this to its child link's origin is at the origin [m]
SAME_JOINT_TYPES = ("revolute", "continuous", "prismatic")
TWO_AXIS_TYPES = ("universal", "revolute2")
MOVING_TYPES = (*SAME_JOINT_TYPES, *TWO_AXIS_TYPES)  # the joints geomcheck's kinematics moves
_LIMITS = LoadLimits()
DEFAULT_AXIS = (0.0, 0.0, 1.0)  # SDFormat's //axis/xyz default (URDF's is x)
# SDFormat's defaults of an <inertia> element's entries [kg m^2]
INERTIA_DEFAULTS = {"ixx": 1.0, "ixy": 0.0, "ixz": 0.0, "iyy": 1.0, "iyz": 0.0, "izz": 1.0}


def pose_of(transform: np.ndarray) -> Pose:
    return Pose.composed(transform[:3, 3], transform[:3, :3])


def limit_value(element: etree._Element, tag: str, default: float, where: str) -> float:
    """A ``<limit>`` entry: a number, or ``inf`` / ``-inf`` (libsdformat's "no limit", written
    out), ``default`` when absent."""
    text = (element.findtext(tag) or "").strip()
    if text.lower() in ("inf", "+inf", "infinity", "-inf", "-infinity"):
        return -math.inf if text.startswith("-") else math.inf
    return number(element, tag, default, where)


def self_collides(scope: ModelScope, link: etree._Element) -> bool:
    """Whether ``link`` collides with the other links of its model in Gazebo: its own
    ``<self_collide>``, else that of the nearest model around it that writes one, else false."""
    for holder in (link, *_enclosing(scope)):
        text = holder.findtext("self_collide")
        if text is not None and text.strip():
            return text.strip().lower() in ("true", "1")
    return False


def _enclosing(scope: ModelScope) -> list[etree._Element]:
    """The elements of ``scope``'s model and of the models around it, innermost first."""
    out: list[etree._Element] = []
    current: ModelScope | None = scope
    while current is not None:
        out.append(current.element)
        current = current.parent
    return out


def _scopes(scope: ModelScope) -> list[ModelScope]:
    """``scope`` and every model nested in it, depth first."""
    out = [scope]
    for nested in scope.models:
        out += _scopes(nested)
    return out


@dataclass
class Built:
    links: list[Link] = field(default_factory=list)
    joints: list[Joint] = field(default_factory=list)


class Mapper:
    """Builds the :class:`Robot` of a scope tree."""

    def __init__(self, bundle: Bundle, root: ModelScope, frames: Frames, root_display: str, limits: LoadLimits) -> None:
        self.bundle = bundle
        self.length = (limits.max_length_m, "max_length_m")
        self.scale = (limits.max_mesh_scale, "max_mesh_scale")
        self.mass = (limits.max_mass_kg, "max_mass_kg")
        self.inertia = (limits.max_inertia_kg_m2, "max_inertia_kg_m2")
        self.root = root
        self.frames = frames
        self.root_display = root_display
        self.link_pose: dict[str, np.ndarray] = {}  # full name -> pose in the root model frame
        self.skipped: list[SkippedCheck] = []  # elements geomcheck does not measure
        self.joined: list[tuple[str, str]] = []  # (parent, child) links of every joint of the file
        self.self_collide: dict[str, bool] = {}  # full link name -> whether it collides with the model's links
        # every name of the file's links and joints: a name the loader makes never takes one
        self.taken: set[str] = set()
        for scope in _scopes(root):
            self.taken.update(scope.prefix + (e.get("name") or "") for e in (*scope.links, *scope.joints))

    def location(self, scope: ModelScope, element: etree._Element) -> SourceLocation:
        line = element.sourceline
        return SourceLocation(scope.file, line, None, line if scope.file == self.root_display else None)

    def robot(self) -> Robot:
        built = Built()
        self.add_links(self.root, built)
        self.add_joints(self.root, built)
        ends = {name for j in built.joints for name in (j.parent, j.child)}
        if WORLD in ends and WORLD not in {link.name for link in built.links}:
            where = SourceLocation(self.root_display, self.root.element.sourceline)
            built.links.insert(0, Link(WORLD, location=where, synthetic=True, world=True))
        where = self.location(self.root, self.root.element)
        return Robot(self.root.name, tuple(built.links), tuple(built.joints), where)

    # -- links --------------------------------------------------------------------------------

    def add_links(self, scope: ModelScope, built: Built) -> None:
        for item in scope.items:
            if isinstance(item, ModelScope):
                self.add_links(item, built)
                continue
            name = item.get("name") or ""
            where = scope.where(item)
            pose = self.frames.root_pose(scope, name, where)
            self.link_pose[scope.prefix + name] = pose
            in_scope = self.frames.pose(scope, name, where)
            visuals = self.shapes(scope, item, "visual", in_scope)
            collisions = self.shapes(scope, item, "collision", in_scope)
            inertial = self.inertial(scope, item, in_scope)
            built.links.append(Link(scope.prefix + name, inertial, visuals, collisions, self.location(scope, item)))
            self.self_collide[scope.prefix + name] = self_collides(scope, item)

    def shapes(
        self, scope: ModelScope, link: etree._Element, kind: Literal["visual", "collision"], link_pose: np.ndarray
    ) -> tuple[Shape, ...]:
        out: list[Shape] = []
        to_link = inverse(link_pose)
        for element in link:
            if element.tag != kind:
                continue
            where = scope.where(element)
            geometry = geometry_of(scope, element, self.bundle, self.length, self.scale)
            if geometry is None:
                continue
            if isinstance(geometry, str):  # a shape geomcheck does not measure
                known = geometry in (*UNMEASURED_GEOMETRY, "submesh")
                reason = "is not measured by geomcheck" if known else "is no SDFormat shape (libsdformat ignores it)"
                what = f"{kind} {element.get('name')!r}: <{geometry}> {reason}"
                self.skipped.append(SkippedCheck("geometry", scope.prefix + (link.get("name") or ""), what))
                continue
            placed = self.frames.placed(scope, pose_child(element), link.get("name") or "", where)
            origin = pose_of(to_link @ placed)
            out.append(Shape(kind, len(out), geometry, origin, element.get("name"), self.location(scope, element)))
        return tuple(out)

    def inertial(self, scope: ModelScope, link: etree._Element, link_pose: np.ndarray) -> Inertial | None:
        element = link.find("inertial")
        if element is None:
            return None
        where = scope.where(element)
        if (element.get("auto") or "").strip().lower() in ("true", "1"):
            raise InputError(
                f'{where}: <inertial auto="true"> (inertia computed by libsdformat from the collisions) '
                "is not supported; write the mass and inertia"
            )
        placed = self.frames.placed(scope, pose_child(element), link.get("name") or "", where)
        origin = pose_of(inverse(link_pose) @ placed)
        tensor = element.find("inertia")
        moments = dict(INERTIA_DEFAULTS)
        if tensor is not None:
            moments = {
                key: number(tensor, key, default, scope.where(tensor), self.inertia) for key, default in moments.items()
            }
        return Inertial(
            number(element, "mass", 1.0, where, self.mass),
            origin,
            ixx=moments["ixx"],
            ixy=moments["ixy"],
            ixz=moments["ixz"],
            iyy=moments["iyy"],
            iyz=moments["iyz"],
            izz=moments["izz"],
            location=self.location(scope, element),
        )

    # -- joints -------------------------------------------------------------------------------

    def add_joints(self, scope: ModelScope, built: Built) -> None:
        for element in scope.joints:
            built.joints += self.joint(scope, element, built)
        for nested in scope.models:
            self.add_joints(nested, built)

    def end(self, scope: ModelScope, element: etree._Element, tag: str) -> str:
        where = scope.where(element)
        name = (element.findtext(tag) or "").strip()
        if not name:
            raise InputError(f"{where}: <joint name='{element.get('name')}'> has no <{tag}>")
        return self.frames.link_of(scope, name, where)

    def frame_of(self, link: str) -> np.ndarray:
        """Pose of link ``link`` in the root model frame; the world frame where the root model's pose puts it."""
        if link == WORLD and link not in self.link_pose:
            return self.frames.world_in_root()
        return self.link_pose[link]

    def axis(self, scope: ModelScope, joint: etree._Element, tag: str, joint_pose: np.ndarray) -> np.ndarray:
        """The unit axis ``tag`` (axis, axis2) of ``joint`` in the joint frame; SDFormat's z when absent."""
        element = joint.find(tag)
        where = scope.where(element if element is not None else joint)
        if element is None:
            return np.array(DEFAULT_AXIS)
        xyz = element.find("xyz")
        text = xyz.text if xyz is not None and (xyz.text or "").strip() else None
        vector = np.array(numbers(text, (3,), where, f"<{tag}><xyz>")) if text else np.array(DEFAULT_AXIS)
        frame = ((xyz.get("expressed_in") if xyz is not None else None) or "").strip() or None
        if frame is None and scope.version < FIRST_FRAME_SEMANTICS:
            in_model = scope.version < (1, 5) or (element.findtext("use_parent_model_frame") or "").strip().lower() in (
                "true",
                "1",
            )
            frame = MODEL_FRAME if in_model else None
        if frame is not None:
            rotation = self.frames.root_pose(scope, frame, where)[:3, :3]
            vector = joint_pose[:3, :3].T @ rotation @ vector
        norm = float(np.linalg.norm(vector))
        return vector / norm if norm > 0.0 else vector

    def limit(self, joint: etree._Element, tag: str, where: str) -> Limit:
        """The ``<limit>`` of axis ``tag``: SDFormat's no-limit default is an open bound."""
        element = joint.find(f"{tag}/limit")
        bound = _LIMITS.unlimited_joint_bound
        if element is None:
            return Limit(unlimited=True)
        lower = limit_value(element, "lower", -bound, where)
        upper = limit_value(element, "upper", bound, where)
        effort = limit_value(element, "effort", -1.0, where)
        velocity = limit_value(element, "velocity", -1.0, where)
        open_lower, open_upper = abs(lower) >= bound, abs(upper) >= bound
        within(
            [v for v, open_ in ((lower, open_lower), (upper, open_upper)) if not open_], self.length, where, "<limit>"
        )
        return Limit(
            None if open_lower else lower,
            None if open_upper else upper,
            effort if 0.0 <= effort < math.inf else None,
            velocity if 0.0 <= velocity < math.inf else None,
            unlimited=open_lower or open_upper,
        )

    def joint(self, scope: ModelScope, element: etree._Element, built: Built) -> list[Joint]:
        where = scope.where(element)
        name = scope.prefix + (element.get("name") or "")
        kind = (element.get("type") or "").strip()
        parent, child = self.end(scope, element, "parent"), self.end(scope, element, "child")
        self.joined.append((parent, child))
        location = self.location(scope, element)
        joint_pose = self.frames.root_pose(scope, element.get("name") or "", where)
        parent_pose, child_pose = self.frame_of(parent), self.frame_of(child)
        to_parent = inverse(parent_pose)
        mimic = self.mimic(scope, element)
        if kind not in MOVING_TYPES:  # fixed, and what geomcheck holds at its reference: ball, screw, gearbox
            origin = pose_of(to_parent @ child_pose)
            return [Joint(name, kind, parent, child, origin, location=location, mimic=mimic)]
        axis = self.axis(scope, element, "axis", joint_pose)
        limit = None if kind == "continuous" else self.limit(element, "axis", where)
        offset = inverse(joint_pose) @ child_pose  # the child link in the joint frame
        at_origin = float(np.linalg.norm(offset[:3, 3])) <= ANCHOR_EPS_M
        if kind in SAME_JOINT_TYPES and (kind == "prismatic" or at_origin):
            # the joint frame and the child link share an origin (a prismatic axis has none):
            # the joint moves the child link itself, its axis turned into the child's frame
            in_child = offset[:3, :3].T @ axis
            origin = pose_of(to_parent @ child_pose)
            return [Joint(name, kind, parent, child, origin, vec3(in_child), limit, mimic, location)]
        between = self.loader_name(f"{child}::{element.get('name') or ''}")
        built.links.append(Link(between, location=location, synthetic=True))
        two_axes = kind in TWO_AXIS_TYPES
        first = Joint(
            name,
            "revolute" if two_axes else kind,
            parent,
            between,
            pose_of(to_parent @ joint_pose),
            vec3(axis),
            limit,
            mimic,
            location,
            declared_type=kind if two_axes else None,
        )
        joints = [first]
        if two_axes:  # the second axis turns about the joint frame too, after the first
            joints.append(self.second_axis(scope, element, built, first, child, joint_pose))
            between = joints[-1].child
        anchor = self.loader_name(f"{child}_anchor")
        joints.append(
            Joint(anchor, "fixed", between, child, pose_of(offset), location=location, synthetic=True, author=name)
        )
        return joints

    def second_axis(
        self, scope: ModelScope, element: etree._Element, built: Built, first: Joint, child: str, joint_pose: np.ndarray
    ) -> Joint:
        """The revolute joint of the ``<axis2>`` of a two-axis joint to link ``child``: from the
        synthetic link after its ``first`` axis to a new synthetic link."""
        name, between, location = first.name, first.child, first.location
        axis2 = self.axis(scope, element, "axis2", joint_pose)
        turned = self.loader_name(f"{child}::{element.get('name') or ''}::axis2")
        built.links.append(Link(turned, location=location, synthetic=True))
        return Joint(
            self.loader_name(f"{name}::axis2"),
            "revolute",
            between,
            turned,
            Pose(),
            vec3(axis2),
            self.limit(element, "axis2", scope.where(element)),
            location=location,
            synthetic=True,
            author=name,
        )

    def mimic(self, scope: ModelScope, element: etree._Element) -> Mimic | None:
        """The ``<axis><mimic>`` of a joint (SDFormat 1.11): the leader joint in the same model."""
        found = element.find("axis/mimic")
        if found is None:
            return None
        where = scope.where(found)
        leader = scope.prefix + (found.get("joint") or "").strip()
        return Mimic(leader, number(found, "multiplier", 1.0, where), number(found, "offset", 0.0, where))

    def collision_filter(self, robot: Robot) -> Srdf | None:
        """The link pairs Gazebo never collides, as disabled pairs: links joined by a joint
        (``Adjacent``), and two links neither of which self-collides (``self_collide``: a link's
        ``<self_collide>``, else its model's, else false; two links of a model collide when either
        does)."""
        with_geometry = [link for link in robot.links if link.collisions and link.authored]
        joined = {tuple(sorted(pair)) for pair in self.joined}
        disabled: list[DisabledPair] = []
        for i, first in enumerate(with_geometry):
            for second in with_geometry[i + 1 :]:
                pair = tuple(sorted((first.name, second.name)))
                reason = ""
                if pair in joined:
                    reason = "Adjacent"
                elif not (self.self_collide.get(first.name) or self.self_collide.get(second.name)):
                    reason = "self_collide"
                if reason:
                    where = second.location or SourceLocation(self.root_display)
                    disabled.append(DisabledPair(pair[0], pair[1], reason, where))
        if not disabled:
            return None
        return Srdf(robot_name="", source=self.root_display, disabled=tuple(disabled), location=disabled[0].location)

    def loader_name(self, wanted: str) -> str:
        """``wanted``, or ``wanted2``... when the file or the loader already uses it."""
        out = self.unique(wanted, self.taken)
        self.taken.add(out)
        return out

    @staticmethod
    def unique(name: str, taken: set[str]) -> str:
        out, k = name, 1
        while out in taken:
            k += 1
            out = f"{name}{k}"
        return out


def load_sdf(bundle: Bundle, limits: LoadLimits, data: bytes) -> LoadedDescription:
    """The SDFormat description of ``bundle`` whose root file holds ``data``."""
    display = bundle.display(bundle.root_file)
    reader = SdfReader(bundle, limits)
    root = reader.root_model(data)
    validate(root)
    mapper = Mapper(bundle, root, Frames(root, limits), display, limits)
    robot = mapper.robot()
    text = reader.sources[display]
    document = ExpandedDocument(text=text, root=display, sources=dict(reader.sources), is_xacro=False)
    return LoadedDescription(
        bundle,
        robot,
        document,
        (),
        format="sdf",
        declared_collision_filter=mapper.collision_filter(robot),
        skipped=tuple(mapper.skipped),
    )
