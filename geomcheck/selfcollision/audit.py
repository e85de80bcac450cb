"""The SRDF audit (GC410-GC416): an existing SRDF's collision entries against the matrix."""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterable, Mapping

from geomcheck.collision.topology import fixed_joints_between
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load.srdf import Srdf
from geomcheck.model import Robot, SourceLocation
from geomcheck.rules.srdf import (
    DISABLED_PAIR_CAN_COLLIDE,
    ENABLED_ADJACENT_IN_CONTACT,
    ENABLED_PAIR_ALWAYS_COLLIDING,
    REASON_MISMATCH,
    ROBOT_NAME_MISMATCH,
    UNKNOWN_JOINT,
    UNKNOWN_LINK,
)
from geomcheck.selfcollision.matrix import CollisionMatrix, PairClass, PairResult, WitnessSource


def _mm(metres: float) -> str:
    return f"{metres * 1000:.1f} mm"


def _evidence(pair: PairResult) -> str:
    witness = pair.witness
    if witness is None:  # enabled pairs always carry one; kept for safety
        return "it collides"
    where = f"at {witness.describe()}"
    if witness.source is WitnessSource.SEARCH:
        how = "found by the witness search from the closest samples; no random sample collided"
    elif witness.source is WitnessSource.SAMPLE:
        how = f"in collision in {pair.collisions} of {pair.tested} random samples"
    else:
        how = "at the default pose"
    return f"{_mm(witness.depth)} deep {where} ({how})"


def _close(name: str, choices: Iterable[str]) -> str | None:
    close = difflib.get_close_matches(name, list(choices), n=1)
    return close[0] if close else None


def _names(items: Iterable[str]) -> str:
    return ", ".join(sorted(set(items)))


def _unknown_links(srdf: Srdf, robot: Robot) -> list[Diagnostic]:
    """GC411. A name close to one of the robot's links is a typo or a rename: a warning per
    entry, as the pair it meant stays checked (or unchecked). Names close to none are the links
    of another variant the SRDF also serves (solo12's shoulders in solo8's SRDF): MoveIt's
    srdfdom skips those entries with a warning and pinocchio ignores them, so they are one info
    finding per SRDF; what the robot itself lacks is reported by the audit of its own pairs."""
    links = robot.link_map
    out = []
    entries: list[tuple[str, tuple[str, ...], SourceLocation]] = [
        ("disable_collisions", (d.link1, d.link2), d.location) for d in srdf.disabled
    ]
    entries += [("enable_collisions", (e.link1, e.link2), e.location) for e in srdf.enabled]
    entries += [("disable_default_collisions", (e.link,), e.location) for e in srdf.disabled_links]
    foreign: list[tuple[str, str, SourceLocation]] = []
    for tag, names, location in entries:
        for name in names:
            if name in links:
                continue
            close = _close(name, links)
            if close is None:
                foreign.append((tag, name, location))
                continue
            pair = (names[0], names[1]) if len(names) == 2 else None
            out.append(
                UNKNOWN_LINK.diagnose(
                    f"<{tag}> in {srdf.source} names link '{name}', which the robot does not have "
                    f"(did you mean '{close}'?)",
                    link=None if pair else name,
                    links=pair,
                    about=name,
                    location=location,
                    data={"element": tag, "unknown_link": name},
                )
            )
    if foreign:
        unknown = _names(name for _, name, _ in foreign)
        out.append(
            UNKNOWN_LINK.diagnose(
                f"{len(foreign)} collision entries in {srdf.source} name links the robot does not have and "
                f"none of its links resembles ({unknown}): entries for another variant of the robot, which "
                "MoveIt and pinocchio skip",
                help="Nothing to change if the SRDF serves several variants; else delete the entries.",
                severity=Severity.INFO,
                about="other variant",
                location=foreign[0][2],
                data={"element": _names(tag for tag, _, _ in foreign), "unknown_link": unknown},
            )
        )
    return out


