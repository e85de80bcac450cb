"""GC110-GC117: unique names, joints between declared links, one root, no loop."""

from __future__ import annotations

from collections.abc import Iterator

from geomcheck.checks.structure.formats import REFERENCE_PARSER
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load.urdf_spec import closest, did_you_mean
from geomcheck.model import Joint, Robot
from geomcheck.rules.structure import (
    CYCLE,
    DUPLICATE_JOINT,
    DUPLICATE_LINK,
    JOINT_MISSING_LINK,
    MULTIPLE_PARENTS,
    MULTIPLE_ROOTS,
    NO_ROOT,
    WORLD_LINK,
)

WORLD = "world"
MAX_ROOTS_NAMED = 10  # root links a GC115 message and its data name [count]


def duplicate_names(robot: Robot) -> Iterator[Diagnostic]:
    """GC110/GC111: a link or joint whose name an earlier one already used."""
    for rule, items, kind in ((DUPLICATE_LINK, robot.links, "link"), (DUPLICATE_JOINT, robot.joints, "joint")):
        first: dict[str, object] = {}
        count: dict[str, int] = {}
        for item in items:
            if not item.name or getattr(item, "synthetic", False):
                continue
            count[item.name] = count.get(item.name, 0) + 1
            if item.name not in first:
                first[item.name] = item.location
                continue
            where = first[item.name]
            yield rule.diagnose(
                f"{kind} name {item.name!r} is already used by the {kind} at {where}",
                link=item.name if kind == "link" else None,
                joint=item.name if kind == "joint" else None,
                about=f"occurrence {count[item.name]}",
                location=item.location,
                data={"first": str(where)},
            )


def joint_links(robot: Robot) -> Iterator[Diagnostic]:
    """GC112/GC113: parents and children that are absent or undeclared."""
    declared = set(robot.link_map)
    for joint in robot.joints:
        if not joint.parent and not joint.child:  # one omission, not two
            yield JOINT_MISSING_LINK.diagnose(
                "joint has no <parent link=...> and no <child link=...>",
                joint=joint.name,
                about="parent+child",
                location=joint.location,
                data={"role": "parent+child", "link": None},
            )
            continue
        for role in ("parent", "child"):
            name = getattr(joint, role)
            if not name:
                yield JOINT_MISSING_LINK.diagnose(
                    f"joint has no <{role} link=...>",
                    joint=joint.name,
                    about=role,
                    location=joint.location,
                    data={"role": role, "link": None},
                )
            elif name not in declared:
                if role == "parent" and name == WORLD:
                    yield WORLD_LINK.diagnose(
                        "parent link 'world' is not declared: urdfdom (robot_state_publisher, MoveIt, Gazebo's "
                        "URDF import) refuses the robot; the boxturtle parser (ROS until 2010) added the link, and "
                        "geomcheck takes it, as the fixed world frame",
                        joint=joint.name,
                        about=role,
                        location=joint.location,
                        data={"role": role, "link": name},
                    )
                    continue
                yield JOINT_MISSING_LINK.diagnose(
                    f"{role} link {name!r} is not declared{did_you_mean(name, declared)}",
                    joint=joint.name,
                    about=role,
                    location=joint.location,
                    data={"role": role, "link": name, "suggestion": closest(name, declared)},
                )


def tree_shape(robot: Robot, fmt: str = "urdf") -> Iterator[Diagnostic]:
    """GC114/GC115/GC117: no root, several roots, links with several parent joints. A joint
    written the wrong way round (its child is the main tree's link, its parent the root of a
    tree of its own: a sensor model attached by ``parent=sensor child=rack``) is one GC117 that
    says so, not also a GC115 calling that tree unconnected."""
    if not robot.links:
        yield NO_ROOT.diagnose("the robot declares no links", location=robot.location)
        return
    parents: dict[str, list[Joint]] = {}
    for joint in robot.joints:
        if joint.child and joint.child in robot.link_map:
            parents.setdefault(joint.child, []).append(joint)
    roots = list(dict.fromkeys(robot.roots))
    undeclared_parents = {j.parent for j in robot.joints if j.parent and j.parent not in robot.link_map}
    if WORLD in undeclared_parents:  # the implicit world frame is the root of what hangs from it
        roots.insert(0, WORLD)
    sizes = {root: _subtree_size(robot, root) for root in roots}
    position = {root: index for index, root in enumerate(roots)}
    main = max(roots, key=lambda r: (sizes[r], -position[r])) if roots else None
    tree_of = _tree_roots(robot, sorted(roots, key=lambda r: r != main))
    joined: set[str] = set()  # roots whose tree a reversed joint joins to another tree
    for link, joints in parents.items():
        if len(joints) > 1:
            yield _multiple_parents(link, joints, tree_of, fmt, joined)
    if not roots and not undeclared_parents:  # joints from undeclared links are GC112 already
        yield _no_root(robot, fmt)
        return
    if len(roots) > 1:
        yield from _multiple_roots(robot, roots, main, sizes, joined, fmt)


