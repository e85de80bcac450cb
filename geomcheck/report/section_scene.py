"""The ``scene`` report section as typed data: the robot as the 3D view draws it.

Written by the scene family (geomcheck/checks/scene.py) as JSON-ready dicts, documented in
docs/report-schema.md; readers parse it here and use named fields. ``from_dict`` tolerates
the keys an older or hand-written report leaves out; ``to_dict`` writes the keys, in the
order, the family writes them, so a parsed section serialises back to the same JSON. Parts
no reader interprets (poses, element geometry, the packed meshes) stay JSON objects.

:meth:`Scene.link_poses` poses the links for any joint values from the frame tree, in plain
Python (a report renders without numpy): what the view shows of a sweep's closest approach
comes from here, not from the page's script.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

JSONObject = Mapping[str, Any]
Matrix = list[list[float]]  # 4 x 4, row-major


@dataclass(frozen=True)
class SceneFrame:
    """How ``frame`` follows from ``parent``: ``parent @ origin @ motion(value)``, the
    ``motion`` (``fixed``, ``rotation``, ``translation``) along the unit ``axis`` of the joint
    frame by ``multiplier * variable + offset`` [rad or m]."""

    frame: str
    parent: str
    joint: str = ""
    origin: JSONObject | None = None
    motion: str = "fixed"
    axis: tuple[float, ...] = (1.0, 0.0, 0.0)
    variable: str | None = None
    multiplier: float = 1.0
    offset: float = 0.0

    @classmethod
    def from_dict(cls, data: JSONObject) -> SceneFrame:
        return cls(
            frame=str(data.get("frame", "")),
            parent=str(data.get("parent", "")),
            joint=str(data.get("joint", "")),
            origin=data.get("origin"),
            motion=str(data.get("motion", "fixed")),
            axis=tuple(data.get("axis") or (1.0, 0.0, 0.0)),
            variable=data.get("variable"),
            multiplier=data.get("multiplier", 1.0),
            offset=data.get("offset", 0.0),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "frame": self.frame,
            "parent": self.parent,
            "joint": self.joint,
            "origin": self.origin,
            "motion": self.motion,
            "axis": list(self.axis),
            "variable": self.variable,
            "multiplier": self.multiplier,
            "offset": self.offset,
        }


@dataclass(frozen=True)
class SceneVariable:
    """A joint the configuration sets: its range and its ``value`` at the default pose."""

    joint: str
    type: str = "revolute"
    lower: float = 0.0
    upper: float = 0.0
    value: float = 0.0

    @classmethod
    def from_dict(cls, data: JSONObject) -> SceneVariable:
        return cls(
            joint=str(data.get("joint", "")),
            type=str(data.get("type", "revolute")),
            lower=data.get("lower", 0.0),
            upper=data.get("upper", 0.0),
            value=data.get("value", 0.0),
        )

    def to_dict(self) -> dict[str, Any]:
        return {"joint": self.joint, "type": self.type, "lower": self.lower, "upper": self.upper, "value": self.value}


@dataclass(frozen=True)
class SceneElement:
    """A visual or collision element: its ``label`` (as findings name it), ``origin`` in the
    link frame and ``geometry`` (``{type: box, size}``, ``{type: cylinder, radius, length}``,
    ``{type: sphere, radius}``, ``{type: mesh, mesh: index or null, problem}``)."""

    label: str
    origin: JSONObject | None = None
    geometry: JSONObject | None = None

    @classmethod
    def from_dict(cls, data: JSONObject) -> SceneElement:
        return cls(label=str(data.get("label", "")), origin=data.get("origin"), geometry=data.get("geometry"))

    def to_dict(self) -> dict[str, Any]:
        return {"label": self.label, "origin": self.origin, "geometry": self.geometry}


@dataclass(frozen=True)
class SceneLink:
    """A placed link: its world ``pose`` at the default configuration and its elements."""

    link: str
    pose: JSONObject | None = None
    visuals: tuple[SceneElement, ...] = ()
    collisions: tuple[SceneElement, ...] = ()

    @classmethod
    def from_dict(cls, data: JSONObject) -> SceneLink:
        return cls(
            link=str(data.get("link", "")),
            pose=data.get("pose"),
            visuals=tuple(SceneElement.from_dict(e) for e in data.get("visuals") or ()),
            collisions=tuple(SceneElement.from_dict(e) for e in data.get("collisions") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "link": self.link,
            "pose": self.pose,
            "visuals": [e.to_dict() for e in self.visuals],
            "collisions": [e.to_dict() for e in self.collisions],
        }


@dataclass(frozen=True)
class Scene:
    """The ``scene`` section: the tree's ``root`` frame, its ``frames`` (parents first), the
    configuration ``variables``, the placed ``links``, the packed ``meshes`` (JSON objects:
    ``file``, ``scale``, ``triangles``, ``source_triangles``, ``origin``, ``step``,
    ``positions``, ``indices``, ``index_bytes``) and the links with geometry no joint places
    (``unplaced``)."""

    root: str = ""
    frames: tuple[SceneFrame, ...] = ()
    variables: tuple[SceneVariable, ...] = ()
    links: tuple[SceneLink, ...] = ()
    meshes: tuple[JSONObject, ...] = ()
    unplaced: tuple[str, ...] = ()

    @classmethod
    def from_dict(cls, data: JSONObject) -> Scene:
        return cls(
            root=str(data.get("root", "")),
            frames=tuple(SceneFrame.from_dict(f) for f in data.get("frames") or ()),
            variables=tuple(SceneVariable.from_dict(v) for v in data.get("variables") or ()),
            links=tuple(SceneLink.from_dict(link) for link in data.get("links") or ()),
            meshes=tuple(data.get("meshes") or ()),
            unplaced=tuple(str(x) for x in data.get("unplaced") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "root": self.root,
            "frames": [f.to_dict() for f in self.frames],
            "variables": [v.to_dict() for v in self.variables],
            "links": [link.to_dict() for link in self.links],
            "meshes": [dict(m) for m in self.meshes],
            "unplaced": list(self.unplaced),
        }

    @property
    def triangles(self) -> int:
        """Triangles of the packed meshes."""
        return sum(int(m.get("triangles") or 0) for m in self.meshes)

    def default_values(self) -> dict[str, float]:
        return {v.joint: float(v.value) for v in self.variables}

    def link_poses(self, values: Mapping[str, float] | None = None) -> dict[str, Matrix]:
        """World-from-link transforms of the placed links with ``values`` ({joint: [rad] or
        [m]}) over the default configuration."""
        q = self.default_values() | dict(values or {})
        world: dict[str, Matrix] = {self.root: identity()}
        for f in self.frames:
            parent = world.get(f.parent)
            if parent is None:
                continue
            placed = times(parent, pose_matrix(f.origin))
            if f.motion != "fixed" and f.variable is not None:
                value = float(f.multiplier) * q.get(f.variable, 0.0) + float(f.offset)
                placed = times(placed, motion_matrix(f.motion, f.axis, value))
            world[f.frame] = placed
        return {link.link: world[link.link] for link in self.links if link.link in world}

    def moved_links(self, joint: str) -> tuple[str, ...]:
        """The placed links a variable moves (its frames' descendants), in the links' order."""
        moving = {f.frame for f in self.frames if f.variable == joint and f.motion != "fixed"}
        for f in self.frames:  # parents first: one pass reaches every descendant
            if f.parent in moving:
                moving.add(f.frame)
        return tuple(link.link for link in self.links if link.link in moving)


def identity() -> Matrix:
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def times(a: Matrix, b: Matrix) -> Matrix:
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def pose_matrix(pose: JSONObject | None) -> Matrix:
    """``{xyz, rpy}`` (URDF: ``R = Rz(yaw) Ry(pitch) Rx(roll)``) as a transform."""
    pose = pose or {}
    x, y, z = (float(v) for v in pose.get("xyz") or (0.0, 0.0, 0.0))
    r, p, w = (float(v) for v in pose.get("rpy") or (0.0, 0.0, 0.0))
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(w), math.sin(w)
    return [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, x],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr, y],
        [-sp, cp * sr, cp * cr, z],
        [0.0, 0.0, 0.0, 1.0],
    ]


def motion_matrix(motion: str, axis: Sequence[float], value: float) -> Matrix:
    """A rotation about (Rodrigues) or a translation along the unit ``axis``."""
    ax, ay, az = (float(v) for v in axis)
    if motion == "translation":
        return [[1.0, 0.0, 0.0, ax * value], [0.0, 1.0, 0.0, ay * value], [0.0, 0.0, 1.0, az * value], [0, 0, 0, 1.0]]
    c, s = math.cos(value), math.sin(value)
    t = 1.0 - c
    return [
        [c + ax * ax * t, ax * ay * t - az * s, ax * az * t + ay * s, 0.0],
        [ay * ax * t + az * s, c + ay * ay * t, ay * az * t - ax * s, 0.0],
        [az * ax * t - ay * s, az * ay * t + ax * s, c + az * az * t, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]


def matrix_pose(m: Matrix) -> dict[str, list[float]]:
    """A transform as ``{xyz, rpy}`` (the inverse of :func:`pose_matrix`; yaw zero at gimbal lock)."""
    pitch = math.asin(max(-1.0, min(1.0, -m[2][0])))
    if math.hypot(m[0][0], m[1][0]) > 1e-9:
        roll, yaw = math.atan2(m[2][1], m[2][2]), math.atan2(m[1][0], m[0][0])
    else:
        roll, yaw = math.atan2(-m[1][2], m[1][1]), 0.0
    return {"xyz": [round(m[0][3], 9), round(m[1][3], 9), round(m[2][3], 9)], "rpy": [roll, pitch, yaw]}


def scene_section(sections: Mapping[str, Any]) -> Scene | None:
    """The report's ``scene`` section, parsed; ``None`` when the family did not run."""
    data = sections.get("scene")
    return Scene.from_dict(data) if isinstance(data, Mapping) else None
