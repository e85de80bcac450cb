"""One robot written in URDF and in SDFormat gives the same model, findings and fixes (each in
its own syntax)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.load import load_description, make_bundle
from geomcheck.model import Box, Cylinder, Joint, Mesh, Sphere
from tests.load.sdftools import world, write

URDF_TWIN = """<robot name="twin">
  <link name="base_link">
    <inertial><origin xyz="0 0 0.05"/><mass value="3"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial>
    <visual><geometry><mesh filename="box.stl"/></geometry></visual>
    <collision><origin xyz="0 0 0.01"/><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/>
    <parent link="base_link"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="arm">
    <inertial><origin xyz="0.1 0 0"/><mass value="1"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.004"/></inertial>
    <visual><origin xyz="0.1 0 0"/><geometry><mesh filename="bar.stl"/></geometry></visual>
    <collision><origin xyz="0.1 0 0" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.01" length="0.2"/></geometry></collision>
  </link>
  <joint name="elbow" type="revolute">
    <origin xyz="0.2 0 0"/>
    <parent link="arm"/><child link="hand"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="5" velocity="1"/>
  </joint>
  <link name="hand">
    <inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
    <collision><geometry><sphere radius="0.04"/></geometry></collision>
  </link>
</robot>
"""


# the same robot by hand in SDFormat 1.7: the shoulder as URDF writes it (relative to its parent,
# the arm relative to the joint), the hand with its pose in the model frame
# (0, 0, 0.1) + Rz(90 deg) (0.2, 0, 0) = (0, 0.2, 0.1)
SDF_TWIN = """<sdf version="1.7"><model name="twin">
  <link name="base_link">
    <inertial><pose>0 0 0.05 0 0 0</pose><mass>3</mass>
      <inertia><ixx>0.02</ixx><iyy>0.02</iyy><izz>0.03</izz></inertia></inertial>
    <visual name="v"><geometry><mesh><uri>box.stl</uri></mesh></geometry></visual>
    <collision name="c"><pose>0 0 0.01 0 0 0</pose><geometry><box><size>0.2 0.2 0.1</size></box></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <pose relative_to="base_link">0 0 0.1 0 0 1.5707963267948966</pose>
    <parent>base_link</parent><child>arm</child>
    <axis><xyz>0 1 0</xyz>
      <limit><lower>-1</lower><upper>1</upper><effort>10</effort><velocity>1</velocity></limit></axis>
  </joint>
  <link name="arm">
    <pose relative_to="shoulder"/>
    <inertial><pose>0.1 0 0 0 0 0</pose><mass>1</mass>
      <inertia><ixx>0.001</ixx><iyy>0.004</iyy><izz>0.004</izz></inertia></inertial>
    <visual name="v"><pose>0.1 0 0 0 0 0</pose><geometry><mesh><uri>bar.stl</uri></mesh></geometry></visual>
    <collision name="c"><pose>0.1 0 0 0 1.5707963267948966 0</pose>
      <geometry><cylinder><radius>0.01</radius><length>0.2</length></cylinder></geometry></collision>
  </link>
  <joint name="elbow" type="revolute">
    <parent>arm</parent><child>hand</child>
    <axis><xyz expressed_in="arm">0 0 1</xyz>
      <limit><lower>-2</lower><upper>2</upper><effort>5</effort><velocity>1</velocity></limit></axis>
  </joint>
  <link name="hand">
    <pose>0 0.2 0.1 0 0 1.5707963267948966</pose>
    <inertial><mass>0.5</mass><inertia><ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz></inertia></inertial>
    <collision name="c"><geometry><sphere><radius>0.04</radius></sphere></geometry></collision>
  </link>