def _unknown_joints(srdf: Srdf, robot: Robot) -> list[Diagnostic]:
    """GC415. A name close to a joint that the pose does not already set is a typo or a rename:
    a warning per value, as the pose is not the one intended. Other unknown names (the joints of
    another variant; a 7-value floating base named as pinocchio names its free-flyer,
    ``root_joint``, without a ``<virtual_joint>``) are skipped by MoveIt and pinocchio while the
    pose's other values apply: one info finding per SRDF."""
    out = []
    foreign: list[tuple[str, str, SourceLocation]] = []
    floating: set[str] = set()
    for state in srdf.group_states:
        for joint, values in state.values.items():
            if joint in robot.joint_map or joint in srdf.virtual_joints:
                continue
            close = None if len(values) == 7 else _close(joint, robot.joint_map)
            if close is None or close in state.values:
                foreign.append((state.name, joint, state.location))
                if len(values) == 7:
                    floating.add(joint)
                continue
            out.append(
                UNKNOWN_JOINT.diagnose(
                    f"group_state '{state.name}' in {srdf.source} sets joint '{joint}', which the robot "
                    f"does not have (did you mean '{close}'?)",
                    joint=joint,
                    about=f"group_state:{state.name}",
                    location=state.location,
                    data={"group_state": state.name, "unknown_joint": joint},
                )
            )
    if foreign:
        names = _names(joint for _, joint, _ in foreign)
        note = (
            f"; {_names(floating)} holds 7 values, a floating base: MoveIt wants it declared as a <virtual_joint>"
            if floating
            else ""
        )
        out.append(
            UNKNOWN_JOINT.diagnose(
                f"{len(foreign)} values of group_states in {srdf.source} set joints the robot does not have "
                f"({names}), none a misspelling of a joint the pose leaves unset: MoveIt and pinocchio skip "
                f"them and apply the rest{note}",
                help="Nothing to change if the SRDF serves several variants; else delete the values.",
                severity=Severity.INFO,
                about="other variant",
                location=foreign[0][2],
                data={"group_state": _names(state for state, _, _ in foreign), "unknown_joint": names},
            )
        )
    return out


def _disabled_entries(srdf: Srdf, matrix: CollisionMatrix) -> dict[tuple[str, str], tuple[str, SourceLocation]]:
    """Every matrix pair the SRDF disables: (reason, location of the element that disables it)."""
    out: dict[tuple[str, str], tuple[str, SourceLocation]] = {}
    for d in srdf.disabled:
        out.setdefault(d.pair, (d.moveit_reason, d.location))
    by_link = {e.link: e.location for e in srdf.disabled_links}
    for pair in matrix.pairs:
        a, b = pair.links
        if pair.links not in out and srdf.is_disabled(a, b):
            location = by_link.get(a) or by_link.get(b) or srdf.location
            out[pair.links] = ("disable_default_collisions", location)
    return out


PairCollides = Callable[[tuple[str, str], Mapping[str, float]], bool]
"""Whether a pair of links collides in a configuration (joint values; the others at the default pose)."""


def rigid_body_of(robot: Robot) -> dict[str, str]:
    """Each link's rigid body: the topmost link it reaches through fixed joints."""
    out: dict[str, str] = {}
    for link in robot.link_map:
        top, seen = link, {link}
        while (joint := robot.parent_joint.get(top)) is not None and joint.type == "fixed" and joint.parent not in seen:
            top = joint.parent
            seen.add(top)
        out[link] = top
    return out


