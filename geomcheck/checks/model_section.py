"""The ``model`` report section: the robot as its file describes it, written by the structure family.

Links and joints are those the format's own tool counts (urdfdom's links and joints, MuJoCo's
bodies but the world and its joints, SDFormat's links and joints): the frames and joints the
loader adds to model a format's semantics (an MJCF body's weld or several joints, an SDFormat
joint frame off its child's origin, a universal joint's second axis) are folded back into the
joint of the file they realise. Joints read as URDF's, whatever the format: ``parent`` and
``child`` are links of the file, ``origin`` the child link's frame in the parent link's frame
with every joint at zero, ``axis`` the direction of motion in the child link's frame (unit
where the format normalises it: SDFormat, MJCF), ``limit`` the bounds in [rad] or [m]
(``null`` on an open side) as the consumers read them. Typed as
:class:`geomcheck.report.section_model.ModelSection`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from geomcheck.model import COMPOSED_DECIMALS, Box, Capsule, Cylinder, Joint, Link, Mesh, Pose, Robot, Shape, Sphere

if TYPE_CHECKING:
    from collections.abc import Iterator

MODEL_SECTION = "model"
SECOND_AXIS = "::axis2"  # the loader's joint for the second axis of an SDFormat two-axis joint


def pose_entry(pose: Pose) -> dict[str, list[float]]:
    return {"xyz": list(pose.xyz), "rpy": list(pose.rpy)}


def geometry_entry(shape: Shape) -> tuple[str, dict[str, Any]]:
    """The shape's type as the file writes it and its dimensions as the file writes them [m]."""
    g = shape.geometry
    kind = type(g).__name__.lower()
    if isinstance(g, Box):
        return kind, {"size": list(g.size)}
    if isinstance(g, Capsule):
        return kind, {"radius": g.radius, "length": g.straight_length}
    if isinstance(g, Cylinder):
        return kind, {"radius": g.radius, "length": g.length}
    if isinstance(g, Sphere):
        return kind, {"radius": g.radius}
    assert isinstance(g, Mesh)
    return kind, {"filename": g.filename, "scale": list(g.scale)}


def shape_entry(shape: Shape) -> dict[str, Any]:
    kind, geometry = geometry_entry(shape)
    return {
        "index": shape.index,
        "name": shape.name,
        "type": kind,
        "origin": pose_entry(shape.origin),
        "geometry": geometry,
    }


def link_entry(link: Link) -> dict[str, Any]:
    inertial = None
    if link.inertial is not None:
        i = link.inertial
        inertial = {
            "mass": i.mass,
            "origin": pose_entry(i.origin),
            "inertia": {"ixx": i.ixx, "ixy": i.ixy, "ixz": i.ixz, "iyy": i.iyy, "iyz": i.iyz, "izz": i.izz},
        }
    return {
        "name": link.name,
        "inertial": inertial,
        "visuals": [shape_entry(s) for s in link.visuals],
        "collisions": [shape_entry(s) for s in link.collisions],
    }


def _up(robot: Robot, joint: Joint) -> Iterator[Joint]:
    """The loader's joints above ``joint`` up to a link of the file, nearest first."""
    link = robot.link_map.get(joint.parent)
    while link is not None and link.synthetic and not link.world and link.name in robot.parent_joint:
        above = robot.parent_joint[link.name]
        yield above
        link = robot.link_map.get(above.parent)


def _down(robot: Robot, joint: Joint) -> list[Joint]:
    """The loader's joints below ``joint`` down to the link of the file it moves, nearest first."""
    out: list[Joint] = []
    child = joint.child
    seen = {child}
    while (link := robot.link_map.get(child)) is not None and link.synthetic and not link.world:
        below = robot.child_joints.get(child, ())
        if len(below) != 1 or below[0].child in seen:
            break
        out.append(below[0])
        child = below[0].child
        seen.add(child)
    return out


def _clean(vector: Any) -> tuple[float, float, float]:
    """A composed direction without the last bits' noise, as :meth:`Pose.composed` cleans a pose
    (the same description reads the same on every CPU)."""
    a, b, c = (round(float(v), COMPOSED_DECIMALS) + 0.0 for v in vector)
    return a, b, c


def joint_entry(robot: Robot, joint: Joint) -> dict[str, Any]:
    above, below = list(_up(robot, joint)), _down(robot, joint)
    parent = above[-1].parent if above else joint.parent
    child = below[-1].child if below else joint.child
    origin, axis = joint.origin, joint.axis
    if above or below:  # the file's child link in its parent link, the loader's joints at zero
        import numpy as np

        matrix = np.eye(4)
        for step in reversed(above):
            matrix = matrix @ step.origin.matrix()
        matrix = matrix @ joint.origin.matrix()
        turn = np.eye(3)  # from the joint's own child frame to the file's child link
        for step in below:
            matrix = matrix @ step.origin.matrix()
            turn = turn @ step.origin.rotation()
        origin = Pose.composed(matrix[:3, 3], matrix[:3, :3])
        axis = _clean(turn.T @ np.asarray(joint.axis, dtype=float))
    limit = joint.limit
    entry: dict[str, Any] = {
        "name": joint.name,
        "type": joint.written_type,
        "parent": parent,
        "child": child,
        "origin": pose_entry(origin),
        "axis": list(axis) if joint.type in ("revolute", "continuous", "prismatic", "planar") else None,
        "limit": None
        if limit is None
        else {"lower": limit.lower, "upper": limit.upper, "effort": limit.effort, "velocity": limit.velocity},
        "mimic": None
        if joint.mimic is None
        else {"joint": joint.mimic.joint, "multiplier": joint.mimic.multiplier, "offset": joint.mimic.offset},
    }
    seconds = [k for k, j in enumerate(below) if j.name.endswith(SECOND_AXIS) and j.author == joint.name]
    if seconds:  # the second axis of an SDFormat universal or revolute2 joint, in the child link
        import numpy as np

        turn = np.eye(3)
        for step in below[seconds[0] + 1 :]:
            turn = turn @ step.origin.rotation()
        entry["axis2"] = list(_clean(turn.T @ np.asarray(below[seconds[0]].axis, dtype=float)))
    return entry


def model_section(robot: Robot) -> dict[str, Any]:
    """The ``model`` section of ``robot`` (see the module docstring)."""
    return {
        "links": [link_entry(link) for link in robot.authored_links],
        "joints": [joint_entry(robot, joint) for joint in robot.authored_joints],
    }
