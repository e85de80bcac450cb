"""The typed model of a robot description: frozen dataclasses, SI units.

Lengths are [m], angles [rad], masses [kg], inertias [kg m^2]. Every element keeps the
:class:`SourceLocation` of its XML element so diagnostics can point at it.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:  # numpy is imported where a transform is computed: `geomcheck rules` never pays for it
    import numpy as np

Vec3 = tuple[float, float, float]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
JointType = Literal["revolute", "continuous", "prismatic", "fixed", "floating", "planar"]
# SDFormat's joint types (libsdformat's JointType): the model keeps ball, screw and gearbox as
# written (geomcheck's kinematics holds them at their reference, as a floating joint); a
# universal or revolute2 joint is two revolute joints through a frame the loader adds
SDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "ball", "universal", "revolute2", "screw", "gearbox")


GIMBAL_EPS = 1e-9  # |cos(pitch)| below this is treated as gimbal lock [1]
# Decimals a pose composed from several transforms keeps [m, rad]: composing them leaves noise of
# about 1e-16 that differs between CPUs and BLAS kernels (a wheel's roll read as -6.8e-21, or as
# -1.4e-20 on another kernel); a picometre and a picoradian lie far below any written value's
# meaning and far above that noise.
COMPOSED_DECIMALS = 12


def rpy_from_matrix(rotation: np.ndarray) -> tuple[float, float, float]:
    """URDF ``rpy`` [rad] of ``rotation`` (3, 3), the inverse of :meth:`Pose.rotation`
    (``R = Rz(yaw) Ry(pitch) Rx(roll)``); at gimbal lock the yaw is set to zero."""
    import numpy as np

    r = np.asarray(rotation, dtype=float)
    pitch = float(np.arcsin(np.clip(-r[2, 0], -1.0, 1.0)))
    if np.hypot(r[0, 0], r[1, 0]) > GIMBAL_EPS:
        roll = float(np.arctan2(r[2, 1], r[2, 2]))
        yaw = float(np.arctan2(r[1, 0], r[0, 0]))
    else:
        roll = float(np.arctan2(-r[1, 2], r[1, 1]))
        yaw = 0.0
    return roll, pitch, yaw


@dataclass(frozen=True)
class SourceLocation:
    """Where an element comes from.

    ``file`` is the source file as displayed (relative to the bundle's display root, posix
    separators) and ``line``/``column`` the position in it when it could be traced (for
    xacro output, the file that holds the element's text); ``expanded_line`` is the line
    in the expanded URDF document, always known for parsed elements.
    """

    file: str
    line: int | None = None
    column: int | None = None
    expanded_line: int | None = None

    def __str__(self) -> str:
        parts = [self.file]
        if self.line is not None:
            parts.append(str(self.line))
            if self.column is not None:
                parts.append(str(self.column))
        return ":".join(parts)


@dataclass(frozen=True)
class Pose:
    """A rigid transform given as URDF ``<origin xyz rpy>``: translation [m], fixed-axis roll-pitch-yaw [rad]."""

    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)

    def rotation(self) -> np.ndarray:
        """Rotation matrix, shape (3, 3): ``Rz(yaw) @ Ry(pitch) @ Rx(roll)`` as URDF defines it."""
        import numpy as np

        r, p, y = self.rpy
        cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
        return np.array(
            [
                [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                [-sp, cp * sr, cp * cr],
            ]
        )

    @classmethod
    def composed(cls, translation: np.ndarray, rotation: np.ndarray) -> Pose:
        """The pose of ``translation`` (3,) [m] and ``rotation`` (3, 3) computed by composing
        transforms, their float noise rounded away (:data:`COMPOSED_DECIMALS`), so that the
        same description reads the same on every CPU."""

        def clean(values: tuple[float, float, float]) -> Vec3:
            a, b, c = (round(float(v), COMPOSED_DECIMALS) + 0.0 for v in values)  # + 0.0: no -0.0
            return a, b, c

        import numpy as np

        t = translation
        # entries that are zero but for noise become +0.0 first: arctan2(-0.0, -1) is -pi, not pi
        r = np.asarray(rotation, dtype=float)
        r = np.where(np.abs(r) < 10.0**-COMPOSED_DECIMALS, 0.0, r)
        return cls(clean((t[0], t[1], t[2])), clean(rpy_from_matrix(r)))

    def matrix(self) -> np.ndarray:
        """Homogeneous transform, shape (4, 4)."""
        import numpy as np

        out = np.eye(4)
        out[:3, :3] = self.rotation()
        out[:3, 3] = self.xyz
        return out


@dataclass(frozen=True)
class Box:
    size: Vec3  # full edge lengths [m]
    # the shape is the ellipsoid inscribed in the box (MJCF, SDFormat): its extents are the box's,
    # its distances, volume and contacts the ellipsoid's (geometry.primitives, the collision engines)
    ellipsoid: bool = False


@dataclass(frozen=True)
class Cylinder:
    radius: float  # [m]
    length: float  # [m], along the local z axis, centred on the origin
    # the shape is the ellipsoid inscribed in the cylinder, round about z (MJCF, SDFormat): its
    # extents are the cylinder's, its distances, volume and contacts the ellipsoid's
    ellipsoid: bool = False


@dataclass(frozen=True)
class Capsule(Cylinder):
    """A capsule (MJCF, SDFormat, URDF 1.1), measured as the cylinder that encloses it: ``radius``
    and ``length`` are that cylinder's (an enclosing shape never makes coverage look better) and
    :attr:`straight_length` is the capsule's own cylindrical part, as the formats write it."""

    @property
    def straight_length(self) -> float:
        return max(self.length - 2.0 * self.radius, 0.0)


@dataclass(frozen=True)
class Cone(Cylinder):
    """An SDFormat cone of base ``radius`` and height ``length``, measured as the cylinder of
    that radius and length that encloses it."""


def kind_name(geometry: object) -> str:
    """What a geometry is called in a message: its class's name (``box``, ``cylinder``,
    ``capsule``, ``sphere``, ``mesh``), ``ellipsoid`` for a box or cylinder marked so."""
    return "ellipsoid" if getattr(geometry, "ellipsoid", False) else type(geometry).__name__.lower()


@dataclass(frozen=True)
class Sphere:
    radius: float  # [m]


@dataclass(frozen=True)
class Mesh:
    filename: str  # as written in the URDF: package://, file://, absolute or relative
    scale: Vec3 = (1.0, 1.0, 1.0)


Geometry = Box | Cylinder | Sphere | Mesh


@dataclass(frozen=True)
class Shape:
    """A ``<visual>`` or ``<collision>`` element of a link.

    ``index`` is its position among the link's elements of the same ``kind``.
    """

    kind: Literal["visual", "collision"]
    index: int
    geometry: Geometry
    origin: Pose = Pose()
    name: str | None = None
    location: SourceLocation | None = None

    @property
    def label(self) -> str:
        """``visual[0]``, ``collision[1]``: how findings name the element."""
        return f"{self.kind}[{self.index}]"


@dataclass(frozen=True)
class Inertial:
    """``<inertial>``: mass [kg], centre of mass frame, tensor [kg m^2] in that frame."""

    mass: float
    origin: Pose = Pose()
    ixx: float = 0.0
    ixy: float = 0.0
    ixz: float = 0.0
    iyy: float = 0.0
    iyz: float = 0.0
    izz: float = 0.0
    location: SourceLocation | None = None
    # MuJoCo computed mass and tensor from the body's geoms (compiler inertiafromgeom): they
    # describe the collision and visual shapes as solids of the default density, not a measurement
    from_geometry: bool = False

    def tensor(self) -> np.ndarray:
        """Inertia tensor in the ``origin`` frame, shape (3, 3) [kg m^2]."""
        import numpy as np

        return np.array(
            [
                [self.ixx, self.ixy, self.ixz],
                [self.ixy, self.iyy, self.iyz],
                [self.ixz, self.iyz, self.izz],
            ]
        )


@dataclass(frozen=True)
class Link:
    name: str
    inertial: Inertial | None = None
    visuals: tuple[Shape, ...] = ()
    collisions: tuple[Shape, ...] = ()
    location: SourceLocation | None = None
    # a frame the loader adds, not an element of the file: one of several joints of one MJCF
    # body turns it (MuJoCo gives the body's mass to the joints together, none to the frame)
    synthetic: bool = False
    # the world frame (MJCF's world body, SDFormat's world): no format counts it as a link of
    # the robot (MuJoCo's bodies but the world, SDFormat's links)
    world: bool = False

    @property
    def authored(self) -> bool:
        """Whether the link is one the format's own tool counts: neither made by the loader nor the world."""
        return not self.synthetic and not self.world

    @property
    def has_geometry(self) -> bool:
        return bool(self.visuals or self.collisions)


@dataclass(frozen=True)
class Limit:
    """``<limit>``: position bounds ([rad] or [m]), effort, velocity; ``None`` when absent."""

    lower: float | None = None
    upper: float | None = None
    effort: float | None = None
    velocity: float | None = None
    # a bound was written as SDFormat's "no limit" sentinel (|value| >= 1e16, read by Gazebo as
    # unlimited): that bound is ``None`` here, and its absence is not a missing limit
    unlimited: bool = False


@dataclass(frozen=True)
class Mimic:
    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class Joint:
    """``<joint>``. ``type`` is kept as written (an unknown type is a GC1xx finding)."""

    name: str
    type: str
    parent: str
    child: str
    origin: Pose = Pose()
    axis: Vec3 = (1.0, 0.0, 0.0)
    limit: Limit | None = None
    mimic: Mimic | None = None
    location: SourceLocation | None = None
    # a joint the loader adds, not an element of the file (a fixed joint hanging an MJCF body
    # without joints or an anchor frame, the second axis of an SDFormat universal joint):
    # findings name ``author``, the file's joint it realises, or its child link
    synthetic: bool = False
    author: str | None = None
    # the type the file writes when the model's differs (an SDFormat universal joint is a
    # revolute joint followed by a loader-made one)
    declared_type: str | None = None

    @property
    def written_type(self) -> str:
        return self.declared_type or self.type

    @property
    def is_moving(self) -> bool:
        return self.type != "fixed"

    @property
    def written_name(self) -> str:
        """The name the file gives this joint: its own, or for a loader-made one the joint it realises."""
        return self.author or self.name


@dataclass(frozen=True)
class Robot:
    """A parsed ``<robot>``; links and joints in document order. ``closures``: pairs of links a
    loop-closing constraint holds together besides the tree's joints (MJCF's ``<equality>``
    ``connect`` and ``weld``: a linkage's rod pinned to the lever it drives), in document order."""

    name: str
    links: tuple[Link, ...] = ()
    joints: tuple[Joint, ...] = ()
    location: SourceLocation | None = None
    materials: Mapping[str, tuple[float, float, float, float]] = field(default_factory=dict)
    closures: tuple[tuple[str, str], ...] = ()

    @functools.cached_property
    def authored_links(self) -> tuple[Link, ...]:
        """The links the format's own tool counts (urdfdom's links, MuJoCo's bodies but the
        world, SDFormat's links): without the frames the loader adds and the world frame."""
        return tuple(link for link in self.links if link.authored)

    @functools.cached_property
    def authored_joints(self) -> tuple[Joint, ...]:
        """The joints the file declares (MuJoCo's compiled joints, SDFormat's joints): without
        the joints the loader adds."""
        return tuple(joint for joint in self.joints if not joint.synthetic)

    @functools.cached_property
    def link_map(self) -> Mapping[str, Link]:
        """Links by name; the first of duplicates wins."""
        out: dict[str, Link] = {}
        for link in self.links:
            out.setdefault(link.name, link)
        return out

    @functools.cached_property
    def joint_map(self) -> Mapping[str, Joint]:
        """Joints by name; the first of duplicates wins."""
        out: dict[str, Joint] = {}
        for joint in self.joints:
            out.setdefault(joint.name, joint)
        return out

    @functools.cached_property
    def parent_joint(self) -> Mapping[str, Joint]:
        """The joint whose child is each link (the first one when a link has several)."""
        out: dict[str, Joint] = {}
        for joint in self.joints:
            out.setdefault(joint.child, joint)
        return out

    @functools.cached_property
    def child_joints(self) -> Mapping[str, tuple[Joint, ...]]:
        """Joints whose parent is each link, in document order."""
        out: dict[str, list[Joint]] = {}
        for joint in self.joints:
            out.setdefault(joint.parent, []).append(joint)
        return {k: tuple(v) for k, v in out.items()}

    @functools.cached_property
    def roots(self) -> tuple[str, ...]:
        """Declared links that are no joint's child, in document order."""
        children = {j.child for j in self.joints}
        return tuple(link.name for link in self.links if link.name not in children)
