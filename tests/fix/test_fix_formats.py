"""``geomcheck fix`` on MJCF and SDFormat descriptions: fixes written in the file's own syntax
(an MJCF ``<geom type size pos quat>``, ``<inertial diaginertia|fullinertia>``; an SDFormat
``<pose>``, ``<box><size>``, ``<cylinder><radius><length>``, ``<inertia><ixx>``, ``<uri>``),
verified by the format's own loader (MuJoCo's compiler, the SDFormat reader) and the check
again, and refused with the reason when they cannot be written safely."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh

from geomcheck.cli import main
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.fixes.help_syntax import help_in_syntax
from geomcheck.fixes.values import quaternion, rotation_rpy
from geomcheck.load import LoadedDescription, load_description, make_bundle
from geomcheck.model import Box, Cylinder
from geomcheck.options import CheckOptions
from geomcheck.patch.plan import plan_fixes
from geomcheck.patch.plan_formats import moments_text
from geomcheck.pipeline import run_check
from tests.conftest import validate_report

# a 0.4 x 0.2 x 0.1 m part whose collision box (a class shared with the correct box of "other")
# is half its size and turned 10 degrees, and whose inertia is 200 times what it can be;
# the other body's part is exactly the class's box
MJCF = """<mujoco model="m">
  <compiler angle="degree"/>
  <asset>
    <mesh name="part" file="part.stl"/>
    <mesh name="small" file="small.stl"/>
  </asset>
  <default>
    <default class="visual"><geom contype="0" conaffinity="0" group="2"/></default>
    <default class="collision"><geom type="box" size="0.1 0.05 0.025" group="3"/></default>
  </default>
  <worldbody>
    <body name="base" pos="0 0 0.5">
      <joint name="j" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="2" diaginertia="5 5 5"/>
      <geom class="visual" type="mesh" mesh="part"/>
      <geom class="collision" pos="0.01 0 0" euler="0 0 10"/>
    </body>
    <body name="other" pos="2 0 0.5">
      <joint name="k" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="1" diaginertia="0.002 0.0005 0.002"/>
      <geom class="visual" type="mesh" mesh="small"/>
      <geom class="collision"/>
    </body>
  </worldbody>
</mujoco>
"""

# a capsule written with fromto and a full inertia on one body; a box placed by a <frame> on another
MJCF_FROMTO = """<mujoco model="m2">
  <asset><mesh name="part" file="part.stl"/></asset>
  <worldbody>
    <body name="a" pos="0 0 0.5">
      <joint name="j" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="2" fullinertia="5 5 5 0.1 0 0"/>
      <geom type="mesh" mesh="part" contype="0" conaffinity="0"/>
      <geom type="capsule" fromto="-0.1 0 0 0.1 0 0" size="0.02"/>
    </body>
    <body name="b" pos="1 0 0.5">
      <joint name="k" type="hinge" axis="0 0 1"/>
      <geom type="mesh" mesh="part" contype="0" conaffinity="0"/>
      <frame pos="0.1 0 0"><geom type="box" size="0.1 0.05 0.025"/></frame>
    </body>
  </worldbody>
</mujoco>
"""

SDF = """<?xml version="1.0"?>
<sdf version="1.9">
  <model name="s">
    <link name="base">
      <pose>0 0 0.5 0 0 0</pose>
      <inertial>
        <mass>2</mass>
        <inertia><ixx>5</ixx><iyy>5</iyy><izz>5</izz></inertia>
      </inertial>
      <visual name="v">
        <geometry><mesh><uri>part.stl</uri></mesh></geometry>
      </visual>
      <collision name="c">
        <pose relative_to="__model__" degrees="true">0.01 0 0.5 0 0 10</pose>
        <geometry>
          <box>
            <size>0.2 0.1 0.05</size>
          </box>
        </geometry>
      </collision>
    </link>
    <link name="rod">
      <pose>1 0 0.5 0 0 0</pose>
      <inertial>
        <mass>0.5</mass>
        <inertia><ixx>0.0038625</ixx><iyy>0.0038625</iyy><izz>0.000225</izz></inertia>
      </inertial>
      <visual name="v">
        <geometry><mesh><uri>Rod.STL</uri></mesh></geometry>
      </visual>
      <collision name="c">
        <geometry><cylinder><radius>0.01</radius><length>0.1</length></cylinder></geometry>
      </collision>
    </link>
    <joint name="j" type="revolute">
      <parent>base</parent><child>rod</child>
      <axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>
    </joint>
  </model>
