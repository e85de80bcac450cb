"""GC1xx checks on the parsed model: names, the kinematic tree, joint types, axes, limits, mimics.

Parse-time GC1xx findings (malformed XML, xacro, unknown elements, numbers) come from the
loader; this family looks at the robot as a graph, as the description's format defines it
(URDF, SDFormat, MJCF: which joint types exist, which trees the format's own parser accepts).
Joints and links the loader adds (an MJCF body's weld, an anchor frame, an SDFormat universal
joint's second axis) are part of the graph but never named: a finding names the file's joint
they realise, or the link they hang.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import replace

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.model_section import MODEL_SECTION, model_section
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load.urdf_spec import closest, did_you_mean
from geomcheck.model import JOINT_TYPES, SDF_JOINT_TYPES, Joint, Robot
from geomcheck.rules.joints import MIMIC_OUTSIDE_LIMITS
from geomcheck.rules.structure import (
    CYCLE,
    DUPLICATE_JOINT,
    DUPLICATE_LINK,
    INVERTED_LIMITS,
    JOINT_MISSING_LINK,
    MIMIC_CYCLE,
    MIMIC_MISSING_JOINT,
    MISSING_LIMITS,
    MULTIPLE_PARENTS,
    MULTIPLE_ROOTS,
    NO_ROOT,
    NON_UNIT_AXIS,
    UNKNOWN_JOINT_TYPE,
    WORLD_LINK,
    ZERO_AXIS,
)
from geomcheck.thresholds import StructureThresholds

WORLD = "world"
AXIS_JOINT_TYPES = ("revolute", "continuous", "prismatic", "planar")
MAX_ROOTS_NAMED = 10  # root links a GC115 message and its data name [count]
LIMITED_JOINT_TYPES = ("revolute", "prismatic")
# the joint types each format defines (an MJCF joint is mapped onto URDF's types, a ball kept)
FORMAT_JOINT_TYPES = {"urdf": JOINT_TYPES, "sdf": SDF_JOINT_TYPES, "mjcf": (*JOINT_TYPES, "ball")}
# the format's own parser, named by a finding on a file it loads as written (``accepted_by``)
REFERENCE_PARSER = {"urdf": "urdfdom", "sdf": "libsdformat", "mjcf": "MuJoCo"}
SECOND_AXIS = "::axis2"  # the suffix of the joint an SDFormat universal or revolute2 joint's second axis is


def joint_subject(joint: Joint) -> tuple[str, str]:
    """The joint a finding names and the part of it (``""``, or ``axis2.`` for the second axis of
    an SDFormat two-axis joint): the file's joint, never one the loader made."""
    if joint.synthetic and joint.name.endswith(SECOND_AXIS):
        return joint.written_name, "axis2."
    return joint.written_name, ""


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


def joint_definitions(robot: Robot, thresholds: StructureThresholds, fmt: str = "urdf") -> Iterator[Diagnostic]:
    """GC118-GC122: joint type, axis, limits, each judged by the description's format."""
    types = FORMAT_JOINT_TYPES.get(fmt, JOINT_TYPES)
    accepted = {"accepted_by": REFERENCE_PARSER[fmt]} if fmt in ("urdf", "sdf") else {}
    for joint in robot.joints:
        name, part = joint_subject(joint)
        if joint.type and joint.type not in types and not joint.synthetic:
            written = joint.written_type
            yield UNKNOWN_JOINT_TYPE.diagnose(
                f"joint type {written!r} is not one of {', '.join(types)}{did_you_mean(written, types)}",
                joint=name,
                about="type",
                location=joint.location,
                data={"type": written, "suggestion": closest(written, types)},
            )
        if joint.type in AXIS_JOINT_TYPES:
            norm = math.sqrt(sum(c * c for c in joint.axis))
            axis = " ".join(f"{c:g}" for c in joint.axis)
            if norm < thresholds.min_axis_norm:
                zero_data: dict[str, object] = {"axis": list(joint.axis), "norm": norm}
                message = f'{joint.type} joint has a zero-length axis (xyz="{axis}")'
                if fmt == "urdf":  # libsdformat and MuJoCo refuse it before
                    message += "; urdfdom loads it as written, and KDL and pinocchio turn it into NaN"
                    zero_data.update(accepted)
                yield ZERO_AXIS.diagnose(
                    message, joint=name, about=f"{part}axis", location=joint.location, data=zero_data
                )
            elif abs(norm - 1.0) > thresholds.axis_norm_tolerance:
                yield NON_UNIT_AXIS.diagnose(
                    f'axis xyz="{axis}" has length {norm:.6g}, not 1',
                    joint=name,
                    about=f"{part}axis",
                    location=joint.location,
                    data={"axis": list(joint.axis), "norm": norm},
                )
        if joint.type in LIMITED_JOINT_TYPES:
            yield from _limits(joint, name, part, accepted)


