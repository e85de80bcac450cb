"""URDF numbers: unparseable, missing and non-finite values, and parsing going on after them."""

from __future__ import annotations

from geomcheck.model import Cylinder
from tests.load.urdf_sample import URDF, line_of


def test_parsing_goes_on_after_bad_numbers(load) -> None:
    text = URDF.replace('<mass value="2.5"/>', '<mass value="heavy"/>').replace(
        '<box size="0.6 0.6 0.2"/>', '<box size="0.6 0.6"/>'
    )
    loaded = load(text)
    found = [(d.code, d.link, d.about, d.location.line) for d in loaded.diagnostics]
    assert found == [
        ("GC107", "base", "inertial.mass.value", line_of(text, "<mass")),
        ("GC107", "base", "collision[0].box.size", line_of(text, '<box size="0.6 0.6"/>')),
    ]
    assert loaded.diagnostics[1].message == (
        '<box size="0.6 0.6"> is not 3 numbers: expected 3, got 2; urdfdom logs an error and loads the link '
        "without this element"
    )
    assert loaded.diagnostics[1].data["accepted_by"] == "urdfdom"  # it drops the collision, the robot loads
    base = loaded.robot.link_map["base"]
    assert base.inertial is not None and base.inertial.mass == 0.0
    assert [s.geometry for s in base.collisions] == [Cylinder(0.1, 0.3)]  # the bad box is dropped
    assert [link.name for link in loaded.robot.links] == ["base", "wheel"]


def test_nan_and_inf_are_invalid(load) -> None:
    loaded = load(URDF.replace('<origin xyz="0 0.3 0"', '<origin xyz="0 nan 0"'))
    (d,) = loaded.diagnostics
    assert (d.code, d.joint, d.about) == ("GC107", "wheel_joint", "origin.xyz")


def test_missing_required_attributes(load) -> None:
    loaded = load(URDF.replace('<limit effort="10" velocity="5"/>', '<limit effort="10"/>'))
    (d,) = loaded.diagnostics
    assert (d.code, d.joint, d.message) == ("GC108", "wheel_joint", "<limit> has no velocity attribute")
