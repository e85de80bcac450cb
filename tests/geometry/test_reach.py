"""Rigid groups and swept bounds (geomcheck.geometry.reach)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay

from geomcheck.geometry.reach import revolved, rigid_groups, swept_bound
from geomcheck.model import Joint, Limit, Link, Pose, Robot


def robot() -> Robot:
    """base -(fixed, x 1 m)- plate; base -(revolute z, x 2 m)- arm -(fixed, x 0.5 m)- tip;
    base -(prismatic x)- slide."""
    links = tuple(Link(n) for n in ("base", "plate", "arm", "tip", "slide"))
    joints = (
        Joint("plate_joint", "fixed", "base", "plate", Pose((1.0, 0.0, 0.0))),
        Joint("arm_joint", "revolute", "base", "arm", Pose((2.0, 0.0, 0.0)), axis=(0.0, 0.0, 1.0)),
        Joint("tip_joint", "fixed", "arm", "tip", Pose((0.5, 0.0, 0.0))),
        Joint("slide_joint", "prismatic", "base", "slide", Pose(), axis=(1.0, 0.0, 0.0), limit=Limit(-0.2, 0.3)),
    )
    return Robot("r", links=links, joints=joints)


def test_rigid_groups_follow_fixed_joints() -> None:
    groups = rigid_groups(robot())
    assert dict(groups.anchor) == {"base": "base", "plate": "base", "arm": "arm", "tip": "arm", "slide": "slide"}
    assert groups.members("arm") == ["arm", "tip"]
    np.testing.assert_allclose(groups.pose["tip"][1], [0.5, 0.0, 0.0])


def test_revolved_bound_contains_every_turn_of_the_points() -> None:
    points = np.array([[0.5, 0.0, 0.1], [0.3, 0.2, -0.1]])
    hull = Delaunay(revolved(points, np.array([0.0, 0.0, 1.0])))
    angles = np.linspace(0.0, 2.0 * np.pi, 37)
    turned = np.concatenate(
        [
            points @ np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]]).T
            for a in angles
        ]
    )
    assert (hull.find_simplex(turned * (1.0 - 1e-9)) >= 0).all()


def test_swept_bound_of_an_arm_is_its_disc_about_the_joint() -> None:
    r = robot()
    root, bound = swept_bound(r, rigid_groups(r), "arm", np.array([[0.5, 0.0, 0.0]]))  # type: ignore[misc]
    assert root == "base"
    # the tip's point turns on a circle of radius 0.5 m about (2, 0, 0)
    assert np.isclose(bound[:, 0].min(), 1.5, atol=0.02) and np.isclose(bound[:, 0].max(), 2.5, atol=0.02)
    assert np.allclose(bound[:, 2], 0.0)


def test_swept_bound_of_a_slide_spans_its_travel() -> None:
    r = robot()
    root, bound = swept_bound(r, rigid_groups(r), "slide", np.zeros((1, 3)))  # type: ignore[misc]
    assert root == "base" and sorted(bound[:, 0].tolist()) == [-0.2, 0.3]


def test_floating_or_unlimited_joints_reach_anywhere() -> None:
    r = robot()
    free = Robot(
        "r",
        links=r.links,
        joints=(*r.joints[:3], Joint("slide_joint", "prismatic", "base", "slide", Pose(), axis=(1.0, 0.0, 0.0))),
    )
    assert swept_bound(free, rigid_groups(free), "slide", np.zeros((1, 3))) is None