def _limits(joint: Joint, name: str, part: str, accepted: dict[str, str]) -> Iterator[Diagnostic]:
    limit = joint.limit
    about = f"{part}limit"
    if limit is None:
        yield MISSING_LIMITS.diagnose(
            f"{joint.type} joint has no <limit>",
            joint=name,
            about=about,
            location=joint.location,
        )
        return
    if limit.lower is None and limit.upper is None and not limit.unlimited:
        yield MISSING_LIMITS.diagnose(
            f"{joint.type} joint's <limit> has no lower or upper: "
            "the range defaults to [0, 0] and the joint cannot move",
            joint=name,
            about=about,
            location=joint.location,
            severity=Severity.WARNING,
        )
        return
    # an absent bound is 0 in urdfdom; one written as SDFormat's "no limit" is open on its side
    lower = (-math.inf if limit.unlimited else 0.0) if limit.lower is None else limit.lower
    upper = (math.inf if limit.unlimited else 0.0) if limit.upper is None else limit.upper
    if lower > upper:
        unit = "m" if joint.type == "prismatic" else "rad"
        message = f"lower limit {lower:g} {unit} is above upper limit {upper:g} {unit}"
        if accepted:
            message += f"; {accepted['accepted_by']} loads it as written, and planners find no valid position"
        yield INVERTED_LIMITS.diagnose(
            message,
            joint=name,
            about=about,
            location=joint.location,
            data={"lower": lower, "upper": upper, **accepted},
        )


def mimics(robot: Robot) -> Iterator[Diagnostic]:
    """GC123/GC125: mimics of missing joints and loops of mimics."""
    joints = robot.joint_map
    for joint in robot.joints:
        if joint.mimic is None:
            continue
        target = joint.mimic.joint
        if target not in joints:
            yield MIMIC_MISSING_JOINT.diagnose(
                f"<mimic joint={target!r}> names no joint{did_you_mean(target, joints)}",
                joint=joint_subject(joint)[0],
                about="mimic",
                location=joint.location,
                data={"mimic": target, "suggestion": closest(target, joints)},
            )
    reported: set[frozenset[str]] = set()
    for joint in robot.joints:
        chain: list[str] = []
        name: str | None = joint.name
        while name is not None and name in joints and name not in chain:
            chain.append(name)
            mimic = joints[name].mimic
            name = mimic.joint if mimic is not None else None
        if name is None or name not in chain:
            continue
        loop = chain[chain.index(name) :]
        if frozenset(loop) in reported:
            continue
        reported.add(frozenset(loop))
        first = min(loop, key=[j.name for j in robot.joints].index)
        yield MIMIC_CYCLE.diagnose(
            "mimic joints follow each other in a loop: " + " -> ".join([*loop, loop[0]]),
            joint=first,
            about="mimic",
            location=joints[first].location,
            data={"joints": loop},
        )


def _bounds(joint: Joint) -> tuple[float, float] | None:
    """A revolute or prismatic joint's finite ``(lower, upper)``, else ``None``."""
    limit = joint.limit
    if joint.type not in ("revolute", "prismatic") or limit is None:
        return None
    if limit.lower is None or limit.upper is None or not (math.isfinite(limit.lower) and math.isfinite(limit.upper)):
        return None
    return (limit.lower, limit.upper) if limit.lower <= limit.upper else None


