"""xacro expansion in process: output, arguments, packages, source lines, GC102/GC104, isolation."""

from __future__ import annotations

import shutil
import subprocess
import threading
from pathlib import Path

import pytest
import xacro

from geomcheck.errors import InputError

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'

MODERN = f"""<?xml version="1.0"?>
<robot name="arm" {NS}>
  <xacro:arg name="width" default="0.5"/>
  <xacro:arg name="two_legs" default="true"/>
  <xacro:property name="radius" value="${{0.1 * 2}}"/>
  <xacro:property name="length" value="${{radius * 3}}"/>
  <xacro:macro name="leg" params="prefix *origin">
    <link name="${{prefix}}_link">
      <visual><geometry><cylinder radius="${{radius}}" length="$(arg width)"/></geometry></visual>
    </link>
    <joint name="${{prefix}}_joint" type="revolute">
      <xacro:insert_block name="origin"/>
      <parent link="base"/>
      <child link="${{prefix}}_link"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/>
    </joint>
  </xacro:macro>
  <link name="base"/>
  <!-- this comment goes away with the macro call -->
  <xacro:leg prefix="a"><origin xyz="0 0 ${{length}}"/></xacro:leg>
  <xacro:if value="$(arg two_legs)">
    <xacro:leg prefix="b"><origin xyz="0 1 0"/></xacro:leg>
  </xacro:if>
</robot>
"""


def line_of(text: str, needle: str) -> int:
    return text.count("\n", 0, text.index(needle)) + 1


def test_modern_xacro_equals_the_xacro_command(load, tmp_path: Path) -> None:
    loaded = load(MODERN, "arm.urdf.xacro")
    command = shutil.which("xacro")
    if command is None:
        pytest.skip("the xacro command is not installed")
    printed = subprocess.run([command, "arm.urdf.xacro"], cwd=tmp_path, capture_output=True, text=True, check=True)
    assert loaded.document.text == printed.stdout
    assert loaded.document.is_xacro
    assert loaded.document.sources == {"arm.urdf.xacro": MODERN}


def test_macro_elements_point_at_the_macro_body_lines(load) -> None:
    loaded = load(MODERN, "arm.urdf.xacro")
    robot = loaded.robot
    assert [link.name for link in robot.links] == ["base", "a_link", "b_link"]
    a_link = robot.link_map["a_link"]
    assert a_link.location is not None
    assert (a_link.location.file, a_link.location.line) == ("arm.urdf.xacro", line_of(MODERN, '<link name="${prefix}'))
    assert a_link.visuals[0].geometry.radius == pytest.approx(0.2)  # type: ignore[union-attr]
    assert a_link.visuals[0].geometry.length == pytest.approx(0.5)  # type: ignore[union-attr]
    joint = robot.joint_map["a_joint"]
    assert joint.origin.xyz == pytest.approx((0, 0, 0.6))
    # the expanded line is the line of the element in the expanded text
    expanded = loaded.document.text.splitlines()
    assert joint.location is not None and joint.location.expanded_line is not None
    assert expanded[joint.location.expanded_line - 1].strip().startswith('<joint name="a_joint"')
    assert loaded.diagnostics == ()


def test_args_override_defaults(load) -> None:
    loaded = load(MODERN, "arm.urdf.xacro", args={"two_legs": "false"})
    assert [link.name for link in loaded.robot.links] == ["base", "a_link"]


def test_find_and_includes_resolve_through_the_package_map(load, tmp_path: Path) -> None:
    part = f'<?xml version="1.0"?>\n<robot {NS}>\n  <link name="${{name}}"/>\n</robot>\n'
    root = (
        f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n'
        '  <xacro:property name="name" value="from_include"/>\n'
        '  <xacro:include filename="$(find parts)/urdf/part.xacro"/>\n</robot>\n'
    )
    loaded = load(root, "top.xacro", files={"pkg/urdf/part.xacro": part}, packages={"parts": tmp_path / "pkg"})
    link = loaded.robot.links[0]
    assert link.name == "from_include"
    assert link.location is not None and (link.location.file, link.location.line) == ("pkg/urdf/part.xacro", 3)
    assert list(loaded.document.sources) == ["top.xacro", "pkg/urdf/part.xacro"]


def test_yaml_is_loaded_and_recorded(load) -> None:
    root = (
        f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n'
        '  <xacro:property name="p" value="${xacro.load_yaml(\'params.yaml\')}"/>\n'
        '  <link name="${p.arm.name}"/>\n</robot>\n'
    )
    loaded = load(root, "r.xacro", files={"params.yaml": "arm:\n  name: upper\n"})
    assert loaded.robot.links[0].name == "upper"
    assert "params.yaml" in loaded.document.sources


