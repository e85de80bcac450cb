"""The SRDF audit (GC410-GC416): an existing SRDF's collision entries against the matrix."""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping

from geomcheck.collision.topology import fixed_joints_between
from geomcheck.diagnostics import Diagnostic
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


def _did_you_mean(name: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(choices), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


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


def _unknown_links(srdf: Srdf, robot: Robot) -> list[Diagnostic]:
    links = robot.link_map
    out = []
    entries: list[tuple[str, tuple[str, ...], SourceLocation]] = [
        ("disable_collisions", (d.link1, d.link2), d.location) for d in srdf.disabled
    ]
    entries += [("enable_collisions", (e.link1, e.link2), e.location) for e in srdf.enabled]
    entries += [("disable_default_collisions", (e.link,), e.location) for e in srdf.disabled_links]
    for tag, names, location in entries:
        for name in names:
            if name in links:
                continue
            pair = (names[0], names[1]) if len(names) == 2 else None
            out.append(
                UNKNOWN_LINK.diagnose(
                    f"<{tag}> in {srdf.source} names link '{name}', which the robot does not have"
                    + _did_you_mean(name, links),
                    link=None if pair else name,
                    links=pair,
                    about=name,
                    location=location,
                    data={"element": tag, "unknown_link": name},
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


def audit_srdf(
    srdf: Srdf,
    matrix: CollisionMatrix,
    robot: Robot,
    adjacent_contacts: Mapping[tuple[str, str], float] | None = None,
) -> list[Diagnostic]:
    """Findings of the SRDF audit. ``adjacent_contacts`` gives the penetration depth [m] at
    the default pose of the adjacent pairs in contact there (the matrix does not test
    adjacent pairs) and of the rigidly attached ones (in contact in every pose, which GC403
    leaves to the matrix and this audit)."""
    out = _unknown_links(srdf, robot)
    if srdf.robot_name and srdf.robot_name != robot.name:
        out.append(
            ROBOT_NAME_MISMATCH.diagnose(
                f"{srdf.source} is written for robot '{srdf.robot_name}', the description is '{robot.name}'",
                location=srdf.location,
                data={"srdf_robot": srdf.robot_name, "urdf_robot": robot.name},
            )
        )
    for state in srdf.group_states:
        for joint, values in state.values.items():
            if joint not in robot.joint_map and joint not in srdf.virtual_joints:
                hint = (
                    f" (its {len(values)} values look like a floating base: declare it as a <virtual_joint>)"
                    if len(values) == 7
                    else _did_you_mean(joint, robot.joint_map)
                )
                out.append(
                    UNKNOWN_JOINT.diagnose(
                        f"group_state '{state.name}' in {srdf.source} sets joint '{joint}', which the robot "
                        "does not have" + hint,
                        joint=joint,
                        about=f"group_state:{state.name}",
                        location=state.location,
                        data={"group_state": state.name, "unknown_joint": joint},
                    )
                )
    disabled = _disabled_entries(srdf, matrix)
    for pair in matrix.pairs:
        entry = disabled.get(pair.links)
        if entry is not None:
            out.extend(_audit_disabled(srdf, pair, *entry))
        elif pair.cls is PairClass.ALWAYS:
            out.append(
                ENABLED_PAIR_ALWAYS_COLLIDING.diagnose(
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
            )
    for links, depth in sorted((adjacent_contacts or {}).items()):
        if links in disabled:
            continue
        fixed = fixed_joints_between(robot, *links)
        rigid = ""
        if fixed:
            joined = f"fixed joint {fixed[0]} joins" if len(fixed) == 1 else f"fixed joints {', '.join(fixed)} join"
            rigid = f", and so in every pose (only {joined} them)"
        result = matrix.pair(*links)
        adjacent = result is None or result.cls is PairClass.ADJACENT
        kind, reason = ("adjacent links", "Adjacent") if adjacent else ("rigidly attached links", "Default")
        out.append(
            ENABLED_ADJACENT_IN_CONTACT.diagnose(
                f"{kind} {links[0]} and {links[1]} are in collision at the default pose ({_mm(depth)} deep)"
                f"{rigid}, but {srdf.source} leaves their collision checking on",
                help=f"Disable the pair: `{_disable_line(links, reason)}`.",
                links=links,
                location=srdf.location,
                data={"depth": round(depth, 6), "depth_mm": round(depth * 1000, 3), "fixed_joints": list(fixed)},
            )
        )
    return out


def _disable_line(links: tuple[str, str], reason: str) -> str:
    return f'<disable_collisions link1="{links[0]}" link2="{links[1]}" reason="{reason}"/>'


def _audit_disabled(srdf: Srdf, pair: PairResult, reason: str, location: SourceLocation) -> list[Diagnostic]:
    a, b = pair.links
    if pair.cls is PairClass.ENABLED:
        witness = pair.witness
        data: dict[str, object] = {"reason": reason, "class": pair.cls.value, "tested": pair.tested}
        if witness is not None:
            data.update(witness.to_dict())
            data["depth_mm"] = round(witness.depth * 1000, 3)
        return [
            DISABLED_PAIR_CAN_COLLIDE.diagnose(
                f"{srdf.source} disables collision checking between {a} and {b} (reason {reason}) but they "
                f"collide: {_evidence(pair)}",
                links=pair.links,
                location=location,
                data=data,
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
