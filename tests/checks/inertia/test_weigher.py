"""The inertia family's severity policy (geomcheck.checks.inertia.weigher): a finding lowered by its
consequence (a light link, a merged body that passes, placeholders), never hidden."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.diagnostics import Severity
from geomcheck.model import Box, Joint, Link, Pose, Robot, Shape
from tests.checks.inertia.test_link import (
    PR2_WHEEL_MASS,
    WHEEL_MESH,
    bundle_dir,
    check,
    codes_of,
    inertial,
    only,
    solid_wheel_tensor,
    wheel_link,
)

__all__ = ["bundle_dir"]  # the fixture, used by name


BASE_BOX = Box((1.0, 1.0, 0.4))  # [m]


def base_box(mass: float) -> Link:
    """A solid 1 x 1 x 0.4 m box of ``mass``: consistent, no finding."""
    a, b, c = BASE_BOX.size
    t = (mass * (b * b + c * c) / 12, 0.0, 0.0, mass * (a * a + c * c) / 12, 0.0, mass * (a * a + b * b) / 12)
    return Link("base", inertial=inertial(mass, t), visuals=(Shape("visual", 0, BASE_BOX),))


def on_base(base: Link, wheel: Link, joint_type: str) -> Robot:
    return Robot("r", links=(base, wheel), joints=(Joint("wheel_joint", joint_type, "base", "wheel", axis=(0, 1, 0)),))


def test_light_moving_link_keeps_its_warning_and_says_its_share(bundle_dir: Path) -> None:
    # the PR2 wheel's impossible tensor on a link of 0.44 kg in a robot of 100 kg: still the
    # description's own wrong values, which its maintainer would change
    robot = on_base(base_box(99.55964), wheel_link("wheel", inertial(PR2_WHEEL_MASS)), "continuous")
    d = only(check(bundle_dir, robot), "GC505")
    assert (d.link, d.severity) == ("wheel", Severity.WARNING)
    assert d.message.endswith("(kept at warning: the link carries 0.44% of the robot's 100 kg)")
    assert d.data["mass_share"] == pytest.approx(0.0044036)
    assert (d.data["body"], d.data["body_mass_share"]) == (None, None)


def test_merged_body_that_passes_keeps_a_fixed_links_warning(bundle_dir: Path) -> None:
    # the wheel is fixed to a 2 kg base box: the merged body (what pinocchio and Gazebo simulate)
    # is possible for the box and wheel together, but the wheel's own tensor is still wrong
    d = only(check(bundle_dir, on_base(base_box(2.0), wheel_link("wheel", inertial(PR2_WHEEL_MASS)), "fixed")), "GC505")
    assert (d.link, d.severity) == ("wheel", Severity.WARNING)
    assert "(kept at warning: fixed joints merge it with base into body base, which passes this check" in d.message
    assert "the link's own values are still wrong" in d.message
    assert (d.data["body"], d.data["body_mass_share"]) == ("base", pytest.approx(PR2_WHEEL_MASS / 2.44036, rel=1e-5))


def test_placeholder_values_on_a_merged_frame_are_info(bundle_dir: Path) -> None:
    # a camera frame's 0.01 kg and 0.001 kg m^2, typed for "unknown", on a frame fixed to a body that passes
    frame = wheel_link("wheel", inertial(0.01, (0.001, 0.0, 0.0, 0.001, 0.0, 0.001)))
    d = only(check(bundle_dir, on_base(base_box(2.0), frame, "fixed")), "GC505")
    assert (d.link, d.severity) == ("wheel", Severity.INFO)
    assert "placeholder values (powers of ten) on a frame fixed to body base, which passes this check" in d.message


def test_negligible_mass_is_a_massless_frames_placeholder(bundle_dir: Path) -> None:
    wheel = wheel_link("wheel", inertial(1e-8, (1e-6, 0.0, 0.0, 1e-6, 0.0, 1e-6)))
    d = only(check(bundle_dir, on_base(base_box(10.0), wheel, "continuous")), "GC505")
    assert d.severity is Severity.INFO
    assert "its 1e-08 kg makes it a massless frame's placeholder, not a part" in d.message


def test_heavy_link_keeps_the_rules_severity(bundle_dir: Path) -> None:
    base = Link("base", inertial=inertial(0.5, solid_wheel_tensor(0.5)), visuals=(Shape("visual", 0, WHEEL_MESH),))
    wheel = wheel_link("wheel", inertial(PR2_WHEEL_MASS))
    joint = Joint("wheel_joint", "fixed", "base", "wheel", axis=(0.0, 1.0, 0.0))
    # merged, base and wheel still need a radius of gyration beyond the wheel: the body fails too
    d = only(check(bundle_dir, Robot("r", links=(base, wheel), joints=(joint,))), "GC505")
    assert d.severity is Severity.WARNING and "lowered" not in d.message and "mass_share" not in d.data


def test_triangle_inequality_is_not_lowered_by_weight(bundle_dir: Path) -> None:
    # MuJoCo refuses A + B < C whatever the link weighs
    wheel = wheel_link("wheel", inertial(0.01, (1e-6, 0.0, 0.0, 1e-6, 0.0, 1e-5)))
    d = only(check(bundle_dir, on_base(base_box(100.0), wheel, "continuous")), "GC504")
    assert d.severity is Severity.ERROR and "lowered" not in d.message


def test_triangle_inequality_in_a_valid_merged_body_is_lowered_to_warning(bundle_dir: Path) -> None:
    wheel = wheel_link("wheel", inertial(0.01, (1e-6, 0.0, 0.0, 1e-6, 0.0, 1e-5)))
    d = only(check(bundle_dir, on_base(base_box(100.0), wheel, "fixed")), "GC504")
    assert d.severity is Severity.WARNING
    assert "(error lowered to warning: fixed joints merge it with base into body base" in d.message


def test_identical_placeholder_inertials_lower_the_plausibility_findings(bundle_dir: Path) -> None:
    # every link carries the same macro default (2 kg, 0.01 kg m^2, centre of mass at the origin)
    placeholder = (0.01, 0.0, 0.0, 0.01, 0.0, 0.01)
    far = Shape("visual", 0, Box((0.02, 0.1, 0.1)), Pose((0.2, 0.0, 0.0)))
    links = [Link(n, inertial=inertial(2.0, placeholder), visuals=(far,)) for n in ("base", "a", "b")]
    joints = tuple(Joint(f"{n}_joint", "revolute", "base", n, axis=(0, 0, 1)) for n in ("a", "b"))
    result = check(bundle_dir, Robot("r", links=tuple(links), joints=joints))
    found = [d for d in result.diagnostics if d.code == "GC506"]
    assert [(d.link, d.severity) for d in found] == [(n, Severity.INFO) for n in ("base", "a", "b")]
    assert "all 3 links with an <inertial> carry this same one: placeholders" in found[0].message


def test_negative_mass_stays_an_error_on_a_light_link(bundle_dir: Path) -> None:
    base = Link("base", inertial=inertial(100.0, solid_wheel_tensor(100.0)), visuals=(Shape("visual", 0, WHEEL_MESH),))
    wheel = wheel_link("wheel", inertial(-0.01, solid_wheel_tensor(0.01)))
    joint = Joint("wheel_joint", "fixed", "base", "wheel", axis=(0.0, 1.0, 0.0))
    d = only(check(bundle_dir, Robot("r", links=(base, wheel), joints=(joint,))), "GC502")
    assert d.severity is Severity.ERROR


def test_a_zero_mass_carrying_a_tensor_on_a_fixed_link(bundle_dir: Path) -> None:
    # a placeholder end effector of 0 kg with a 1e-8 tensor: no body without mass has inertia
    gripper = wheel_link("wheel", inertial(0.0, (1e-8, 0.0, 0.0, 1e-8, 0.0, 1e-8)))
    d = only(check(bundle_dir, on_base(base_box(10.0), gripper, "fixed")), "GC502")
    assert (d.link, d.severity) == ("wheel", Severity.WARNING)
    assert d.message == (
        "mass is 0 kg but the inertia tensor is not zero (largest value 1e-08 kg m^2): no body without mass has "
        "rotational inertia"
    )
    # a massless frame (or PyBullet's static world root) wants its tensor gone, not a mass
    assert d.help is not None and d.help.startswith("Delete the tensor (zero inertia) if the link is meant to be")
    massless = wheel_link("wheel", inertial(0.0, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)))
    assert "GC502" not in codes_of(check(bundle_dir, on_base(base_box(10.0), massless, "fixed")))