def mimic_ranges(robot: Robot, thresholds: StructureThresholds) -> Iterator[Diagnostic]:
    """GC130: mimic joints whose limits cut off the positions their leader's range gives them."""
    joints = robot.joint_map
    for joint in robot.joints:
        mimic = joint.mimic
        leader = joints.get(mimic.joint) if mimic is not None else None
        if mimic is None or leader is None or leader is joint:
            continue
        own, led = _bounds(joint), _bounds(leader)
        if own is None or led is None or led[1] <= led[0] or mimic.multiplier == 0.0:
            continue
        ends = sorted(mimic.multiplier * q + mimic.offset for q in led)
        span = ends[1] - ends[0]
        cut = max(0.0, own[0] - ends[0]) + max(0.0, ends[1] - own[1])
        share = min(1.0, cut / span)
        if share <= thresholds.mimic_range_tolerance:
            continue
        unit = "m" if joint.type == "prismatic" else "rad"
        offset_text = f" and offset {mimic.offset:g} {unit}" if mimic.offset else ""
        yield MIMIC_OUTSIDE_LIMITS.diagnose(
            MIMIC_OUTSIDE_LIMITS.message(
                leader=leader.name,
                leader_lower=led[0],
                leader_upper=led[1],
                unit=unit,
                multiplier=mimic.multiplier,
                offset_text=offset_text,
                needed_lower=ends[0],
                needed_upper=ends[1],
                lower=own[0],
                upper=own[1],
                share=share,
            ),
            joint=joint.name,
            about="limit",
            location=joint.location,
            severity=Severity.ERROR if share >= thresholds.mimic_gross_share else Severity.WARNING,
            data={
                "leader": leader.name,
                "multiplier": mimic.multiplier,
                "offset": mimic.offset,
                "needed": [round(v, 9) + 0.0 for v in ends],
                "limits": list(own),
                "outside_share": round(share, 4),
            },
        )


def check_robot(robot: Robot, thresholds: StructureThresholds | None = None, fmt: str = "urdf") -> list[Diagnostic]:
    """Every graph-level GC1xx finding of ``robot``, a description in format ``fmt`` (``urdf``,
    ``sdf``, ``mjcf``), in a stable order."""
    thresholds = thresholds or StructureThresholds()
    out: list[Diagnostic] = []
    out.extend(duplicate_names(robot))
    out.extend(joint_links(robot))
    out.extend(tree_shape(robot, fmt))
    out.extend(cycles(robot, fmt))
    out.extend(joint_definitions(robot, thresholds, fmt))
    out.extend(mimics(robot))
    out.extend(mimic_ranges(robot, thresholds))
    return group_by_source_line(out)


MAX_ALSO_NAMED = 5  # other subjects a grouped finding names in its message [count]


def group_by_source_line(found: list[Diagnostic]) -> list[Diagnostic]:
    """``found`` with the findings one source line wrote for several subjects (a xacro macro
    expanded for the left and the right side) merged into the one with the first subject name,
    which names the others:
    the author fixes one line."""
    first: dict[tuple[str, str, int, str, str], int] = {}
    others: dict[int, list[Diagnostic]] = {}
    kept: list[Diagnostic] = []
    for d in found:
        loc = d.location
        # only an expanded document writes several elements from one source line (a plain
        # file minified onto one line holds distinct elements: they stay distinct findings)
        expanded = loc is not None and loc.expanded_line is not None and loc.expanded_line != loc.line
        if loc is None or loc.line is None or not expanded or not (d.joint or d.link):
            kept.append(d)
            continue
        key = (d.code, loc.file, loc.line, d.about, d.message)
        if key in first:
            others.setdefault(first[key], []).append(d)
            continue
        first[key] = len(kept)
        kept.append(d)
    for index, group in others.items():
        # the member named first stands for the group, whatever the order of the file
        d = min([kept[index], *group], key=lambda m: m.joint or m.link or "")
        names = sorted({m.joint or m.link or "" for m in [kept[index], *group] if m is not d})
        listed = ", ".join(names[:MAX_ALSO_NAMED])
        if len(names) > MAX_ALSO_NAMED:
            listed += f" and {len(names) - MAX_ALSO_NAMED} more"
        kept[index] = replace(d, message=f"{d.message} (also in {listed})", data={**d.data, "also": names})
    return kept


def run(ctx: CheckContext) -> FamilyResult:
    fmt = ctx.loaded.format
    return FamilyResult(
        diagnostics=check_robot(ctx.robot, ctx.thresholds.structure, fmt),
        sections={MODEL_SECTION: model_section(ctx.robot)},
    )