def _proxies(
    pair: PairResult,
    matrix: CollisionMatrix,
    disabled: Mapping[tuple[str, str], object],
    body: Mapping[str, str],
    collides: PairCollides | None,
    holds: Callable[[str, str], bool] | None,
) -> tuple[str, str] | None:
    """An enabled pair of other links fixed to the same two bodies, each holding the collision
    geometry of the link it stands for, that collides where ``pair`` does (at its witness): the
    SRDF checks the two bodies through these proxies (Franka's ``*_sc`` capsule links), so
    disabling ``pair`` loses no contact. ``None`` without one."""
    a, b = pair.links
    witness = pair.witness
    if collides is None or holds is None or witness is None:
        return None
    for other in matrix.pairs:
        c, d = other.links
        if other.links == pair.links or other.links in disabled or other.cls is PairClass.ADJACENT:
            continue
        if body.get(a) == body.get(b):
            continue
        if body.get(c) == body.get(a) and body.get(d) == body.get(b):
            stand = holds(c, a) and holds(d, b)
        elif body.get(c) == body.get(b) and body.get(d) == body.get(a):
            stand = holds(c, b) and holds(d, a)
        else:
            continue
        if stand and collides(other.links, witness.configuration):
            return other.links
    return None


def audit_srdf(
    srdf: Srdf,
    matrix: CollisionMatrix,
    robot: Robot,
    adjacent_contacts: Mapping[tuple[str, str], float] | None = None,
    collides: PairCollides | None = None,
    holds: Callable[[str, str], bool] | None = None,
) -> list[Diagnostic]:
    """Findings of the SRDF audit. ``adjacent_contacts`` gives the penetration depth [m] at
    the default pose of the adjacent pairs in contact there (the matrix does not test
    adjacent pairs) and of the rigidly attached ones (in contact in every pose, which GC403
    leaves to the matrix and this audit); ``collides`` tests a pair at a witness and ``holds``
    whether one link's collision geometry holds another's, to find the proxy links through which
    the SRDF checks a pair it disables."""
    out = _unknown_links(srdf, robot)
    if srdf.robot_name and srdf.robot_name != robot.name:
        out.append(
            ROBOT_NAME_MISMATCH.diagnose(
                f"{srdf.source} is written for robot '{srdf.robot_name}', the description is '{robot.name}'",
                location=srdf.location,
                data={"srdf_robot": srdf.robot_name, "urdf_robot": robot.name},
            )
        )
    out += _unknown_joints(srdf, robot)
    disabled = _disabled_entries(srdf, matrix)
    body = rigid_body_of(robot)
    for pair in matrix.pairs:
        entry = disabled.get(pair.links)
        if entry is not None:
            proxy = _proxies(pair, matrix, disabled, body, collides, holds) if pair.cls is PairClass.ENABLED else None
            out.extend(_audit_disabled(srdf, pair, *entry, proxy=proxy))
        elif pair.cls is PairClass.ALWAYS:
            out.append(_always_colliding(srdf, pair))
    free_flyer = pinocchio_free_flyer(srdf, robot)
    for links, depth in sorted((adjacent_contacts or {}).items()):
        if links not in disabled:
            out.append(_adjacent_in_contact(srdf, matrix, robot, links, depth, free_flyer))
    return out


def _always_colliding(srdf: Srdf, pair: PairResult) -> Diagnostic:
    """GC412: a pair the SRDF checks though it collides in nearly every sampled pose."""
    return ENABLED_PAIR_ALWAYS_COLLIDING.diagnose(
        f"{pair.links[0]} and {pair.links[1]} are in collision in {pair.collisions} of {pair.tested} "
        f"random samples ({pair.fraction or 0:.1%}) but {srdf.source} leaves their collision checking on",
        help=(
            f"Disable the pair (`{_disable_line(pair.links, 'Always')}`), or better, fix the "
            "collision shapes so that they do not overlap."
        ),
        links=pair.links,
        location=srdf.location,
        data={"fraction": round(pair.fraction or 0.0, 6), "tested": pair.tested},
    )


