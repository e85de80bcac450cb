"""SDFormat geometry: the shapes geomcheck measures, those it leaves out and says so, and
numbers no geometry can hold."""

from __future__ import annotations

from pathlib import Path

import pytest

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.errors import InputError
from geomcheck.model import Cone
from tests.load.sdftools import load


def test_shapes_geomcheck_does_not_measure_are_left_out_and_said(tmp_path: Path) -> None:
    """A submesh, a height map or a polyline is valid SDFormat: the model loads, the element is
    left out of every check and the report's skipped entries say which and why."""
    text = """<sdf version="1.11"><model name="m"><link name="a">
      <visual name="part"><geometry><mesh><uri>a.dae</uri><submesh><name>part</name></submesh></mesh></geometry>
      </visual>
      <collision name="ground"><geometry><heightmap/></geometry></collision>
      <collision name="plate"><geometry><polyline><point>0 0</point><point>1 0</point><point>0 1</point>
        <height>0.1</height></polyline></geometry></collision>
      <collision name="c"><geometry><cone><radius>0.2</radius><length>0.5</length></cone></geometry></collision>
      <visual name="empty"/>
      <visual name="nothing"><geometry/></visual>
    </link></model></sdf>"""
    loaded = load(tmp_path, text)
    (link,) = loaded.robot.links
    assert link.visuals == () and [c.name for c in link.collisions] == ["c"]
    assert link.collisions[0].geometry == Cone(0.2, 0.5)  # measured as the cylinder that encloses it
    assert [(s.check, s.subject, s.reason) for s in loaded.skipped] == [
        ("geometry", "a", "visual 'part': <submesh> is not measured by geomcheck"),
        ("geometry", "a", "collision 'ground': <heightmap> is not measured by geomcheck"),
        ("geometry", "a", "collision 'plate': <polyline> is not measured by geomcheck"),
    ]


@pytest.mark.parametrize(
    ("element", "limit"),
    [
        ("<pose>1e300 0 0 0 0 0</pose>", "max_length_m"),
        ("<collision name='c'><geometry><box><size>1e308 1 1</size></box></geometry></collision>", "max_length_m"),
        ("<inertial><mass>1e300</mass></inertial>", "max_mass_kg"),
        (
            "<visual name='v'><geometry><mesh><uri>m.stl</uri><scale>1e9 1 1</scale></mesh></geometry></visual>",
            "max_mesh_scale",
        ),
    ],
)
def test_numbers_no_geometry_can_hold_are_refused(tmp_path: Path, element: str, limit: str) -> None:
    text = f'<sdf version="1.7"><model name="m"><link name="a">{element}</link></model></sdf>'
    with pytest.raises(InputError, match=f"beyond the limit of .* \\({limit}\\)"):
        load(tmp_path, text)
    # SDFormat's own "no limit" (1e16) is an open bound, not a number out of range
    joint = """<sdf version="1.7"><model name="m"><link name="a"/><link name="b"/>
      <joint name="j" type="prismatic"><parent>a</parent><child>b</child>
        <axis><xyz>1 0 0</xyz><limit><lower>-1e16</lower><upper>0.5</upper></limit></axis></joint></model></sdf>"""
    (j,) = load(tmp_path, joint, "joint.sdf").robot.joints
    assert j.limit is not None and (j.limit.lower, j.limit.upper, j.limit.unlimited) == (None, 0.5, True)