</sdf>
"""
CYLINDER = "<radius>0.03</radius><length>0.3</length>"


@pytest.fixture
def work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    trimesh.creation.box((0.4, 0.2, 0.1)).export(tmp_path / "part.stl")
    trimesh.creation.box((0.2, 0.1, 0.05)).export(tmp_path / "small.stl")
    trimesh.creation.cylinder(radius=0.03, height=0.3, sections=64).export(tmp_path / "rod.stl")
    return tmp_path


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def findings(path: Path, link: str | None = None) -> list[tuple[str, str | None, str]]:
    report = run_check(make_bundle(path, display_root=path.parent), CheckOptions())
    return sorted((d.code, d.link, d.about) for d in report.diagnostics if link is None or d.link == link)


def line_with(text: str, needle: str) -> str:
    [line] = [line.strip() for line in text.splitlines() if needle in line]
    return line


def loaded(path: Path) -> LoadedDescription:
    return load_description(make_bundle(path, display_root=path.parent))


def test_an_mjcf_geom_takes_the_fitted_box_and_the_body_the_implied_inertia(
    work: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = MJCF
    (work / "m.xml").write_text(text)
    assert [(c, link) for c, link, _ in findings(work / "m.xml") if c in ("GC301", "GC505")] == [
        ("GC301", "base"),
        ("GC505", "base"),
    ]
    status, _, err = run(capsys, "fix", "--unsafe-fixes", "--format", "concise", "m.xml")
    fixed = (work / "m.xml").read_text()
    assert err.splitlines()[0] == "geomcheck: fixed 2 findings in m.xml"
    # on the geom itself, MuJoCo's half extents, a quaternion (w x y z) instead of the degrees of
    # euler, the type its class gives not written again; the class other geoms share stays as it
    # is, and so does the other body's geom
    assert line_with(fixed, 'class="collision" pos') == (
        '<geom class="collision" pos="0 0 0" size="0.2 0.1 0.05" quat="1 0 0 0"/>'
    )
    assert line_with(fixed, '<default class="collision">') in text
    assert '<geom class="collision"/>' in fixed
    # the box's tensor about its centre for 2 kg: m (b^2 + c^2) / 12 ...
    moments = [2.0 * (0.2**2 + 0.1**2) / 12.0, 2.0 * (0.4**2 + 0.1**2) / 12.0, 2.0 * (0.4**2 + 0.2**2) / 12.0]
    written = line_with(fixed, 'mass="2"').split('diaginertia="')[1].split('"')[0]
    assert [float(v) for v in written.split()] == pytest.approx(moments, rel=1e-5)
    assert written == "0.0083333 0.0283333 0.0333333"
    # everything else byte for byte
    before = [line for line in text.splitlines() if 'mass="2"' not in line and 'pos="0.01 0 0"' not in line]
    after = [line for line in fixed.splitlines() if 'mass="2"' not in line and 'class="collision" pos' not in line]
    assert before == after
    # MuJoCo compiles the fixed file and the check finds neither finding again
    [box] = loaded(work / "m.xml").robot.link_map["base"].collisions
    assert isinstance(box.geometry, Box) and box.geometry.size == pytest.approx((0.4, 0.2, 0.1))
    assert box.origin.xyz == pytest.approx((0.0, 0.0, 0.0)) and box.origin.rpy == pytest.approx((0.0, 0.0, 0.0))
    assert [c for c, _, _ in findings(work / "m.xml", "base") if c in ("GC301", "GC505")] == []
    assert status == 0
    _, _, err = run(capsys, "fix", "--unsafe-fixes", "m.xml")
    assert err.splitlines()[0] == "geomcheck: fixed nothing"


def test_an_mjcf_fromto_capsule_keeps_its_type_and_a_full_inertia_stays_full(
    work: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (work / "m2.xml").write_text(MJCF_FROMTO)
    report = run_check(make_bundle(work / "m2.xml", display_root=work), CheckOptions())
    [fit] = [d for d in report.diagnostics if d.code == "GC301" and d.link == "a"]
    suggested = fit.data["suggested"]
    assert suggested["type"] == "cylinder"
    radius, length = suggested["geometry"]["radius"], suggested["geometry"]["length"]
    assert radius == pytest.approx(math.hypot(0.1, 0.05), abs=1e-5) and length == pytest.approx(0.4, abs=1e-5)
    status, _, err = run(capsys, "fix", "--unsafe-fixes", "m2.xml")
    fixed = (work / "m2.xml").read_text()
    # the capsule the fitted cylinder encloses (half-length of its cylinder part: L/2 - r), at
    # the fitted pose: pos and quat replace fromto, the z axis turned onto the body's x axis
    quat = quaternion(rotation_rpy(suggested["origin"]["rpy"]))
    assert np.abs(quat) == pytest.approx([math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0], abs=1e-6)
    geom = line_with(fixed, 'type="capsule"')
    assert "fromto" not in geom
    assert geom.startswith(f'<geom type="capsule" size="{radius:.6g} {length / 2 - radius:.6g}" pos="0 0 0" quat="')
    # fullinertia as before, in the body's axes, the products of inertia exactly 0
    assert line_with(fixed, "<inertial") == (
        '<inertial pos="0 0 0" mass="2" fullinertia="0.0083333 0.0283333 0.0333333 0 0 0"/>'
    )
    capsule = loaded(work / "m2.xml").robot.link_map["a"].collisions[0]
    assert isinstance(capsule.geometry, Cylinder)
    assert (capsule.geometry.radius, capsule.geometry.length) == pytest.approx((radius, length), abs=2e-6)
    # the <frame>'s box is not in its body's frame: refused, named, and left as written
    assert (
        "geomcheck: not fixed automatically: GC301 link b: use the fitted box: the <geom> at m2.xml:13 is inside "
        "the <frame> at m2.xml:13: its pos and quat are not in its body's frame; write the fitted primitive by hand"
    ) in err.splitlines()
    assert '<frame pos="0.1 0 0"><geom type="box" size="0.1 0.05 0.025"/></frame>' in fixed
    assert [(c, link) for c, link, _ in findings(work / "m2.xml") if c in ("GC301", "GC505")] == [("GC301", "b")]
    assert status == 1  # the <frame>'s box still fails


def test_an_inertia_mujoco_infers_from_the_geoms_is_refused(work: Path) -> None:
    text = MJCF.replace('      <inertial pos="0 0 0" mass="2" diaginertia="5 5 5"/>\n', "")
    (work / "m.xml").write_text(text)
    description = loaded(work / "m.xml")
    base = description.robot.link_map["base"]
    assert base.inertial is not None and base.inertial.from_geometry
    implied = {"ixx": 0.01, "ixy": 0.0, "ixz": 0.0, "iyy": 0.03, "iyz": 0.0, "izz": 0.03}
    d = Diagnostic(
        "GC505",
        "inertia-exceeds-geometry",
        Severity.WARNING,
        "message",
        "help",
        link="base",
        about="inertia",
        location=base.inertial.location,
        data={"implied_inertia": implied},
        syntax="mjcf",
    )
    [planned] = plan_fixes(description, [d], unsafe=True).fixes
    assert planned.edits == ()
    assert planned.reason.startswith("MuJoCo infers this body's inertia from its geoms")


def test_an_sdf_collision_takes_the_fitted_primitives_pose_in_its_links_frame(
    work: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (work / "s.sdf").write_text(SDF.replace("Rod.STL", "rod.stl"))
    before = findings(work / "s.sdf")
    assert [(c, link) for c, link, _ in before if c in ("GC301", "GC505")] == [
        ("GC301", "base"),
        ("GC301", "rod"),
        ("GC505", "base"),
    ]
    report = run_check(make_bundle(work / "s.sdf", display_root=work), CheckOptions())
    [rod_fit] = [d for d in report.diagnostics if d.code == "GC301" and d.link == "rod"]
    cylinder = rod_fit.data["suggested"]
    status, _, err = run(capsys, "fix", "--unsafe-fixes", "s.sdf")
    fixed = (work / "s.sdf").read_text()
    assert err.splitlines()[0] == "geomcheck: fixed 3 findings in s.sdf"
    # the pose stated relative to the model is now stated relative to the link, in radians
    assert line_with(fixed, "<pose relative_to") == '<pose relative_to="base">0 0 0 0 0 0</pose>'
    assert line_with(fixed, "<size>") == "<size>0.4 0.2 0.1</size>"  # full extents
    moments = "<ixx>0.0083333</ixx><iyy>0.0283333</iyy><izz>0.0333333</izz>"
    assert f"<inertia>{moments}</inertia>" in fixed  # the products of inertia stay SDFormat's 0, unwritten
    radius, length = cylinder["geometry"]["radius"], cylinder["geometry"]["length"]
    assert radius == pytest.approx(0.03, abs=1e-3) and length == pytest.approx(0.3, abs=1e-5)
    assert line_with(fixed, "<cylinder>") == (
        f"<geometry><cylinder><radius>{radius:.6g}</radius><length>{length:.6g}</length></cylinder></geometry>"
    )
    assert cylinder["origin"]["xyz"] == pytest.approx([0, 0, 0], abs=1e-6)  # at the link origin: no <pose> added
    # the SDFormat loader reads the fixed file; neither finding is reported again
    robot = loaded(work / "s.sdf").robot
    [box] = robot.link_map["base"].collisions
    assert isinstance(box.geometry, Box) and box.geometry.size == pytest.approx((0.4, 0.2, 0.1))
    assert box.origin.xyz == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
    [rod] = robot.link_map["rod"].collisions
    assert isinstance(rod.geometry, Cylinder) and rod.geometry.radius == pytest.approx(radius)
    after = findings(work / "s.sdf")
    assert [f for f in after if f[0] in ("GC301", "GC505")] == []
    assert set(after) <= set(before)
    assert status == 0


def test_an_sdf_mesh_uri_in_the_wrong_letter_case_is_a_safe_fix(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # the rod's cylinder as it should be: once the mesh is found, the fit check finds nothing
    (work / "s.sdf").write_text(SDF.replace("<radius>0.01</radius><length>0.1</length>", CYLINDER))
    assert ("GC201", "rod", "visual[0]") in findings(work / "s.sdf")
    status, out, err = run(capsys, "fix", "--diff", "s.sdf")
    assert status == 1
    assert [line for line in out.splitlines() if line[:1] in "+-" and line[:3] not in ("+++", "---")] == [
        "-        <geometry><mesh><uri>Rod.STL</uri></mesh></geometry>",
        "+        <geometry><mesh><uri>rod.stl</uri></mesh></geometry>",
    ]
    assert err.splitlines() == [
        "geomcheck: would fix 1 finding in s.sdf",
        "geomcheck: 2 more fixes available with --unsafe-fixes",
    ]
    assert "Rod.STL" in (work / "s.sdf").read_text()  # --diff writes nothing


def test_the_reports_fixes_section_holds_the_formats_own_patch(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (work / "m.xml").write_text(MJCF)
    (work / "s.sdf").write_text(SDF)
    for root, wanted in (
        ("m.xml", '+      <geom class="collision" pos="0 0 0" size="0.2 0.1 0.05" quat="1 0 0 0"/>'),
        ("s.sdf", '+        <pose relative_to="base">0 0 0 0 0 0</pose>'),
    ):
        _, out, _ = run(capsys, "check", "--format", "json", root)
        document: dict[str, Any] = json.loads(out)
        validate_report(document)
        section = document["sections"]["fixes"]
        assert wanted in section["unsafe_patch"].splitlines()
        fixes = {d["code"]: d["fix"] for d in document["diagnostics"] if d["fix"] is not None}
        assert fixes["GC301"]["syntax"] == ("mjcf" if root == "m.xml" else "sdf")
        assert fixes["GC301"]["element"] == ("geom" if root == "m.xml" else "collision")


URDF_FIT_HELP = (
    "Enlarge or move the cylinder to enclose the mesh; a fitted cylinder:\n"
    '<origin xyz="0.1 0 0.02" rpy="0 1.5708 0"/>\n<geometry><cylinder radius="0.03" length="0.3"/></geometry>'
)


@pytest.mark.parametrize(
    ("syntax", "expected"),
    [
        ("urdf", URDF_FIT_HELP),
        (
            "mjcf",
            "Enlarge or move the cylinder to enclose the mesh; a fitted cylinder:\n"
            '<geom type="cylinder" size="0.03 0.15" pos="0.1 0 0.02" quat="0.707107 0 0.707107 0"/>',
        ),
        (
            "sdf",
            "Enlarge or move the cylinder to enclose the mesh; a fitted cylinder:\n<pose>0.1 0 0.02 0 1.5708 0</pose>\n"
            "<geometry><cylinder><radius>0.03</radius><length>0.3</length></cylinder></geometry>",
        ),
    ],
)
def test_the_help_gives_the_fitted_primitive_in_the_formats_syntax(syntax: str, expected: str) -> None:
    # MuJoCo's half-length, and the quarter turn the help's four decimals round off snapped back
    assert help_in_syntax(URDF_FIT_HELP, syntax) == expected


def test_the_help_of_a_turned_cylinder_and_a_mesh_path_in_the_formats_syntax() -> None:
    turn = 'Set rpy="1.5708 0 0" on the cylinder\'s origin: <origin xyz="0 0 0.1" rpy="1.5708 0 0"/>'
    assert help_in_syntax(turn, "mjcf") == (
        'Set quat="0.707107 0.707107 0 0" on the geom: <geom pos="0 0 0.1" quat="0.707107 0.707107 0 0"/>'
    )
    assert help_in_syntax(turn, "sdf") == (
        "Set the angles of the collision's <pose> to 1.5708 0 0: <pose>0 0 0.1 1.5708 0 0</pose>"
    )
    path = 'The file exists with other letter case: use filename="meshes/rod.stl".'
    assert help_in_syntax(path, "sdf") == "The file exists with other letter case: use <uri>meshes/rod.stl</uri>."


def test_a_reports_mjcf_and_sdf_findings_give_their_help_in_their_syntax(work: Path) -> None:
    (work / "m.xml").write_text(MJCF)
    (work / "s.sdf").write_text(SDF)
    helps = {}
    for root in ("m.xml", "s.sdf"):
        report = run_check(make_bundle(work / root, display_root=work), CheckOptions())
        helps.update({(root, d.code, d.link): d.help for d in report.diagnostics})
    assert helps[("m.xml", "GC301", "base")].endswith(
        '\n<geom type="box" size="0.2 0.1 0.05" pos="0 0 0" quat="1 0 0 0"/>'
    )
    assert helps[("s.sdf", "GC301", "base")].endswith(
        "\n<pose>0 0 0 0 0 0</pose>\n<geometry><box><size>0.4 0.2 0.1</size></box></geometry>"
    )
    assert helps[("s.sdf", "GC201", "rod")] == "The file exists with other letter case: use <uri>rod.stl</uri>."


def fitted_cylinder() -> dict[str, Any]:
    return {
        "element": "cylinder",
        "suggested": {
            "type": "cylinder",
            "origin": {"xyz": [0.0, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]},
            "geometry": {"radius": 0.03, "length": 0.3},
        },
    }


def sdf_finding(description: LoadedDescription, link: str, data: dict[str, Any]) -> Diagnostic:
    [shape] = description.robot.link_map[link].collisions
    return Diagnostic(
        "GC301",
        "collision-does-not-cover-mesh",
        Severity.ERROR,
        "message",
        "help",
        link=link,
        about="collision[0]",
        location=shape.location,
        data=data,
        syntax="sdf",
    )


def test_sdf_fixes_of_a_capsule_and_of_a_model_included_from_outside_are_refused(tmp_path: Path) -> None:
    """A capsule is read as the cylinder enclosing it (the fitted cylinder is not a capsule's
    value to write), and an included model's file outside the checked folder is never written."""
    models = tmp_path / "models" / "widget"
    models.mkdir(parents=True)
    (models / "model.config").write_text("<model><name>widget</name><sdf version='1.9'>widget.sdf</sdf></model>")
    (models / "widget.sdf").write_text(
        '<sdf version="1.9"><model name="widget"><link name="body">'
        "<collision name='c'><geometry><cylinder><radius>0.01</radius><length>0.1</length></cylinder></geometry>"
        "</collision></link></model></sdf>"
    )
    robot = tmp_path / "robot"
    robot.mkdir()
    (robot / "model.sdf").write_text(
        '<sdf version="1.9"><model name="cart"><link name="base">\n'
        "<collision name='c'><geometry><capsule><radius>0.01</radius><length>0.1</length></capsule></geometry>"
        "</collision></link>\n"
        "<include><uri>model://widget</uri><name>w</name></include>\n"
        '<joint name="j" type="fixed"><parent>base</parent><child>w::body</child></joint></model></sdf>'
    )
    description = load_description(make_bundle(robot / "model.sdf", search=[tmp_path / "models"], display_root=robot))
    capsule = sdf_finding(description, "base", fitted_cylinder())
    included = sdf_finding(description, "w::body", fitted_cylinder())
    plan = plan_fixes(description, [capsule, included], unsafe=True)
    assert [(p.subject, p.reason) for p in plan.fixes] == [
        (
            "link base",
            "the <capsule> at model.sdf:2 is read as the cylinder enclosing it: write the fitted cylinder by hand",
        ),
        ("link w::body", "../models/widget/widget.sdf is outside the checked folder: fixes write only inside it"),
    ]
    assert plan.edits == ()


