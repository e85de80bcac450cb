"""The report's ``model`` section: the file's links and joints with their frames, axes and
limits, read as URDF's whatever the format, the loader's frames folded back in."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import geomcheck
from geomcheck.report.section_model import ModelSection


def section(tmp_path: Path, name: str, text: str) -> ModelSection:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    report = geomcheck.check(path, select=["GC1"], use_config=False)
    return ModelSection.from_dict(report.sections["model"])


def test_a_urdf_joint_is_written_as_the_file_writes_it(tmp_path: Path) -> None:
    text = """<robot name="r"><link name="a"><inertial><origin xyz="0 0 0.1"/><mass value="2"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="2" iyz="0" izz="3"/></inertial>
      <collision name="c"><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.1" length="0.4"/></geometry></collision>
      </link><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="1 2 3" rpy="0 0 0.5"/>
        <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="2"/></joint></robot>"""
    model = section(tmp_path, "r.urdf", text)
    a = model.link("a")
    assert a is not None and a.inertial is not None and a.inertial.mass == 2.0
    assert dict(a.inertial.inertia) == {"ixx": 1.0, "ixy": 0.0, "ixz": 0.0, "iyy": 2.0, "iyz": 0.0, "izz": 3.0}
    (c,) = a.collisions
    assert (c.name, c.type, dict(c.geometry), c.origin.xyz) == (
        "c",
        "cylinder",
        {"radius": 0.1, "length": 0.4},
        (0, 0, 0.2),
    )
    j = model.joint("j")
    assert j is not None and (j.type, j.parent, j.child) == ("revolute", "a", "b")
    assert (j.origin.xyz, j.origin.rpy, j.axis) == ((1.0, 2.0, 3.0), (0.0, 0.0, 0.5), (0.0, 1.0, 0.0))
    assert dict(j.limit or {}) == {"lower": -1.0, "upper": 1.0, "effort": 5.0, "velocity": 2.0}


def test_an_sdformat_universal_joint_is_one_joint_with_two_axes_in_its_child(tmp_path: Path) -> None:
    """The joint frame 0.2 above the child's origin and turned: the loader turns both axes about
    it through frames of its own; the section gives the child in the parent, and both axes in
    the child link's frame."""
    text = """<sdf version="1.7"><model name="m">
      <link name="a"/>
      <link name="b"><pose>0 0 1 0 0 1.5707963267948966</pose></link>
      <joint name="u" type="universal"><pose>0 0 0.2 0 0 0</pose><parent>a</parent><child>b</child>
        <axis><xyz expressed_in="__model__">1 0 0</xyz></axis><axis2><xyz>0 0 1</xyz></axis2></joint>
    </model></sdf>"""
    model = section(tmp_path, "model.sdf", text)
    assert [link.name for link in model.links] == ["a", "b"]  # no frame of the loader's
    (u,) = model.joints
    assert (u.name, u.type, u.parent, u.child) == ("u", "universal", "a", "b")
    assert u.origin.xyz == pytest.approx((0.0, 0.0, 1.0)) and u.origin.rpy == pytest.approx((0.0, 0.0, math.pi / 2))
    assert u.axis == pytest.approx((0.0, -1.0, 0.0))  # the model's x, in b's frame turned a quarter about z
    assert u.axis2 == pytest.approx((0.0, 0.0, 1.0))
    assert u.limit is not None and (u.limit["lower"], u.limit["upper"]) == (None, None)  # SDFormat's default: open