</model></sdf>
"""


def twin_meshes(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    trimesh.creation.box((0.2, 0.2, 0.16)).export(folder / "box.stl")  # taller than its collision box: GC301
    bar = trimesh.creation.box((0.2, 0.03, 0.03))
    bar.export(folder / "bar.stl")


def check(root: Path) -> list[tuple[str, str | None, tuple[str, ...], str, str]]:
    from geomcheck.options import CheckOptions, Selection
    from geomcheck.pipeline import run_check

    options = CheckOptions(selection=Selection(select=("GC2", "GC3", "GC5", "GC403")))
    report = run_check(make_bundle(root, display_root=root.parent), options)
    return sorted((d.code, d.link, d.links or (), d.about, d.severity) for d in report.diagnostics)


def test_one_robot_in_urdf_and_sdf_gives_the_same_model_and_findings(tmp_path: Path) -> None:
    twin_meshes(tmp_path)
    urdf = write(tmp_path / "twin.urdf", URDF_TWIN)
    sdf = write(tmp_path / "twin.sdf", SDF_TWIN)
    a = load_description(make_bundle(urdf, display_root=tmp_path)).robot
    b = load_description(make_bundle(sdf, display_root=tmp_path)).robot
    assert [link.name for link in a.links] == [link.name for link in b.links]
    assert [(j.name, j.type, j.parent, j.child) for j in a.joints] == [
        (j.name, j.type, j.parent, j.child) for j in b.joints
    ]
    for q in ({}, {"shoulder": 0.4, "elbow": -0.7}):
        wa, wb = world(a, q), world(b, q)
        for name in wa:
            np.testing.assert_allclose(wa[name], wb[name], atol=1e-6, err_msg=name)
    for link in a.links:
        twin = b.link_map[link.name]
        assert link.inertial is not None and twin.inertial is not None
        assert twin.inertial.mass == link.inertial.mass
        np.testing.assert_allclose(twin.inertial.tensor(), link.inertial.tensor(), atol=1e-12)
        np.testing.assert_allclose(twin.inertial.origin.matrix(), link.inertial.origin.matrix(), atol=1e-9)
        for mine, theirs in zip((*link.visuals, *link.collisions), (*twin.visuals, *twin.collisions), strict=True):
            assert type(mine.geometry) is type(theirs.geometry) and isinstance(
                mine.geometry, Box | Cylinder | Sphere | Mesh
            )
            np.testing.assert_allclose(mine.origin.matrix(), theirs.origin.matrix(), atol=1e-9)
    findings = check(urdf)
    assert findings == check(sdf)
    assert {f[:2] for f in findings} >= {("GC301", "base_link")}


def test_joint_frames_agree_with_the_urdf_twin(tmp_path: Path) -> None:
    twin_meshes(tmp_path)
    a = load_description(make_bundle(write(tmp_path / "twin.urdf", URDF_TWIN), display_root=tmp_path)).robot
    b = load_description(make_bundle(write(tmp_path / "twin.sdf", SDF_TWIN), display_root=tmp_path)).robot
    for joint in a.joints:
        other: Joint = b.joint_map[joint.name]
        np.testing.assert_allclose(other.axis, joint.axis, atol=1e-12)
        np.testing.assert_allclose(other.origin.matrix(), joint.origin.matrix(), atol=1e-9)
        assert other.limit is not None and joint.limit is not None
        assert (other.limit.lower, other.limit.upper, other.limit.effort) == (
            joint.limit.lower,
            joint.limit.upper,
            joint.limit.effort,
        )


def test_cli_checks_an_sdf_model(tmp_path: Path) -> None:
    import json

    from geomcheck.cli import main

    twin_meshes(tmp_path)
    root = write(tmp_path / "twin.sdf", SDF_TWIN)
    out = tmp_path / "report.json"
    assert main(["check", str(root), "--format", "json", "-o", str(out), "--no-untrusted", "--exit-zero"]) == 0
    report = json.loads(out.read_text())
    assert report["robot"]["name"] == "twin"
    codes = {(d["code"], d.get("link")) for d in report["diagnostics"]}
    assert ("GC301", "base_link") in codes
    # the fixes section's patch is written in SDFormat: the base's collision box takes the mesh's height
    patch = report["sections"]["fixes"]["unsafe_patch"]
    assert '+    <collision name="c"><pose>0 0 0 0 0 0</pose><geometry><box><size>0.2 0.2 0.16</size>' in patch


def test_each_twins_finding_offers_its_fix_in_its_own_syntax(tmp_path: Path) -> None:
    """The SDFormat twin's GC301 keeps the URDF twin's advice and gets the same fix written in
    SDFormat (``<pose>``, ``<box><size>``), in the report and in its JSON form read back."""
    from geomcheck.diagnostics import diagnostic_from_dict, diagnostic_to_dict
    from geomcheck.fixes.model import SetAttribute, SetPose, SetText
    from geomcheck.options import CheckOptions, Selection
    from geomcheck.pipeline import run_check

    twin_meshes(tmp_path)
    options = CheckOptions(selection=Selection(select=("GC301",)))
    found = {}
    for name, text in (("twin.urdf", URDF_TWIN), ("twin.sdf", SDF_TWIN)):
        report = run_check(make_bundle(write(tmp_path / name, text), display_root=tmp_path), options)
        [d] = [d for d in report.diagnostics if d.link == "base_link"]
        found[name] = d
    urdf, sdf = found["twin.urdf"], found["twin.sdf"]
    assert urdf.fix is not None and urdf.editable and urdf.syntax == "urdf"
    assert sdf.fix is not None and sdf.editable and sdf.syntax == "sdf"
    assert sdf.message == urdf.message and sdf.fix.title == urdf.fix.title
    assert urdf.help.endswith('<origin xyz="0 0 0" rpy="0 0 0"/>\n<geometry><box size="0.2 0.2 0.16"/></geometry>')
    assert sdf.help.endswith("<pose>0 0 0 0 0 0</pose>\n<geometry><box><size>0.2 0.2 0.16</size></box></geometry>")
    assert sdf.help.split(":\n")[0] == urdf.help.split(":\n")[0]
    assert SetAttribute(("origin",), "xyz", "0 0 0") in urdf.fix.changes
    assert sdf.fix.changes == (SetPose("0 0 0", "0 0 0"), SetText(("geometry", "box", "size"), "0.2 0.2 0.16"))
    assert diagnostic_to_dict(sdf)["fix"]["syntax"] == "sdf" and "syntax" not in diagnostic_to_dict(urdf)["fix"]
    assert diagnostic_from_dict(diagnostic_to_dict(sdf)).fix == sdf.fix
    assert diagnostic_from_dict(diagnostic_to_dict(urdf)).fix == urdf.fix