@pytest.mark.parametrize(
    ("body", "needle", "fragment"),
    [
        (
            '<link name="a"><visual><geometry><sphere radius="${radius}"/></geometry></visual></link>',
            "${radius}",
            "name 'radius' is not defined when evaluating expression 'radius'",
        ),
        ('<xacro:wheel side="l"/>', "<xacro:wheel", "unknown macro name: xacro:wheel"),
        ('<link name="$(arg prefix)base"/>', "$(arg prefix)", "Undefined substitution argument prefix"),
        ('<xacro:include filename="missing_part.xacro"/>', 'filename="missing', "No such file or directory"),
        ('<xacro:include filename="$(find nopkg)/x.xacro"/>', "$(find nopkg)", "package 'nopkg' not found"),
    ],
)
def test_xacro_errors_are_gc102_with_the_line(load, body: str, needle: str, fragment: str) -> None:
    text = f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n  <link name="base"/>\n  {body}\n</robot>\n'
    with pytest.raises(InputError) as info:
        load(text, "bad.xacro")
    diagnostic = info.value.diagnostic
    assert diagnostic is not None
    assert (diagnostic.code, diagnostic.name, diagnostic.severity.value) == ("GC102", "xacro-error", "error")
    assert fragment in diagnostic.message
    assert diagnostic.location is not None
    assert (diagnostic.location.file, diagnostic.location.line) == ("bad.xacro", 4)
    column = text.splitlines()[3].index(needle) + 1
    assert diagnostic.location.column == column
    assert str(info.value) == f"bad.xacro:4:{column}: GC102 xacro-error: {diagnostic.message}"


def test_error_inside_a_macro_points_into_the_macro_file(load) -> None:
    macros = (
        f'<?xml version="1.0"?>\n<robot {NS}>\n'
        '  <xacro:macro name="m">\n    <link name="${nope}"/>\n  </xacro:macro>\n</robot>\n'
    )
    root = (
        f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n'
        '  <xacro:include filename="macros.xacro"/>\n  <xacro:m/>\n</robot>\n'
    )
    with pytest.raises(InputError) as info:
        load(root, "r.xacro", files={"macros.xacro": macros})
    diagnostic = info.value.diagnostic
    assert diagnostic is not None and diagnostic.location is not None
    assert (diagnostic.location.file, diagnostic.location.line) == ("macros.xacro", 4)
    assert diagnostic.message.endswith("(in macro m)")


def test_bad_condition_points_at_the_condition(load) -> None:
    text = MODERN.replace('default="true"', 'default="maybe"')
    with pytest.raises(InputError) as info:
        load(text, "arm.urdf.xacro")
    assert str(info.value).startswith(f"arm.urdf.xacro:{line_of(text, '<xacro:if')}:")
    assert 'Xacro conditional "$(arg two_legs)" evaluated to "maybe"' in str(info.value)


def test_malformed_include_is_gc101_in_the_included_file(load) -> None:
    root = f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n  <xacro:include filename="part.xacro"/>\n</robot>\n'
    with pytest.raises(InputError) as info:
        load(root, "r.xacro", files={"part.xacro": "<robot>\n  <link>\n</robot>\n"})
    assert info.value.diagnostic is not None and info.value.diagnostic.code == "GC101"
    assert str(info.value).startswith("part.xacro:3:")


def test_xacro_warnings_become_gc104(load) -> None:
    root = (
        f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n'
        '  <xacro:property name="w" value="1" colour="red"/>\n  <link name="base"/>\n</robot>\n'
    )
    loaded = load(root, "r.xacro")
    warnings = [d for d in loaded.diagnostics if d.code == "GC104"]
    assert len(warnings) == 1
    assert warnings[0].name == "xacro-warning"
    assert "unknown attribute(s): colour" in warnings[0].message
    assert warnings[0].location is not None and warnings[0].location.file == "r.xacro"
    clean = load(root.replace(' colour="red"', ""), "r.xacro")
    assert not [d for d in clean.diagnostics if d.code == "GC104"]


def test_one_call_does_not_leak_into_the_next(load) -> None:
    saved = (xacro.parse, xacro.handle_macro_call, xacro.safe_eval, xacro._global_symbols)
    first = (
        f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n  <xacro:arg name="b" default="2"/>\n'
        '  <link name="${math.clear() or python.dict.clear(python) or 1}"/>\n</robot>\n'
    )
    load(first, "first.xacro", args={"a": "1"})
    second = f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n  <link name="x${{math.pi > 3}}"/>\n</robot>\n'
    assert load(second, "second.xacro").robot.links[0].name == "xTrue"
    with pytest.raises(InputError, match="Undefined substitution argument b"):
        load(f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n  <link name="$(arg b)"/>\n</robot>\n', "third.xacro")
    assert (xacro.parse, xacro.handle_macro_call, xacro.safe_eval, xacro._global_symbols) == saved
    assert xacro.substitution_args_context in ({}, {"arg": {}})


def test_concurrent_expansions_are_serialised(load) -> None:
    results: list[str] = []
    errors: list[BaseException] = []

    def run(n: int) -> None:
        try:
            loaded = load(
                MODERN.replace('name="arm"', f'name="arm{n}"'), f"arm{n}.xacro", args={"two_legs": str(n % 2)}
            )
            results.append(f"{loaded.robot.name}:{len(loaded.robot.links)}")
        except BaseException as err:  # pragma: no cover - reported below
            errors.append(err)

    threads = [threading.Thread(target=run, args=(n,)) for n in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors
    assert sorted(results) == ["arm0:2", "arm1:3", "arm2:2", "arm3:3"]
