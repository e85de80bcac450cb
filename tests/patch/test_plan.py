"""Planning fixes against xacro sources: literal values, property definitions, expressions,
macro parameters, elements written once for several links, and conflicting fixes."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load import LoadedDescription, load_description, make_bundle
from geomcheck.model import SourceLocation
from geomcheck.patch.apply import fixed_sources
from geomcheck.patch.plan import plan_fixes

ROBOT = """<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <!-- sizes of the body -->
  <xacro:property name="box_x" value="0.10"/>
  <xacro:property name="shared_z" value="0.2"/>
  <xacro:property name="height" value="0.5"/>
  <link name="a">
    <collision>
      <origin xyz="0 0 ${height/2}"   rpy="0 0 0"/>
      <geometry><box size="${box_x} 0.2 ${shared_z}"/></geometry>
    </collision>
  </link>
  <link name="b">
    <collision>
      <geometry><box size="0.1 0.1 ${shared_z}"/></geometry>
    </collision>
  </link>
  <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
  <xacro:macro name="leg" params="side length">
    <link name="${side}_leg">
      <inertial>
        <mass value="1"/>
        <inertia ixx="1" ixy="0" ixz="0"
                 iyy="1" iyz="0" izz="1"/>
      </inertial>
      <collision>
        <geometry><cylinder radius="0.05" length="${length}"/></geometry>
      </collision>
    </link>
    <joint name="${side}_joint" type="fixed"><parent link="a"/><child link="${side}_leg"/></joint>
  </xacro:macro>
  <xacro:leg side="l" length="0.4"/>
  <xacro:leg side="r" length="0.4"/>