def _adjacent_in_contact(
    srdf: Srdf,
    matrix: CollisionMatrix,
    robot: Robot,
    links: tuple[str, str],
    depth: float,
    free_flyer: str | None,
) -> Diagnostic:
    """GC413: an adjacent or rigidly attached pair in contact at the default pose ``depth`` [m] deep that
    the SRDF checks; information when pinocchio, posing a free-flyer, merges the rigid pair."""
    fixed = fixed_joints_between(robot, *links)
    rigid, severity = "", None
    if fixed:
        joined = f"fixed joint {fixed[0]} joins" if len(fixed) == 1 else f"fixed joints {', '.join(fixed)} join"
        rigid = f", and so in every pose (only {joined} them)"
        if free_flyer is not None:
            severity = Severity.INFO
            rigid += (
                f"; the SRDF poses pinocchio's free-flyer '{free_flyer}' (7 values, no <virtual_joint>), and "
                "pinocchio makes links joined by fixed joints one body, which it never collides with itself"
            )
    result = matrix.pair(*links)
    adjacent = result is None or result.cls is PairClass.ADJACENT
    kind, reason = ("adjacent links", "Adjacent") if adjacent else ("rigidly attached links", "Default")
    return ENABLED_ADJACENT_IN_CONTACT.diagnose(
        f"{kind} {links[0]} and {links[1]} are in collision at the default pose ({_mm(depth)} deep)"
        f"{rigid}, but {srdf.source} leaves their collision checking on",
        help=f"Disable the pair: `{_disable_line(links, reason)}`.",
        severity=severity,
        links=links,
        location=srdf.location,
        data={"depth": round(depth, 6), "depth_mm": round(depth * 1000, 3), "fixed_joints": list(fixed)},
    )


def pinocchio_free_flyer(srdf: Srdf, robot: Robot) -> str | None:
    """The joint a ``<group_state>`` gives 7 values (a position and a quaternion) that is neither a
    joint of the robot nor a ``<virtual_joint>``: pinocchio's free-flyer, which its model builder
    adds above the root link (``root_joint``) and its SRDF reader poses, while MoveIt needs a
    virtual joint for it. Such an SRDF is written for pinocchio; ``None`` otherwise."""
    for state in srdf.group_states:
        for joint, values in state.values.items():
            if len(values) == 7 and joint not in robot.joint_map and joint not in srdf.virtual_joints:
                return joint
    return None


def _disable_line(links: tuple[str, str], reason: str) -> str:
    return f'<disable_collisions link1="{links[0]}" link2="{links[1]}" reason="{reason}"/>'


def _audit_disabled(
    srdf: Srdf, pair: PairResult, reason: str, location: SourceLocation, proxy: tuple[str, str] | None = None
) -> list[Diagnostic]:
    a, b = pair.links
    if pair.cls is PairClass.ENABLED:
        witness = pair.witness
        data: dict[str, object] = {"reason": reason, "class": pair.cls.value, "tested": pair.tested}
        if witness is not None:
            data.update(witness.to_dict())
            data["depth_mm"] = round(witness.depth * 1000, 3)
        data["checked_through"] = list(proxy) if proxy is not None else None
        message = (
            f"{srdf.source} disables collision checking between {a} and {b} (reason {reason}) but they "
            f"collide: {_evidence(pair)}"
        )
        if proxy is not None:
            message += (
                f"; the SRDF checks their bodies through {proxy[0]} and {proxy[1]}, fixed to them, which collide "
                "there too: no contact is lost"
            )
        return [
            DISABLED_PAIR_CAN_COLLIDE.diagnose(
                message,
                links=pair.links,
                location=location,
                data=data,
                severity=Severity.INFO if proxy is not None else None,
            )
        ]
    expected = pair.cls.srdf_reason
    if reason in ("User", "disable_default_collisions"):
        return []
    if expected is not None and reason != expected:
        return [
            REASON_MISMATCH.diagnose(
                f"{srdf.source} disables {a} / {b} as '{reason}', the collision matrix finds '{expected}'",
                links=pair.links,
                location=location,
                data={"reason": reason, "class": pair.cls.value},
            )
        ]
    return []
