"""Forward kinematics: transforms, limits, default pose, mimic joints, tree queries."""

from __future__ import annotations

import numpy as np
import pytest

from geomcheck.errors import UsageError
from geomcheck.kinematics import Kinematics, rotation_matrices
from geomcheck.model import Joint, Limit, Link, Mimic, Pose, Robot


def joint(name, type_, parent, child, xyz=(0, 0, 0), rpy=(0, 0, 0), axis=(0, 0, 1), limit=None, mimic=None):
    return Joint(name, type_, parent, child, Pose(xyz, rpy), axis, limit, mimic)


def chain_robot() -> Robot:
    """world -(planar)- base -(revolute z, x=1)- arm -(prismatic x)- slider, arm -(continuous)- wheel,
    base -(revolute, mimics 'shoulder' x2 + 0.1)- twin, base -(fixed)- laser."""
    links = tuple(Link(n) for n in ("base", "arm", "slider", "wheel", "twin", "laser"))
    joints = (
        joint("base_joint", "planar", "world", "base", xyz=(0, 0, 0.5)),
        joint("shoulder", "revolute", "base", "arm", xyz=(1, 0, 0), limit=Limit(-1.0, 2.0)),
        joint("slide", "prismatic", "arm", "slider", axis=(1, 0, 0), limit=Limit(0.1, 0.3)),
        joint("spin", "continuous", "arm", "wheel", xyz=(0, 0.5, 0), axis=(0, 1, 0)),
        joint("twin_joint", "revolute", "base", "twin", limit=Limit(-5, 5), mimic=Mimic("shoulder", 2.0, 0.1)),
        joint("laser_joint", "fixed", "base", "laser", xyz=(0.2, 0, 0.3)),
    )
    return Robot("chain", links, joints)


def test_variables_limits_and_tree_order() -> None:
    kin = Kinematics(chain_robot())
    assert kin.root == "world"
    assert [j.name for j in kin.joints] == ["shoulder", "slide", "spin"]
    assert kin.link_names == ("base", "arm", "slider", "wheel", "twin", "laser")
    np.testing.assert_allclose(kin.lower, [-1.0, 0.1, -np.pi])
    np.testing.assert_allclose(kin.upper, [2.0, 0.3, np.pi])
    assert kin.index("slide") == 1


def test_default_configuration_mid_range_and_pose() -> None:
    kin = Kinematics(chain_robot())
    np.testing.assert_allclose(kin.default_configuration(), [0.0, 0.2, 0.0])
    np.testing.assert_allclose(kin.default_configuration({"spin": 1.5}), [0.0, 0.2, 1.5])
    with pytest.raises(UsageError, match=r"invalid joint 'nope'.*shoulder, slide, spin"):
        kin.default_configuration({"nope": 1.0})
    with pytest.raises(UsageError, match="mimics 'shoulder'"):
        kin.default_configuration({"twin_joint": 1.0})
    with pytest.raises(UsageError, match="laser_joint"):
        kin.index("laser_joint")


def test_link_transforms_match_hand_computation() -> None:
    kin = Kinematics(chain_robot())
    q = np.array([[np.pi / 2, 0.25, 0.3], [0.0, 0.1, 0.0]])
    t = kin.link_transforms(q)
    assert t.shape == (2, 6, 4, 4)
    base, arm, slider, wheel, twin, laser = range(6)
    np.testing.assert_allclose(t[0, base, :3, 3], [0, 0, 0.5])  # planar root held at its origin
    np.testing.assert_allclose(t[0, arm, :3, 3], [1, 0, 0.5])
    np.testing.assert_allclose(t[0, arm, :3, :3], rotation_matrices(np.array([0, 0, 1.0]), np.array([np.pi / 2]))[0])
    # slider moves 0.25 along the arm's x, which the shoulder turned onto world y
    np.testing.assert_allclose(t[0, slider, :3, 3], [1, 0.25, 0.5], atol=1e-12)
    # the wheel sits 0.5 along the arm's y (world -x) and spins about it
    np.testing.assert_allclose(t[0, wheel, :3, 3], [0.5, 0, 0.5], atol=1e-12)
    np.testing.assert_allclose(t[0, wheel, :3, 1], [-1, 0, 0], atol=1e-12)
    # the mimic follows: 2 * pi/2 + 0.1 about z
    expected = rotation_matrices(np.array([0, 0, 1.0]), np.array([np.pi + 0.1]))[0]
    np.testing.assert_allclose(t[0, twin, :3, :3], expected, atol=1e-12)
    np.testing.assert_allclose(t[1, laser, :3, 3], [0.2, 0, 0.8])