</robot>
"""
ROOT = "robot.urdf.xacro"


def line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


def at(needle: str) -> str:
    """``file:line`` of the first line of ``ROBOT`` holding ``needle``."""
    return f"{ROOT}:{line_of(ROBOT, needle)}"


@pytest.fixture
def loaded(tmp_path: Path) -> LoadedDescription:
    (tmp_path / ROOT).write_text(ROBOT)
    return load_description(make_bundle(tmp_path / ROOT, display_root=tmp_path))


def collision_of(loaded: LoadedDescription, link: str) -> SourceLocation:
    location = loaded.robot.link_map[link].collisions[0].location
    assert location is not None
    return location


def inertial_of(loaded: LoadedDescription, link: str) -> SourceLocation:
    inertial = loaded.robot.link_map[link].inertial
    assert inertial is not None and inertial.location is not None
    return inertial.location


def finding(code: str, link: str, about: str, location: SourceLocation, data: dict[str, Any]) -> Diagnostic:
    return Diagnostic(
        code, "rule", Severity.ERROR, "message", "help", link=link, about=about, location=location, data=data
    )


def fitted_box(size: list[float], xyz: list[float]) -> dict[str, Any]:
    return {
        "element": "box",
        "suggested": {"type": "box", "origin": {"xyz": xyz, "rpy": [0.0, 0.0, 0.0]}, "geometry": {"size": size}},
    }


def inertia(ixx: float) -> dict[str, Any]:
    return {"implied_inertia": {"ixx": ixx, "ixy": 0.0, "ixz": 0.0, "iyy": 0.5, "iyz": 0.0, "izz": 0.5}}


def test_literals_in_place_expressions_in_place_and_a_lone_property_at_its_definition(
    loaded: LoadedDescription,
) -> None:
    d = finding("GC301", "a", "collision[0]", collision_of(loaded, "a"), fitted_box([0.3, 0.25, 0.2], [0, 0, 0.3]))
    plan = plan_fixes(loaded, [d], unsafe=True)
    assert [p.reason for p in plan.fixes] == [""]
    after = fixed_sources(loaded.document.sources, plan.edits)[ROOT]
    expected = (
        ROBOT.replace('name="box_x" value="0.10"', 'name="box_x" value="0.3"')
        .replace('xyz="0 0 ${height/2}"', 'xyz="0 0 0.3"')
        .replace('size="${box_x} 0.2 ${shared_z}"', 'size="${box_x} 0.25 ${shared_z}"')
    )
    assert after == expected  # shared_z (0.2 already) and rpy untouched, spacing and comments kept


def test_a_property_used_elsewhere_is_refused_naming_both_places(loaded: LoadedDescription) -> None:
    d = finding("GC301", "a", "collision[0]", collision_of(loaded, "a"), fitted_box([0.1, 0.2, 0.4], [0, 0, 0.25]))
    plan = plan_fixes(loaded, [d], unsafe=True)
    (refused,) = plan.fixes
    definition, other_use = at('name="shared_z"'), at('size="0.1 0.1 ${shared_z}"')
    assert refused.reason == f"property shared_z (defined at {definition}) is also used at {other_use}"
    assert definition in refused.locations and other_use in refused.locations
    assert plan.edits == ()


def test_unsafe_fixes_need_the_flag(loaded: LoadedDescription) -> None:
    d = finding("GC301", "a", "collision[0]", collision_of(loaded, "a"), fitted_box([0.3, 0.25, 0.2], [0, 0, 0.3]))
    assert plan_fixes(loaded, [d], unsafe=False).fixes == ()


def test_an_element_written_once_in_a_macro_is_changed_when_every_link_agrees(loaded: LoadedDescription) -> None:
    both = [finding("GC505", f"{s}_leg", "inertia", inertial_of(loaded, f"{s}_leg"), inertia(0.25)) for s in "lr"]
    plan = plan_fixes(loaded, both, unsafe=True)
    assert [p.applicable for p in plan.fixes] == [True, True]
    after = fixed_sources(loaded.document.sources, plan.edits)[ROOT]
    assert 'inertia ixx="0.25" ixy="0" ixz="0"\n                 iyy="0.5" iyz="0" izz="0.5"/>' in after
    assert after.count('ixx="0.25"') == 1  # one macro body, changed once


def test_an_element_written_once_in_a_macro_is_refused_for_some_links_or_differing_fixes(
    loaded: LoadedDescription,
) -> None:
    line = at("<inertial>")
    left = finding("GC505", "l_leg", "inertia", inertial_of(loaded, "l_leg"), inertia(0.25))
    (one,) = plan_fixes(loaded, [left], unsafe=True).fixes
    assert (
        one.reason
        == f"the <inertial> at {line} is written once for 2 elements; this fix applies to 1 of them (link l_leg)"
    )
    right = finding("GC505", "r_leg", "inertia", inertial_of(loaded, "r_leg"), inertia(0.3))
    plan = plan_fixes(loaded, [left, right], unsafe=True)
    assert {p.reason for p in plan.fixes} == {
        f"the <inertial> at {line} is written once for 2 elements whose fixes differ (link l_leg, link r_leg)"
    }


def test_a_macro_parameter_is_refused_naming_the_macro(loaded: LoadedDescription) -> None:
    cylinder = {
        "element": "cylinder",
        "suggested": {
            "type": "cylinder",
            "origin": {"xyz": [0, 0, 0], "rpy": [0, 0, 0]},
            "geometry": {"radius": 0.05, "length": 0.5},
        },
    }
    both = [finding("GC302", f"{s}_leg", "collision[0]", collision_of(loaded, f"{s}_leg"), cylinder) for s in "lr"]
    plan = plan_fixes(loaded, both, unsafe=True)
    attribute, macro = at('length="${length}"'), at("<xacro:macro")
    assert {p.reason for p in plan.fixes} == {f"${{length}} at {attribute} is a parameter of the macro at {macro}"}
    assert plan.fixes[0].locations == (attribute, macro)


def test_a_value_from_an_argument_is_refused(tmp_path: Path) -> None:
    (tmp_path / ROOT).write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n  <xacro:arg name="w" default="0.1"/>\n'
        '  <link name="a"><collision><geometry><box size="$(arg w) 1 1"/></geometry></collision>\n'
        "  </link>\n</robot>\n"
    )
    loaded = load_description(make_bundle(tmp_path / ROOT, display_root=tmp_path))
    d = finding("GC302", "a", "collision[0]", collision_of(loaded, "a"), fitted_box([0.5, 1, 1], [0, 0, 0]))
    (refused,) = plan_fixes(loaded, [d], unsafe=True).fixes
    assert refused.reason == f"$(arg w) at {ROOT}:3 comes from a substitution (an argument): set it where it is given"


def test_fixes_that_want_different_text_at_one_place_conflict(tmp_path: Path) -> None:
    (tmp_path / "r.urdf").write_text(
        '<robot name="r">\n  <link name="a"><collision><origin xyz="0 0 0"/>'
        '<geometry><box size="1 1 1"/></geometry></collision>\n  </link>\n</robot>\n'
    )
    loaded = load_description(make_bundle(tmp_path / "r.urdf", display_root=tmp_path))
    where = collision_of(loaded, "a")
    first = finding("GC301", "a", "collision[0]", where, fitted_box([2, 2, 2], [0, 0, 0]))
    second = finding("GC302", "a", "collision[0]", where, fitted_box([3, 3, 3], [0, 0, 0]))
    plan = plan_fixes(loaded, [first, second], unsafe=True)
    assert [p.reason for p in plan.fixes] == ["", "conflicts with the fix of GC301 link a"]
    text = fixed_sources(loaded.document.sources, plan.edits)["r.urdf"]
    assert '<box size="2 2 2"/>' in text


def test_a_missing_origin_is_inserted_with_the_childrens_indentation(tmp_path: Path) -> None:
    source = (
        '<robot name="r">\n  <link name="a">\n    <collision>\n'
        '      <geometry><box size="1 1 1"/></geometry>\n    </collision>\n  </link>\n</robot>\n'
    )
    (tmp_path / "r.urdf").write_text(source)
    loaded = load_description(make_bundle(tmp_path / "r.urdf", display_root=tmp_path))
    d = finding("GC301", "a", "collision[0]", collision_of(loaded, "a"), fitted_box([1, 1, 2], [0, 0, 0.5]))
    plan = plan_fixes(loaded, [d], unsafe=True)
    assert fixed_sources(loaded.document.sources, plan.edits)["r.urdf"] == source.replace(
        "    <collision>\n", '    <collision>\n      <origin xyz="0 0 0.5"/>\n'
    ).replace('size="1 1 1"', 'size="1 1 2"')  # rpy keeps URDF's default: not written
    at_origin = finding("GC302", "a", "collision[0]", collision_of(loaded, "a"), fitted_box([1, 1, 0.5], [0, 0, 0]))
    plan = plan_fixes(loaded, [at_origin], unsafe=True)
    assert fixed_sources(loaded.document.sources, plan.edits)["r.urdf"] == source.replace(
        'size="1 1 1"', 'size="1 1 0.5"'
    )


def test_an_srdf_pair_takes_the_reason_the_matrix_finds(tmp_path: Path) -> None:
    (tmp_path / "r.urdf").write_text('<robot name="r">\n  <link name="a"/>\n  <link name="b"/>\n</robot>\n')
    srdf = (
        '<robot name="r">\n  <disable_collisions link1="a" link2="b" reason="Never" />\n'
        '  <disable_collisions link1="a" link2="c" reason="Never" />\n</robot>\n'
    )
    (tmp_path / "r.srdf").write_text(srdf)
    loaded = load_description(make_bundle(tmp_path / "r.urdf", display_root=tmp_path))
    d = Diagnostic(
        "GC414",
        "srdf-reason-mismatch",
        Severity.INFO,
        "message",
        "help",
        links=("a", "b"),
        location=SourceLocation("r.srdf", 2),
        data={"reason": "Never", "class": "adjacent"},
    )
    assert plan_fixes(loaded, [d], unsafe=False).fixes == ()
    plan = plan_fixes(loaded, [d], unsafe=True)
    assert [(p.fix.title, p.applicable) for p in plan.fixes] == [
        ("disable the pair as Adjacent, the class the collision matrix finds", True)
    ]
    assert fixed_sources(plan.sources, plan.edits) == {
        "r.srdf": srdf.replace('link2="b" reason="Never"', 'link2="b" reason="Adjacent"')
    }
