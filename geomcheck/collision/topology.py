"""Which link pairs the tree relates: MoveIt's *Adjacent* pairs, and rigid bodies.

Two semantics of "a pair of links" exist for self-collision:

* **moveit** (MoveIt, the default): every two links with collision geometry make a pair;
  the SRDF must disable the pairs that touch by design (Adjacent, Default, Always).
* **pinocchio** (Pinocchio's ``GeometryModel.addAllCollisionPairs``): links joined only by
  fixed joints are one body, moved by the same joint, and are never checked against each
  other; an SRDF written for Pinocchio does not list those pairs.
"""

from __future__ import annotations

from collections.abc import Iterable

from geomcheck.model import Joint, Robot
from geomcheck.options import SEMANTICS

__all__ = ["SEMANTICS", "adjacent_pairs", "body_root", "excluded_pairs", "fixed_joints_between", "rigid_pairs"]


def adjacent_pairs(robot: Robot, scene_links: Iterable[str]) -> set[tuple[str, str]]:
    """Link pairs MoveIt calls *Adjacent*: the tree path between the two links (both with
    geometry) passes only through links without geometry; a parent and child with geometry
    are the shortest case. Pairs are sorted tuples."""
    with_geometry = set(scene_links)
    graph: dict[str, set[str]] = {}
    for j in robot.joints:
        if j.parent and j.child and j.parent != j.child:
            graph.setdefault(j.parent, set()).add(j.child)
            graph.setdefault(j.child, set()).add(j.parent)
    out: set[tuple[str, str]] = set()
    for start in sorted(with_geometry):
        seen, frontier = {start}, [start]
        while frontier:
            node = frontier.pop()
            for nxt in graph.get(node, ()):
                if nxt in seen:
                    continue
                seen.add(nxt)
                if nxt in with_geometry:
                    out.add((start, nxt) if start < nxt else (nxt, start))
                else:
                    frontier.append(nxt)
    return out


def _fixed_chain(robot: Robot, link: str) -> list[Joint]:
    """The fixed joints from ``link`` up to the top of its rigid body, bottom-up."""
    parent = robot.parent_joint
    out: list[Joint] = []
    seen = {link}
    while (joint := parent.get(out[-1].parent if out else link)) is not None and joint.type == "fixed":
        if joint.parent in seen:
            break
        seen.add(joint.parent)
        out.append(joint)
    return out


def body_root(robot: Robot, link: str) -> str:
    """The top link of ``link``'s rigid body: up the tree while the joint above is fixed."""
    chain = _fixed_chain(robot, link)
    return chain[-1].parent if chain else link


def rigid_pairs(robot: Robot, links: Iterable[str]) -> set[tuple[str, str]]:
    """Pairs of ``links`` that only fixed joints join (one rigid body), as sorted tuples."""
    bodies: dict[str, list[str]] = {}
    for link in sorted(set(links)):
        bodies.setdefault(body_root(robot, link), []).append(link)
    return {(a, b) for members in bodies.values() for i, a in enumerate(members) for b in members[i + 1 :]}


def fixed_joints_between(robot: Robot, a: str, b: str) -> tuple[str, ...]:
    """The joints (sorted names) on the tree path between links ``a`` and ``b`` when all of
    them are fixed, else ``()``: the joints up to the body's top from one link and not the other."""
    chain_a, chain_b = _fixed_chain(robot, a), _fixed_chain(robot, b)
    top_a = chain_a[-1].parent if chain_a else a
    top_b = chain_b[-1].parent if chain_b else b
    if a == b or top_a != top_b:
        return ()
    return tuple(sorted({j.name for j in chain_a} ^ {j.name for j in chain_b}))


def excluded_pairs(robot: Robot, links: Iterable[str], semantics: str) -> set[tuple[str, str]]:
    """Pairs of ``links`` that are not collision pairs under ``semantics`` (sorted tuples)."""
    return rigid_pairs(robot, links) if semantics == "pinocchio" else set()