def test_joint_axes() -> None:
    kin = Kinematics(chain_robot())
    points, dirs = kin.joint_axes(np.array([[np.pi / 2, 0.2, 0.0]]))
    np.testing.assert_allclose(points[0, 0], [1, 0, 0.5])
    np.testing.assert_allclose(dirs[0, 0], [0, 0, 1])
    np.testing.assert_allclose(dirs[0, 2], [-1, 0, 0], atol=1e-12)


def test_sample_is_seeded_and_within_limits() -> None:
    kin = Kinematics(chain_robot())
    a = kin.sample(500, np.random.default_rng(3))
    b = kin.sample(500, np.random.default_rng(3))
    assert a.shape == (500, 3)
    np.testing.assert_array_equal(a, b)
    assert np.all(a >= kin.lower) and np.all(a <= kin.upper)


def test_path_joints_and_subtree() -> None:
    kin = Kinematics(chain_robot())
    assert kin.path_joints("slider", "wheel") == ("slide", "spin")
    assert kin.path_joints("base", "slider") == ("shoulder", "slide")
    assert kin.path_joints("twin", "arm") == ("shoulder",)  # the mimic contributes its leader
    assert kin.path_joints("base", "laser") == ()
    assert kin.subtree("arm") == ("arm", "slider", "wheel")
    assert kin.subtree("laser") == ("laser",)
    with pytest.raises(UsageError, match="invalid link"):
        kin.subtree("ghost")


def test_mimic_chain_folds_and_broken_mimic_is_a_variable() -> None:
    links = tuple(Link(n) for n in ("a", "b", "c", "d"))
    joints = (
        joint("j1", "revolute", "a", "b", limit=Limit(-1, 1)),
        joint("j2", "revolute", "b", "c", limit=Limit(-9, 9), mimic=Mimic("j1", 2.0, 0.5)),
        joint("j3", "revolute", "c", "d", limit=Limit(-9, 9), mimic=Mimic("j2", 3.0, 0.25)),
    )
    kin = Kinematics(Robot("m", links, joints))
    assert [j.name for j in kin.joints] == ["j1"]
    t = kin.link_transforms(np.array([[0.1]]))
    # j3 = 3 * (2 * 0.1 + 0.5) + 0.25 = 2.35; total rotation about z: 0.1 + 0.7 + 2.35
    angle = np.arctan2(t[0, 3, 1, 0], t[0, 3, 0, 0])
    assert angle == pytest.approx(np.arctan2(np.sin(3.15), np.cos(3.15)))
    broken = (joints[0], joint("j2", "revolute", "b", "c", limit=Limit(-1, 1), mimic=Mimic("missing")))
    assert [j.name for j in Kinematics(Robot("m", links[:3], broken)).joints] == ["j1", "j2"]


def test_several_roots_keep_the_largest_tree() -> None:
    links = tuple(Link(n) for n in ("lonely", "a", "b", "c"))
    joints = (joint("ab", "fixed", "a", "b"), joint("bc", "continuous", "b", "c"))
    kin = Kinematics(Robot("r", links, joints))
    assert kin.root == "a"
    assert kin.link_names == ("a", "b", "c")


def test_batched_transforms_are_vectorised_and_fast() -> None:
    kin = Kinematics(chain_robot())
    q = kin.sample(10000, np.random.default_rng(0))
    t = kin.link_transforms(q)
    single = np.stack([kin.link_transforms(q[i : i + 1])[0] for i in (0, 4321, 9999)])
    np.testing.assert_allclose(t[[0, 4321, 9999]], single)