def test_rounded_principal_moments_keep_the_triangle_inequality_mujoco_enforces() -> None:
    # a flat plate: C = A + B exactly; six digits each would make C exceed A + B and MuJoCo refuse it
    plate = np.array([0.1234564, 0.1234564, 0.2469128])
    text = moments_text(plate)
    a, b, c = (float(v) for v in text.split())
    assert text.split()[:2] == ["0.123456", "0.123456"] and c <= a + b and c == pytest.approx(0.2469128, rel=1e-5)
    assert moments_text(np.array([1.0, 2.0, 2.5])) == "1 2 2.5"


def test_a_diagonal_mjcf_inertia_of_a_turned_part_takes_the_quat_of_its_principal_axes(
    work: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    turn = trimesh.transformations.rotation_matrix(math.radians(30.0), [0, 0, 1])
    trimesh.creation.box((0.4, 0.2, 0.1), transform=turn).export(work / "turned.stl")
    text = (
        MJCF.replace('file="part.stl"', 'file="turned.stl"')
        .replace('      <geom class="collision" pos="0.01 0 0" euler="0 0 10"/>\n', "")
        .replace('<default class="visual"><geom contype="0" conaffinity="0" group="2"/></default>', "")
        .replace('class="visual" ', "")
    )
    (work / "m.xml").write_text(text)
    _, _, err = run(capsys, "fix", "--unsafe-fixes", "--select", "GC505", "m.xml")
    assert err.splitlines()[0] == "geomcheck: fixed 1 finding in m.xml"
    inertial = line_with((work / "m.xml").read_text(), 'mass="2"')
    assert " quat=" in inertial and " diaginertia=" in inertial
    # MuJoCo's compiled tensor, in the body's axes, is the turned box's
    moments = np.diag([2.0 * (0.2**2 + 0.1**2), 2.0 * (0.4**2 + 0.1**2), 2.0 * (0.4**2 + 0.2**2)]) / 12.0
    expected = turn[:3, :3] @ moments @ turn[:3, :3].T
    compiled = loaded(work / "m.xml").robot.link_map["base"].inertial
    assert compiled is not None and not compiled.from_geometry
    axes = compiled.origin.rotation()
    assert axes @ compiled.tensor() @ axes.T == pytest.approx(expected, abs=1e-7)
    assert [c for c, _, _ in findings(work / "m.xml", "base") if c == "GC505"] == []


def test_a_missing_sdf_inertia_is_written_as_one_element(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # without <inertia>, SDFormat gives the 2 kg base a unit tensor: far beyond its geometry
    text = SDF.replace("        <inertia><ixx>5</ixx><iyy>5</iyy><izz>5</izz></inertia>\n", "")
    (work / "s.sdf").write_text(text)
    _, out, _ = run(capsys, "fix", "--unsafe-fixes", "--diff", "--select", "GC505", "s.sdf")
    assert [line for line in out.splitlines() if line[:1] in "+-" and line[:3] not in ("+++", "---")] == [
        "+        <inertia><ixx>0.0083333</ixx><iyy>0.0283333</iyy><izz>0.0333333</izz></inertia>"
    ]


MJCF_CLASS_CAPSULE = """<mujoco model="m3">
  <default>
    <default class="collision">
      <geom type="capsule"/>
      <default class="collision-left"><geom contype="2"/></default>
    </default>
  </default>
  <asset><mesh name="part" file="part.stl"/></asset>
  <worldbody>
    <body name="a" pos="0 0 0.5" childclass="collision-left">
      <joint name="j" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="2" diaginertia="0.0083333 0.0283333 0.0333333"/>
      <geom type="mesh" mesh="part" contype="0" conaffinity="0"/>
      <geom size="0.02 0.05" quat="0.707107 0 0.707107 0"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_a_capsule_its_class_gives_stays_a_capsule(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The type comes from the class ``collision`` that ``collision-left`` (the body's
    childclass) is nested in: the fitted cylinder is written as the capsule it encloses, and
    no ``type`` is added."""
    (work / "m3.xml").write_text(MJCF_CLASS_CAPSULE)
    report = run_check(make_bundle(work / "m3.xml", display_root=work), CheckOptions())
    [fit] = [d for d in report.diagnostics if d.code == "GC301"]
    assert fit.data["suggested"]["type"] == "cylinder"
    radius, length = fit.data["suggested"]["geometry"]["radius"], fit.data["suggested"]["geometry"]["length"]
    _, _, err = run(capsys, "fix", "--unsafe-fixes", "--select", "GC301", "m3.xml")
    assert err.splitlines()[0] == "geomcheck: fixed 1 finding in m3.xml"
    geom = line_with((work / "m3.xml").read_text(), "<geom size=")
    assert geom.startswith(f'<geom size="{radius:.6g} {length / 2 - radius:.6g}" quat="')
    assert "type=" not in geom
