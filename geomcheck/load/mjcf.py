"""MJCF (MuJoCo) descriptions, compiled by MuJoCo and mapped onto :mod:`geomcheck.model`.

MuJoCo's compiler is the authority on what an MJCF file means: default classes, ``<include>``,
``meshdir``/``assetdir``, ``fromto``, angle units, Euler sequences, mesh scale, inertia inferred
from geometry and automatic limits are all applied by MuJoCo's compiler and read from the
compiled model, never re-implemented; it compiles copies of the files geomcheck read for it
(:mod:`geomcheck.load.mjcf_assets`: MuJoCo opens no file itself). The XML is parsed alongside (lxml) only to point
findings at the ``file:line`` of each body, geom and joint element.

Mapping (all frames are MuJoCo's body frames, so a link's frame is its body's):

- body -> :class:`Link` (the world body is the link ``world``; an unnamed body is ``body<id>``);
  its mass and inertia -> :class:`Inertial` (principal moments in MuJoCo's inertial frame),
  ``from_geometry`` when MuJoCo inferred them from the geoms (``inertiafromgeom``).
- geom -> a collision element when it takes part in contacts (``contype`` or ``conaffinity``
  non-zero), a visual element otherwise (Menagerie's convention: visual geoms have both zero).
  Sphere, box, cylinder, mesh map exactly. A capsule is a :class:`Capsule`, measured as the
  cylinder that encloses it (length ``2 * (half-length + radius)``) and collided as the capsule;
  an ellipsoid is the cylinder that encloses it when two radii are equal (a disc or rod, the
  common case) and otherwise its bounding box, marked ``ellipsoid``: the fit and the collision
  engines measure the ellipsoid itself.
  Planes, height fields and SDF geoms are not robot parts geomcheck can measure, and a mesh
  without a file (vertices in the XML, a builtin mesh) has nothing to read: skipped.
- mesh geom -> the asset's file read by geomcheck's mesh loader with the asset's ``scale``.
  MuJoCo re-centres a mesh at its centroid and turns it to its principal axes, moving ``refpos``
  / ``refquat`` into the compiled ``mesh_pos`` / ``mesh_quat``, and the compiled geom frame is the
  frame of those re-centred vertices; the element's origin is therefore the geom frame composed
  with the inverse of that offset, which puts the file's vertices exactly where MuJoCo's compiled
  vertices are (``tests/load/test_mjcf.py`` compares them). Reading the file, not the compiled
  vertices, keeps mesh findings on the file the author wrote and shares the mesh cache.
- joint -> hinge: ``revolute`` when limited, else ``continuous``; slide: ``prismatic``, its
  range open when MuJoCo leaves it unlimited (``limited="false"``, or ``"auto"`` without a
  ``range``); limits counted from the joint's ``ref`` (the written body pose is MuJoCo's
  ``qpos0``, URDF's zero); free: ``floating``; ball: ``ball`` (a 3-DOF rotation: geomcheck's
  kinematics holds it at its reference, as it does a floating joint). A body without joints
  hangs from its parent by a ``fixed`` joint ``<body>_fixed``. A joint whose anchor (``pos``) is
  off the body origin, or a body with several joints, gets an intermediate link
  ``<body>::<joint>`` without geometry per joint so that each joint turns about its own anchor,
  MuJoCo's joint order kept. Those links and joints are the loader's (``synthetic``): the
  report counts MuJoCo's bodies but the world (``nbody - 1``) and its joints (``njnt``), and
  findings name the body or the joint of the file.
- ``<equality>`` ``connect`` and ``weld`` between two bodies (or their sites), active at the
  start -> :attr:`Robot.closures`: the links a closed linkage holds together besides the tree.
- the body pairs MuJoCo never collides (one welded body, a body and its parent, contact bits
  that never match, ``<exclude>``) -> disabled collision pairs
  (:attr:`LoadedDescription.declared_collision_filter`, read where an SRDF's would be).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from lxml import etree

from geomcheck.errors import InputError
from geomcheck.load.description import ExpandedDocument, LoadedDescription
from geomcheck.load.mjcf_assets import StagedModel, compile_staged, stage_model
from geomcheck.load.mjcf_filter import collision_filter
from geomcheck.load.mjcf_limits import check_magnitudes
from geomcheck.load.mjcf_xml import XmlBody, XmlModel, read_xml
from geomcheck.load.xmlsafe import parse_bytes
from geomcheck.model import (
    Box,
    Capsule,
    Cylinder,
    Geometry,
    Inertial,
    Joint,
    Limit,
    Link,
    Mesh,
    Pose,
    Robot,
    Shape,
    SourceLocation,
    Sphere,
)

if TYPE_CHECKING:
    from geomcheck.load.bundle import Bundle
    from geomcheck.thresholds import LoadLimits

WORLD = "world"
EQUAL_RADII_RTOL = 1e-6  # ellipsoid radii this close (relative) are equal: the ellipsoid is round about the third [1]
MAX_START_TAG_LINES = 64  # how far above libxml2's line the opening of a start tag is looked for [lines]
ANCHOR_EPS_M = 1e-12  # a joint anchor closer than this to the body origin is at the origin [m]
# geom types of mjtGeom
_PLANE, _HFIELD, _SPHERE, _CAPSULE, _ELLIPSOID, _CYLINDER, _BOX, _MESH = range(8)
# joint types of mjtJoint
_FREE, _BALL, _SLIDE, _HINGE = range(4)


# ---------------------------------------------------------------------------------------------
# Compiling and mapping


def compile_model(bundle: Bundle, staged: StagedModel, display: str) -> Any:
    """MuJoCo's compiled model of the staged files (MuJoCo reads nothing else:
    :mod:`geomcheck.load.mjcf_assets`); :class:`InputError` with MuJoCo's message when its
    compiler refuses the model (MuJoCo itself would not load it)."""
    try:
        import mujoco
    except ImportError as err:  # pragma: no cover - a dependency
        raise InputError(f"{display}: reading MJCF needs the mujoco package ({err})") from None
    warnings: list[str] = []
    previous = mujoco.get_mju_user_warning()
    # MuJoCo's default warning handler appends to MUJOCO_LOG.TXT in the working folder: a
    # check never writes there. The warnings (a singular mass matrix at qpos0) are kept from it.
    mujoco.set_mju_user_warning(warnings.append)
    try:
        return compile_staged(staged)
    except ValueError as err:
        message = bundle.scrub(staged.named(" ".join(str(err).split())))
        raise InputError(f"{display}: MuJoCo's compiler rejects the model: {message}") from None
    finally:
        mujoco.set_mju_user_warning(previous)


def rotation_of(quat: np.ndarray) -> np.ndarray:
    """Rotation matrix (3, 3) of a MuJoCo quaternion ``(w, x, y, z)``."""
    w, x, y, z = np.asarray(quat, dtype=float) / np.linalg.norm(quat)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def pose_of(translation: np.ndarray, rotation: np.ndarray) -> Pose:
    return Pose.composed(translation, rotation)


def vec3(values: np.ndarray) -> tuple[float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]))


def geometry_of(model: Any, g: int) -> tuple[Geometry, np.ndarray, np.ndarray] | None:
    """Geometry of geom ``g`` with its pose in the body frame (translation, rotation), or
    ``None`` for geoms that are not robot parts (plane, height field, SDF)."""
    kind, size = int(model.geom_type[g]), model.geom_size[g]
    pos, rot = np.asarray(model.geom_pos[g], dtype=float), rotation_of(model.geom_quat[g])
    geometry: Geometry
    if kind == _SPHERE:
        geometry = Sphere(float(size[0]))
    elif kind == _BOX:
        geometry = Box(vec3(2.0 * size))
    elif kind == _CYLINDER:
        geometry = Cylinder(float(size[0]), float(2.0 * size[1]))
    elif kind == _CAPSULE:  # named a capsule, measured as the cylinder that encloses it
        geometry = Capsule(float(size[0]), float(2.0 * (size[1] + size[0])))
    elif kind == _ELLIPSOID:  # the cylinder or box enclosing it, marked: measured and collided as itself
        if math.isclose(size[0], size[1], rel_tol=EQUAL_RADII_RTOL):
            geometry = Cylinder(float(size[0]), float(2.0 * size[2]), ellipsoid=True)
        else:
            geometry = Box(vec3(2.0 * size), ellipsoid=True)
    elif kind == _MESH:
        m = int(model.geom_dataid[g])
        if int(model.mesh_pathadr[m]) < 0:
            return None  # vertices written in the XML or a builtin mesh: no file to read
        path = model.paths[int(model.mesh_pathadr[m]) :].split(b"\0", 1)[0].decode("utf-8", "replace")
        # compiled vertices v_c = R_m^T (s v - p_m): the file's frame in the body is geom * offset^-1
        offset = rotation_of(model.mesh_quat[m])
        rot = rot @ offset.T
        pos = pos - rot @ np.asarray(model.mesh_pos[m], dtype=float)
        geometry = Mesh(path, vec3(model.mesh_scale[m]))
    else:
        return None
    return geometry, pos, rot


class Mapper:
    """Builds the :class:`Robot` of a compiled model, locating elements in the XML."""

    def __init__(self, bundle: Bundle, model: Any, xml: XmlModel, files: Mapping[str, Path] | None = None) -> None:
        import mujoco

        self.bundle = bundle
        self.files = dict(files or {})  # MuJoCo's name of a file (a VFS name) -> the file
        self.model = model
        self.xml = xml
        self.mujoco = mujoco
        self.root_display = bundle.display(bundle.root_file)
        self.lines: dict[str, list[str]] = {}
        ordered = len(xml.bodies) == model.nbody  # MuJoCo's ids follow the document: match by order
        self.body_xml: list[XmlBody | None] = list(xml.bodies) if ordered else self._by_name(xml.bodies)
        # the names of the file's bodies and joints: a name the loader makes never takes one
        self.taken = {self.body_name(b) for b in range(model.nbody)}
        self.taken |= {n for j in range(model.njnt) if (n := self.name(mujoco.mjtObj.mjOBJ_JOINT, j))}
        inferred = xml.compiler.get("inertiafromgeom", "auto").lower()
        self.all_inferred = inferred == "true"
        self.none_inferred = inferred == "false"

    def _by_name(self, bodies: list[XmlBody]) -> list[XmlBody | None]:
        named = {b.element.get("name"): b for b in bodies if b.element is not None and b.element.get("name")}
        out: list[XmlBody | None] = [bodies[0]]
        out += [named.get(self.name(self.mujoco.mjtObj.mjOBJ_BODY, b) or "") for b in range(1, self.model.nbody)]
        return out

    def loader_name(self, wanted: str) -> str:
        """``wanted``, or ``wanted2``, ``wanted3``... when the file or the loader already uses it:
        a frame or joint the loader makes is never confused with one of the file's."""
        out, k = wanted, 1
        while out in self.taken:
            k += 1
            out = f"{wanted}{k}"
        self.taken.add(out)
        return out

    def name(self, kind: Any, index: int) -> str | None:
        return self.mujoco.mj_id2name(self.model, kind, index) or None

    def body_name(self, b: int) -> str:
        return WORLD if b == 0 else self.name(self.mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"

    def location(self, element: etree._Element | None, file: str) -> SourceLocation:
        if element is None:
            return SourceLocation(file)
        line = self.start_line(element, file)
        return SourceLocation(file, line, None, line if file == self.root_display else None)

    def start_line(self, element: etree._Element, file: str) -> int | None:
        """The line of ``<tag`` that opens ``element``: libxml2 gives the line where the start
        tag ends, and MJCF writers spread a geom's attributes over several lines."""
        line = element.sourceline
        lines = self.lines.setdefault(file, self.xml.sources.get(file, "").splitlines())
        if line is None or line > len(lines):
            return line
        opening = f"<{element.tag}"
        for candidate in range(line, max(0, line - MAX_START_TAG_LINES), -1):
            if opening in lines[candidate - 1]:
                return candidate
        return line

    def matched(self, elements: list[tuple[etree._Element, str]], count: int, names: list[str | None]) -> list[Any]:
        """The element of each of ``count`` compiled objects: by order when the counts agree,
        else by name; ``None`` where neither finds one."""
        if len(elements) == count:
            return list(elements)
        named = {e.get("name"): (e, f) for e, f in elements if e.get("name")}
        return [named.get(n) if n else None for n in names]

    def body_location(self, b: int) -> SourceLocation:
        entry = self.body_xml[b]
        if entry is None:
            return SourceLocation(self.root_display)
        return self.location(entry.element, entry.file)

    def shapes(self, b: int) -> tuple[tuple[Shape, ...], tuple[Shape, ...]]:
        model = self.model
        first, count = int(model.body_geomadr[b]), int(model.body_geomnum[b])
        geoms = range(first, first + count) if first >= 0 else range(0)
        entry = self.body_xml[b]
        names = [self.name(self.mujoco.mjtObj.mjOBJ_GEOM, g) for g in geoms]
        elements = self.matched(entry.geoms if entry else [], len(geoms), names)
        visuals: list[Shape] = []
        collisions: list[Shape] = []
        for g, found, name in zip(geoms, elements, names, strict=True):
            mapped = geometry_of(model, g)
            if mapped is None:
                continue
            geometry, pos, rot = mapped
            if isinstance(geometry, Mesh):
                geometry = Mesh(self.relative(geometry.filename), geometry.scale)
            collides = bool(model.geom_contype[g]) or bool(model.geom_conaffinity[g])
            into = collisions if collides else visuals
            where = self.location(*found) if found else self.body_location(b)
            kind: Any = "collision" if collides else "visual"
            into.append(Shape(kind, len(into), geometry, pose_of(pos, rot), name, where))
        return tuple(visuals), tuple(collisions)

    def relative(self, path: str) -> str:
        """A mesh path MuJoCo resolved, relative to the root file's folder when inside it (as a
        URDF's relative mesh filename is), absolute otherwise."""
        absolute = self.files.get(path, Path(path))
        try:
            return absolute.resolve().relative_to(self.bundle.root_file.parent.resolve()).as_posix()
        except ValueError:
            return absolute.as_posix()

    def inertial(self, b: int) -> Inertial | None:
        model = self.model
        mass = float(model.body_mass[b])
        if b == 0 or mass == 0.0:
            return None
        entry = self.body_xml[b]
        declared = None
        if entry is not None and entry.element is not None:
            declared = next((c for c in entry.element if c.tag == "inertial"), None)
        inferred = self.all_inferred or (declared is None and not self.none_inferred)
        moments = model.body_inertia[b]
        origin = pose_of(model.body_ipos[b], rotation_of(model.body_iquat[b]))
        where = self.location(declared, entry.file) if declared is not None and entry else self.body_location(b)
        return Inertial(
            mass,
            origin,
            ixx=float(moments[0]),
            iyy=float(moments[1]),
            izz=float(moments[2]),
            location=where,
            from_geometry=inferred,
        )

    def joints_of(self, b: int, parent: str, child: str) -> tuple[list[Joint], list[Link]]:
        """The joints that hang body ``b`` from ``parent`` and the intermediate links they need."""
        model, mj = self.model, self.mujoco
        body_pose = np.eye(4)
        body_pose[:3, :3] = rotation_of(model.body_quat[b])
        body_pose[:3, 3] = model.body_pos[b]
        first, count = int(model.body_jntadr[b]), int(model.body_jntnum[b])
        ids = range(first, first + count) if first >= 0 else range(0)
        entry = self.body_xml[b]
        names = [self.name(mj.mjtObj.mjOBJ_JOINT, j) for j in ids]
        elements = self.matched(entry.joints if entry else [], len(ids), names)
        if not ids:
            origin = pose_of(body_pose[:3, 3], body_pose[:3, :3])
            weld = self.loader_name(f"{child}_fixed")
            return [Joint(weld, "fixed", parent, child, origin, location=self.body_location(b), synthetic=True)], []
        joints: list[Joint] = []
        links: list[Link] = []
        previous, offset = parent, body_pose  # the body frame in the previous link's frame, joints at zero
        for k, (j, found, name) in enumerate(zip(ids, elements, names, strict=True)):
            anchor = np.asarray(model.jnt_pos[j], dtype=float)
            joint_name = name or self.loader_name(f"{child}_joint{k}")
            at_anchor = offset.copy()
            at_anchor[:3, 3] = offset[:3, :3] @ anchor + offset[:3, 3]
            last = k == len(ids) - 1
            centred = float(np.linalg.norm(anchor)) <= ANCHOR_EPS_M
            target = child if last and centred else self.loader_name(f"{child}::{joint_name}")
            where = self.location(*found) if found else self.body_location(b)
            joints.append(self.joint(j, joint_name, previous, target, at_anchor, where))
            if target != child:
                links.append(Link(target, location=where, synthetic=True))
            previous = target
            offset = np.eye(4)
            offset[:3, 3] = -anchor  # from the anchor back to the body origin
        if previous != child:
            anchor_name = self.loader_name(f"{child}_anchor")
            final = joints[-1]
            origin = pose_of(offset[:3, 3], np.eye(3))
            joints.append(
                Joint(
                    anchor_name,
                    "fixed",
                    previous,
                    child,
                    origin,
                    location=final.location,
                    synthetic=True,
                    author=final.name,
                )
            )
        return joints, links

    def joint(self, j: int, name: str, parent: str, child: str, frame: np.ndarray, where: SourceLocation) -> Joint:
        model = self.model
        kind = int(model.jnt_type[j])
        origin = pose_of(frame[:3, 3], frame[:3, :3])
        axis = vec3(model.jnt_axis[j])
        effort = None
        if bool(model.jnt_actfrclimited[j]):
            effort = float(np.max(np.abs(model.jnt_actfrcrange[j])))
        limited = bool(model.jnt_limited[j])
        # the body sits at its written pose when the joint is at its reference (``ref``, qpos0);
        # URDF's zero is the written pose, so positions are counted from the reference
        ref = float(model.qpos0[int(model.jnt_qposadr[j])]) if kind in (_HINGE, _SLIDE) else 0.0
        lower, upper = (
            (float(model.jnt_range[j][0]) - ref, float(model.jnt_range[j][1]) - ref) if limited else (None, None)
        )
        if kind == _HINGE:
            joint_type = "revolute" if limited else "continuous"
            limit = Limit(lower, upper, effort) if limited or effort is not None else None
        elif kind == _SLIDE:  # unlimited: MuJoCo lets it slide freely, no range of [0, 0]
            joint_type, limit = "prismatic", Limit(lower, upper, effort, unlimited=not limited)
        else:  # free, ball
            joint_type, limit, axis = ("ball" if kind == _BALL else "floating"), None, (1.0, 0.0, 0.0)
        return Joint(name, joint_type, parent, child, origin, axis, limit, location=where)

    def robot(self, name: str) -> Robot:
        model = self.model
        links: list[Link] = []
        joints: list[Joint] = []
        for b in range(model.nbody):
            link_name = self.body_name(b)
            visuals, collisions = self.shapes(b)
            links.append(Link(link_name, self.inertial(b), visuals, collisions, self.body_location(b), world=b == 0))
            if b == 0:
                continue
            hung, between = self.joints_of(b, self.body_name(int(model.body_parentid[b])), link_name)
            joints += hung
            links += between
        location = SourceLocation(self.root_display, 1, None, 1)
        return Robot(name, tuple(links), tuple(joints), location, closures=self.closures())

    def closures(self) -> tuple[tuple[str, str], ...]:
        """The body pairs an active ``connect`` or ``weld`` equality holds together (its objects
        bodies or sites, the world left out: a weld to the world fixes a body, it closes no loop)."""
        mj = self.mujoco
        model = self.model
        kinds = (int(mj.mjtEq.mjEQ_CONNECT), int(mj.mjtEq.mjEQ_WELD))
        out: list[tuple[str, str]] = []
        for e in range(int(model.neq)):
            if int(model.eq_type[e]) not in kinds or not bool(model.eq_active0[e]):
                continue
            site = int(model.eq_objtype[e]) == int(mj.mjtObj.mjOBJ_SITE)
            ends = [int(model.eq_obj1id[e]), int(model.eq_obj2id[e])]
            bodies = [int(model.site_bodyid[i]) if site else i for i in ends]
            if 0 not in bodies and bodies[0] != bodies[1]:
                pair = (self.body_name(bodies[0]), self.body_name(bodies[1]))
                if pair not in out:
                    out.append(pair)
        return tuple(out)


def load_mjcf(bundle: Bundle, limits: LoadLimits, data: bytes) -> LoadedDescription:
    """The MJCF description of ``bundle`` whose root file holds ``data``."""
    display = bundle.display(bundle.root_file)
    xml = read_xml(bundle, limits, data)
    staged = stage_model(bundle, limits, data)
    model = compile_model(bundle, staged, display)
    mapper = Mapper(bundle, model, xml, staged.paths)
    check_magnitudes(model, mapper, limits)
    root = parse_bytes(data, display, limits)
    robot = mapper.robot(root.get("model") or bundle.root_file.stem)
    text = xml.sources[display]
    document = ExpandedDocument(text=text, root=display, sources=dict(xml.sources), is_xacro=False)
    return LoadedDescription(
        bundle, robot, document, (), format="mjcf", declared_collision_filter=collision_filter(model, mapper)
    )