def _multiple_parents(
    link: str, joints: list[Joint], tree_of: dict[str, str], fmt: str, joined: set[str]
) -> Diagnostic:
    """GC117 for ``link``, the child of several ``joints``; the roots whose tree a joint written the
    wrong way round joins go in ``joined``."""
    names = [j.written_name for j in joints]
    home = tree_of.get(link)
    reversed_joints = [j for j in joints if tree_of.get(j.parent) not in (None, home)]
    message = f"link is the child of {len(joints)} joints: {', '.join(names)}"
    for j in reversed_joints:
        other = tree_of[j.parent]
        joined.add(other)
        message += f"; joint {j.written_name} joins the tree of {other!r}, which no joint attaches"
        if j.parent == other:
            message += f": swapped (parent {link!r}, child {other!r}) it makes one tree"
    data: dict[str, object] = {"joints": names, "reversed": [j.written_name for j in reversed_joints]}
    if fmt == "urdf":
        message += "; urdfdom loads it, but KDL (robot_state_publisher) refuses the robot"
        data["accepted_by"] = REFERENCE_PARSER[fmt]
    elif fmt == "sdf":
        message += "; libsdformat loads it, but gz-physics (dartsim) refuses the second joint: its part falls free"
        data["accepted_by"] = REFERENCE_PARSER[fmt]
    return MULTIPLE_PARENTS.diagnose(message, link=link, location=joints[1].location, data=data)


def _no_root(robot: Robot, fmt: str) -> Diagnostic:
    """GC114 for links that are all the child of a joint."""
    message = f"every one of the {len(robot.link_map)} links is the child of a joint: there is no root link"
    accepted: dict[str, object] = {}
    if fmt == "sdf":  # a kinematic loop: valid SDFormat, which Gazebo's physics cannot build as a tree
        message += "; libsdformat loads the loop, but gz-physics (dartsim) refuses the joint that closes it"
        accepted["accepted_by"] = REFERENCE_PARSER[fmt]
    return NO_ROOT.diagnose(message, location=robot.location, data=accepted)


def _multiple_roots(
    robot: Robot, roots: list[str], main: str | None, sizes: dict[str, int], joined: set[str], fmt: str
) -> Iterator[Diagnostic]:
    """GC115 for every root but the main tree's, the world frame's and those a reversed joint joins."""
    # each finding names a few roots, not all: 3,000 unjoined links must not make a report
    # that grows with the square of the link count
    named = roots[:MAX_ROOTS_NAMED]
    listed = ", ".join(named) + (f" and {len(roots) - len(named)} more" if len(roots) > len(named) else "")
    for root in roots:
        if root in (main, WORLD) or root in joined:
            continue
        message = f"link is not connected to the tree rooted at {main!r} ({len(roots)} root links: {listed})"
        data = {"roots": named, "root_count": len(roots), "main_root": main, "subtree_links": sizes[root]}
        severity = None
        if fmt == "sdf":  # SDFormat's free bodies: valid, simulated apart from the robot
            message += ": libsdformat loads it as a free body, which Gazebo simulates apart from the robot"
            data["accepted_by"] = REFERENCE_PARSER[fmt]
            severity = Severity.INFO
        yield MULTIPLE_ROOTS.diagnose(
            message, link=root, location=robot.link_map[root].location, data=data, severity=severity
        )


def _tree_roots(robot: Robot, roots: list[str]) -> dict[str, str]:
    """The root whose tree each link lies in, the trees walked in ``roots``' order (a link two
    trees reach, through a second parent joint, is the first tree's)."""
    out: dict[str, str] = {}
    for root in roots:
        if root in out:
            continue
        out[root] = root
        stack = [root]
        while stack:
            for joint in robot.child_joints.get(stack.pop(), ()):
                if joint.child and joint.child not in out:
                    out[joint.child] = root
                    stack.append(joint.child)
    return out


def _subtree_size(robot: Robot, root: str) -> int:
    seen = {root}
    stack = [root]
    while stack:
        for joint in robot.child_joints.get(stack.pop(), ()):
            if joint.child and joint.child not in seen:
                seen.add(joint.child)
                stack.append(joint.child)
    return len(seen)


def cycles(robot: Robot, fmt: str = "urdf") -> Iterator[Diagnostic]:
    """GC116: closed loops of joints, each reported once at its first joint in document order."""
    order: dict[str, int] = {}
    for index, joint in enumerate(robot.joints):
        order.setdefault(joint.name, index)
    parent_joint = robot.parent_joint
    reported: set[frozenset[str]] = set()
    # links whose walk to the root has been made: a later walk stops there, so every link is
    # walked once and a 10,000-link chain costs 10,000 steps, not 50 million
    walked: set[str] = set()
    for start in robot.link_map:
        path: list[str] = []
        on_path: set[str] = set()
        link = start
        while link in parent_joint and link not in on_path and link not in walked:
            path.append(link)
            on_path.add(link)
            link = parent_joint[link].parent
        walked.update(path)
        if link not in on_path:
            continue
        loop = path[path.index(link) :]
        key = frozenset(loop)
        if key in reported:
            continue
        reported.add(key)
        joints = sorted((parent_joint[name] for name in loop), key=lambda j: order.get(j.name, 0))
        written = list(dict.fromkeys(j.written_name for j in joints))
        links = [name for name in loop if robot.link_map[name].authored] or loop
        chain = " -> ".join([*reversed(links), links[-1]])
        message = f"joints {', '.join(written)} form a closed loop: {chain}"
        data: dict[str, object] = {"links": sorted(links), "joints": written}
        if fmt == "sdf":
            message += "; libsdformat loads it, but gz-physics (dartsim) refuses the joint that closes it"
            data["accepted_by"] = REFERENCE_PARSER[fmt]
        yield CYCLE.diagnose(message, joint=written[0], location=joints[0].location, data=data)
