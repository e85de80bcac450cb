"""Which link pairs the tree relates: MoveIt adjacency, rigid bodies, the two semantics."""

from __future__ import annotations

import pytest

from geomcheck.collision import adjacent_pairs, excluded_pairs, fixed_joints_between, rigid_pairs
from geomcheck.collision.topology import body_root
from geomcheck.model import Joint, Link, Pose, Robot


def robot() -> Robot:
    """base - hub (fixed) - arm (revolute) - tip (fixed) - tool (fixed); base - post (fixed);
    arm - finger (prismatic). Only the names and joint types matter here."""
    names = ("base", "hub", "arm", "tip", "tool", "post", "finger")
    joints = (
        Joint("base_hub", "fixed", "base", "hub", Pose()),
        Joint("hub_arm", "revolute", "hub", "arm", Pose(), (0, 0, 1)),
        Joint("arm_tip", "fixed", "arm", "tip", Pose()),
        Joint("tip_tool", "fixed", "tip", "tool", Pose()),
        Joint("base_post", "fixed", "base", "post", Pose()),
        Joint("arm_finger", "prismatic", "arm", "finger", Pose(), (1, 0, 0)),
    )
    return Robot("r", tuple(Link(n) for n in names), joints)


def test_adjacent_pairs_follow_moveit() -> None:
    r = robot()
    # hub has no geometry here: base and arm are adjacent through it
    assert adjacent_pairs(r, ("base", "arm", "post")) == {("arm", "base"), ("base", "post")}
    # with tip in, arm-tip is adjacent, base-tip is not (arm in between has geometry)
    assert adjacent_pairs(r, ("base", "arm", "tip", "post")) == {("arm", "base"), ("base", "post"), ("arm", "tip")}
    # without geometry on the base, everything joined through it is adjacent
    assert adjacent_pairs(r, ("arm", "post")) == {("arm", "post")}
    # tip without geometry: arm-tool adjacent through it
    assert ("arm", "tool") in adjacent_pairs(r, ("arm", "tool", "finger"))


def test_rigid_bodies_are_links_joined_by_fixed_joints_only() -> None:
    r = robot()
    assert [body_root(r, n) for n in ("base", "hub", "post", "arm", "tip", "tool", "finger")] == [
        "base",
        "base",
        "base",
        "arm",
        "arm",
        "arm",
        "finger",
    ]
    links = ("base", "hub", "arm", "tip", "tool", "post", "finger")
    assert rigid_pairs(r, links) == {
        ("base", "hub"),
        ("base", "post"),
        ("hub", "post"),
        ("arm", "tip"),
        ("arm", "tool"),
        ("tip", "tool"),
    }
    assert fixed_joints_between(r, "tool", "arm") == ("arm_tip", "tip_tool")
    assert fixed_joints_between(r, "hub", "post") == ("base_hub", "base_post")
    assert fixed_joints_between(r, "tip", "finger") == ()  # the finger slides
    assert fixed_joints_between(r, "base", "arm") == ()  # the arm turns


@pytest.mark.parametrize(("semantics", "expected"), [("moveit", set()), ("pinocchio", {("arm", "tip")})])
def test_excluded_pairs_by_semantics(semantics: str, expected: set[tuple[str, str]]) -> None:
    assert excluded_pairs(robot(), ("base", "arm", "tip", "finger"), semantics) == expected
