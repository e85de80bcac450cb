"""Regression tests of the hostile inputs that once hung, crashed or leaked: DOCTYPE SYSTEM
identifiers naming special files, DTDs in the upload, finite numbers too large for geometry,
and xacro CPU bombs the first guards missed. Each is refused or reported at once."""

from __future__ import annotations

import json
import os
import threading
import time
import warnings
from pathlib import Path

import pytest

from geomcheck.cli import main
from geomcheck.errors import InputError, LimitExceeded
from geomcheck.load import load_description, make_bundle
from geomcheck.thresholds import LoadLimits

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def xacro_doc(body: str) -> str:
    return f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n  <link name="base"/>\n  {body}\n</robot>\n'


def check_json(path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, dict, str]:  # type: ignore[type-arg]
    status = main(["check", str(path), "--format", "json", "--no-sweep"])
    out, err = capsys.readouterr()
    return status, (json.loads(out) if out else {}), err


# --- DOCTYPE and DTDs ------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".urdf", ".urdf.xacro"])
def test_doctype_naming_a_fifo_does_not_block(tmp_path: Path, suffix: str) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    root = tmp_path / f"r{suffix}"
    root.write_text(
        f'<?xml version="1.0"?>\n<!DOCTYPE robot SYSTEM "{fifo}">\n<robot name="r" {NS}><link name="a"/></robot>\n'
    )
    result: list[object] = []
    worker = threading.Thread(
        target=lambda: result.append(load_description(make_bundle(root, display_root=tmp_path))), daemon=True
    )
    worker.start()
    worker.join(10)
    if worker.is_alive():  # unblock the parser so the test process can end
        with open(fifo, "wb"):
            pass
        pytest.fail("the DOCTYPE's SYSTEM identifier was opened: the parse blocked on a FIFO")
    assert [link.name for link in result[0].robot.links] == ["a"]  # type: ignore[attr-defined]


def test_doctype_system_file_is_no_existence_oracle(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    answers = []
    for target in ("/etc/hostname", "/nonexistent/file.dtd"):
        root = tmp_path / "r.urdf"
        root.write_text(
            f'<?xml version="1.0"?>\n<!DOCTYPE robot SYSTEM "{target}">\n<robot name="r"><link name="a"/></robot>\n'
        )
        status, report, err = check_json(root, capsys)
        answers.append((status, report["summary"], report["diagnostics"], err))
    assert answers[0] == answers[1]
    assert answers[0][0] == 0


def test_dtd_inside_the_upload_declares_no_entities(tmp_path: Path) -> None:
    (tmp_path / "ents.dtd").write_text('<!ENTITY name "from_the_dtd">\n')
    for name, text in (
        ("r.urdf", '<robot name="r"><link name="&name;"/><link name="b"/></robot>'),
        ("r.urdf.xacro", f'<robot name="r" {NS}><link name="x&name;"/><link name="b"/></robot>'),
    ):
        root = tmp_path / name
        root.write_text(f'<?xml version="1.0"?>\n<!DOCTYPE robot SYSTEM "ents.dtd">\n{text}\n')
        loaded = load_description(make_bundle(root, display_root=tmp_path, confined=True))
        assert all("from_the_dtd" not in link.name for link in loaded.robot.links)
        assert loaded.robot.links[-1].name == "b"


# --- numbers ---------------------------------------------------------------------------

HUGE = """<robot name="r">
  <link name="a">
    <visual><geometry><box size="1e308 1 1"/></geometry></visual>
    <collision><origin xyz="1e308 0 0"/><geometry><cylinder radius="0.1" length="1e308"/></geometry></collision>
    <inertial><mass value="1e308"/><inertia ixx="1e308" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="b"><visual><geometry><mesh filename="m.stl" scale="1e308 1 1"/></geometry></visual></link>
  <joint name="j" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1e308 0 0"/>
    <limit lower="-1e308" upper="1e308" effort="1" velocity="1"/></joint>
</robot>
"""


def test_huge_finite_numbers_are_gc126_findings_not_crashes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    root = tmp_path / "huge.urdf"
    root.write_text(HUGE)
    started = time.monotonic()
    status, report, err = check_json(root, capsys)
    assert time.monotonic() - started < 30
    assert (status, err) == (1, "")
    found = sorted((d["about"], d["data"]["value"]) for d in report["diagnostics"] if d["code"] == "GC126")
    assert found == [
        ("axis.xyz", 1e308),
        ("collision[0].cylinder.length", 1e308),
        ("collision[0].origin.xyz", 1e308),
        ("inertial.inertia.ixx", 1e308),
        ("inertial.mass.value", 1e308),
        ("limit.lower", -1e308),
        ("limit.upper", 1e308),
        ("visual[0].box.size", 1e308),
        ("visual[0].mesh.scale", 1e308),
    ]


TINY_ROBOT = """<robot name="r"><link name="base">
  <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  <visual><geometry>{geometry}</geometry></visual>
  <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
</link></robot>
"""


@pytest.mark.parametrize(
    ("geometry", "about", "value"),
    [
        ('<sphere radius="1e-20"/>', "visual[0].sphere.radius", 1e-20),  # was: LinAlgError, SVD did not converge
        ('<sphere radius="1e-100"/>', "visual[0].sphere.radius", 1e-100),  # was: StopIteration in the suggestion
        ('<sphere radius="1e-308"/>', "visual[0].sphere.radius", 1e-308),
        ('<sphere radius="5e-324"/>', "visual[0].sphere.radius", 5e-324),
        ('<box size="0.1 1e-30 0.1"/>', "visual[0].box.size", 1e-30),
        ('<cylinder radius="1e-200" length="0.1"/>', "visual[0].cylinder.radius", 1e-200),
        ('<mesh filename="m.stl" scale="1e-300 1 1"/>', "visual[0].mesh.scale", 1e-300),
    ],
)
def test_degenerate_sizes_are_gc126_findings_not_crashes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], geometry: str, about: str, value: float
) -> None:
    root = tmp_path / "tiny.urdf"
    root.write_text(TINY_ROBOT.format(geometry=geometry))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning from the tessellation or the SVDs either
        status, report, err = check_json(root, capsys)
    assert (status, err) == (1, "")
    found = [
        (d["about"], d["data"]["value"], d["data"]["limit"]) for d in report["diagnostics"] if d["code"] == "GC126"
    ]
    assert found == [(about, value, 1e-9)]


def test_a_zero_sphere_is_no_crash(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    root = tmp_path / "zero.urdf"
    root.write_text(TINY_ROBOT.format(geometry='<sphere radius="0"/>'))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        status, report, err = check_json(root, capsys)
    assert (status, err) == (0, "")  # GC505 is a warning: the dynamics are wrong, no consumer refuses it
    assert [(d["code"], d["severity"]) for d in report["diagnostics"]] == [("GC505", "warning")]  # not the visual


def test_numbers_within_the_limits_are_kept(tmp_path: Path) -> None:
    root = tmp_path / "r.urdf"
    root.write_text(
        '<robot name="r"><link name="a"><visual><geometry><box size="99999 1 1"/></geometry></visual></link></robot>'
    )
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    assert not [d for d in loaded.diagnostics if d.code == "GC126"]
    assert loaded.robot.links[0].visuals[0].geometry.size == (99999.0, 1.0, 1.0)  # type: ignore[union-attr]


# --- xacro work budget -----------------------------------------------------------------


def doubling_blocks(levels: int) -> str:
    blocks = ['<xacro:property name="p0"><link name="x"/></xacro:property>']
    blocks += [
        f'<xacro:property name="p{i}"><xacro:insert_block name="p{i - 1}"/><xacro:insert_block name="p{i - 1}"/>'
        "</xacro:property>"
        for i in range(1, levels + 1)
    ]
    return "".join(blocks) + f'<xacro:insert_block name="p{levels}"/>'


@pytest.mark.parametrize(
    ("body", "fragment"),
    [
        ('<link name="${10**10**10}"/>', "10**10000000000 is too large"),
        ('<link name="$(eval 10**10**10)"/>', "10**10000000000 is too large"),
        ("<link name=\"${'x' * 10**10}\"/>", "sequence of 10000000000 items"),
        ('<link name="${math.factorial(10**6)}"/>', "factorial(1000000) is too large"),
        ('<link name="${factorial(10**6)}"/>', "factorial(1000000) is too large"),
        ('<link name="${math.comb(10**7, 5*10**6)}"/>', "comb/perm(10000000, 5000000) is too large"),
        ('<link name="${math.prod(python.range(1, 10**6))}"/>', "work budget"),
        ('<link name="${math.prod(python.range(1, 10**5))}"/>', "too large integer"),
        (
            '<link name="${python.sum(i*j for i in python.range(10**6) for j in python.range(10**6))}"/>',
            "work budget",
        ),
        ('<link name="${len([i for i in python.range(10**6) for j in python.range(10)])}"/>', "work budget"),
        (doubling_blocks(40), "max_sibling_work"),
    ],
)
@pytest.mark.parametrize("confined", [True, False], ids=["upload", "trusted"])
def test_xacro_cpu_bombs_are_refused_at_once(load, body: str, fragment: str, confined: bool) -> None:  # type: ignore[no-untyped-def]
    """Trusted descriptions too: ``${10**10**10}`` in a local or CI run once ran for hours (the
    description fuzzer's first finding), and a check must end within seconds whatever the input."""
    started = time.monotonic()
    with pytest.raises(LimitExceeded) as info:
        load(xacro_doc(body), "r.urdf.xacro", confined=confined)
    assert time.monotonic() - started < 10
    assert fragment in str(info.value)
    assert info.value.diagnostic is not None and info.value.diagnostic.code == "GC102"


def doubling_properties(levels: int, add: bool) -> str:
    """``p{i}`` is ``p{i-1}`` twice, by text substitution (``${p}${p}``) or by ``+``."""
    props = ['<xacro:property name="p0" value="ab"/>']
    for i in range(1, levels + 1):
        value = f"${{p{i - 1}+p{i - 1}}}" if add else f"${{p{i - 1}}}${{p{i - 1}}}"
        props.append(f'<xacro:property name="p{i}" value="{value}"/>')
    return "".join(props) + f'<link name="l${{p{levels}}}"/>'


@pytest.mark.parametrize(
    ("body", "fragment", "confined"),
    [
        ('<link name="l${max(range(10**18))}"/>', "range of 1000000000000000000 items", False),  # ran until killed
        (doubling_properties(40, add=False), "beyond max_expanded_bytes", False),  # ran until killed
        (doubling_properties(40, add=True), "builds a sequence of", False),
        ("<link name=\"l${'a'.center(10**9)}\"/>", "pads a value to 1000000000", False),  # 43 s, 3 GB
        ("<link name=\"l${'%999999999d' % 1}\"/>", "pads a value to 999999999", True),  # 8 s, 1 GB in uploads
        ("<link name=\"l${'%999999999d' % 1}\"/>", "pads a value to 999999999", False),
        ("<link name=\"l${'%*d' % (10**9, 1)}\"/>", "pads a value to 1000000000", True),
        ("<link name=\"l$(eval '%999999999d' % 1)\"/>", "pads a value to 999999999", False),
        ("<link name=\"l${','.join(['a' * 10**6] * 1000)}\"/>", "joins 1000000999 characters", True),
        ("<link name=\"l${('a' * 10**7).replace('a', 'aaaaaaaaaa')}\"/>", "pads a value to 100000000", False),
    ],
)
def test_every_expression_is_bounded_in_time_and_memory(  # type: ignore[no-untyped-def]
    load, body: str, fragment: str, confined: bool
) -> None:
    """The work budget bounds trusted runs as documented: C code such as ``str.center`` or
    ``max`` over a range cannot be interrupted, so what it would build is refused before."""
    import resource

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # [KiB]
    started = time.monotonic()
    with pytest.raises(LimitExceeded) as info:
        load(xacro_doc(body), "r.urdf.xacro", confined=confined)
    assert time.monotonic() - started < 15
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - peak < 400 * 1024
    assert fragment in str(info.value)


@pytest.mark.parametrize(
    "expression",
    [
        "f'{1:999999999}'",
        "'{:999999999}'.format(1)",
        "format(1, '999999999')",
        "str.center('a', 10**9)",
        "bytes(10**10)",
    ],
)
def test_padding_in_any_spelling_is_refused_before_it_runs(expression: str) -> None:
    """Spellings xacro's lexer cannot carry inside ``${}`` (braces), or only ``$(eval)`` with
    Python's builtins can: the evaluator refuses them all the same."""
    import builtins

    from geomcheck.load.xacro_eval import GUARD_NAME, compile_budgeted, make_guard

    scope = {"format": builtins.format, "str": str, "bytes": bytes}
    with pytest.raises(LimitExceeded, match="pads a value to"):
        eval(compile_budgeted(expression), {GUARD_NAME: make_guard(64 << 20), "__builtins__": {}}, scope)


def test_element_budget_stops_macro_free_growth(load) -> None:  # type: ignore[no-untyped-def]
    limits = LoadLimits(max_xacro_elements=500)
    with pytest.raises(LimitExceeded, match="more than 500 elements"):
        load(xacro_doc(doubling_blocks(10)), "r.urdf.xacro", limits=limits)


def test_budgets_leave_ordinary_expressions_alone(load) -> None:  # type: ignore[no-untyped-def]
    body = (
        '<xacro:property name="n" value="${python.sum(i for i in python.range(10))}"/><link name="a${n}"/>'
        '<link name="b${math.factorial(5)}_${math.comb(5, 2)}_${math.prod([2, 3])}"/>'
        '<link name="c${max(1, *[2, 3])}"/>'
    )
    loaded = load(xacro_doc(body), "r.urdf.xacro", confined=True)
    assert [link.name for link in loaded.robot.links] == ["base", "a45", "b120_10_6", "c3"]
    more = '<link name="d${\'7\'.zfill(3)}"/><link name="e$(eval 2**3)"/>'  # .zfill is refused in uploads
    trusted = load(xacro_doc(body + more), "r.urdf.xacro")
    assert [link.name for link in trusted.robot.links] == ["base", "a45", "b120_10_6", "c3", "d007", "e8"]


def test_trusted_expressions_keep_xacros_rules(load) -> None:  # type: ignore[no-untyped-def]
    """The work budget adds no restriction of its own to trusted descriptions, and removes none of xacro's."""
    with pytest.raises(InputError, match="Use of invalid name"):
        load(xacro_doc('<link name="${(1).__class__}"/>'), "r.urdf.xacro")
    with pytest.raises(InputError, match="double underscore"):
        load(xacro_doc('<link name="$(eval 1 .__class__)"/>'), "r.urdf.xacro")


# --- meshes ----------------------------------------------------------------------------

MESH_URDF = """<robot name="m"><link name="a">
  <visual><geometry><mesh filename="part.stl"{scale}/></geometry></visual>
  <collision><geometry><mesh filename="part.stl"{scale}/></geometry></collision>
  <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
</link></robot>
"""


def ascii_stl(*corners: tuple[float, float, float]) -> str:
    points = "".join(f"  vertex {x!r} {y!r} {z!r}\n" for x, y, z in corners)
    return f"solid s\nfacet normal 0 0 0\n outer loop\n{points} endloop\nendfacet\nendsolid s\n"


def check_mesh(tmp_path: Path, stl: str, scale: str, capsys: pytest.CaptureFixture[str]) -> list[tuple[str, str]]:
    """The GC2xx findings of one mesh through the CLI, with every warning an error."""
    (tmp_path / "part.stl").write_text(stl)
    (tmp_path / "r.urdf").write_text(MESH_URDF.format(scale=scale))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        status, report, err = check_json(tmp_path / "r.urdf", capsys)
    assert (status, err) == (1, "")
    return [(d["code"], d["message"]) for d in report["diagnostics"] if d["code"].startswith("GC2")]


def test_mesh_coordinates_too_large_for_geometry_are_gc207(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """An ASCII STL corner at 1e308 m overflowed the vertex welding (``RuntimeWarning: overflow``,
    an internal error when warnings are errors): found by the mesh fuzzer."""
    stl = ascii_stl((-0.85, 1e30, 1e308), (-1e308, 0.0, -0.27), (1e-30, 0.0, 1e30))
    message = "part.stl has vertex coordinates of 1e+308 m (scale applied), beyond the 100000 m any robot"
    found = check_mesh(tmp_path, stl, "", capsys)
    assert [code for code, _ in found] == ["GC207", "GC207"]  # visual and collision
    assert all(message in text for _, text in found)


def test_a_scale_takes_a_mesh_beyond_the_range(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    stl = ascii_stl((0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (0.0, 2.0, 0.0))
    found = check_mesh(tmp_path, stl, ' scale="1e5 1e5 1e5"', capsys)
    assert [code for code, _ in found] == ["GC207", "GC207"]
    assert "vertex coordinates of 2e+05 m (scale applied)" in found[0][1]


def test_infinite_corner_under_a_zero_scale_is_gc207(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """inf times a zero scale factor: ``RuntimeWarning: invalid value encountered in multiply``."""
    stl = ascii_stl((0.0, 0.0, 0.0), (float("inf"), 0.0, 0.0), (0.0, 1.0, 0.0))
    found = check_mesh(tmp_path, stl, ' scale="0 0 0"', capsys)
    assert [code for code, _ in found] == ["GC207", "GC207"]
    assert "non-finite (NaN or infinite) vertex coordinates" in found[0][1]


def test_a_mesh_a_trillionth_of_a_metre_across_is_gc207(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A tetrahedron 1e-13 m across, at scale 0.001: the inertia bound of its link is so small that
    the ratio to it overflowed (``RuntimeWarning: overflow encountered in divide``)."""
    corners = [(2.5e-171, -3e-153, 0.0), (1.4e-13, -3.8e-15, 0.0), (1.5e-89, 8.1e-14, 0.0), (-2.9e-14, 1e-18, 0.0)]
    obj = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in corners) + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
    (tmp_path / "part.obj").write_text(obj)
    (tmp_path / "r.urdf").write_text(
        MESH_URDF.format(scale=' scale="0.001 0.001 0.001"').replace("part.stl", "part.obj")
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        status, report, err = check_json(tmp_path / "r.urdf", capsys)
    assert (status, err) == (1, "")
    assert sorted(d["code"] for d in report["diagnostics"]) == ["GC207", "GC207", "GC505"]


# --- no server paths in reports --------------------------------------------------------------------


def test_confined_reports_hold_no_folder_of_the_machine(tmp_path: Path) -> None:
    """``$(find pkg)``, ``$(cwd)``, ``xacro.abs_filename()`` and refused or failed mesh reads
    gave the server's folders in link names, mesh filenames and GC203 messages."""
    from geomcheck.options import CheckOptions
    from geomcheck.pipeline import run_check
    from geomcheck.report import render

    up = tmp_path / "upload"
    (up / "robot").mkdir(parents=True)
    (up / "arm" / "meshes" / "folder.stl").mkdir(parents=True)
    (up / "arm" / "package.xml").write_text("<package><name>arm</name></package>")
    (up / "arm" / "meshes" / "part.stl").write_text(ascii_stl((0, 0, 0), (0.1, 0, 0), (0, 0.1, 0)))
    body = (
        '<link name="cwd_$(cwd)"/><link name="abs_${xacro.abs_filename(\'x\')}"/>'
        '<link name="find_$(find arm)"><visual><geometry><mesh filename="$(find arm)/meshes/part.stl"/></geometry>'
        '</visual><collision><geometry><mesh filename="$(find arm)/meshes/folder.stl"/></geometry></collision></link>'
        '<link name="out"><visual><geometry><mesh filename="../../outside.stl"/></geometry></visual></link>'
    )
    (up / "robot" / "r.urdf.xacro").write_text(xacro_doc(body))
    bundle = make_bundle(up / "robot" / "r.urdf.xacro", search=[up], display_root=up, confined=True)
    report = run_check(bundle, CheckOptions(sweep=False))
    text = render(report, "json")
    assert str(tmp_path) not in text
    links = [link.name for link in load_description(bundle).robot.links]
    assert links == ["base", "cwd_..", "abs_./x", "find_../arm", "out"]  # relative to the root file's folder
    messages = {d.message for d in report.diagnostics if d.code in ("GC201", "GC203")}
    assert "visual[0] of link 'out': access outside the uploaded bundle refused: ../outside.stl" in messages
    assert report.robot.meshes_loaded == 1  # the mesh named through $(find arm) is found and read
    # trusted runs keep the absolute folders: they resolve wherever the report is read
    trusted = load_description(make_bundle(up / "robot" / "r.urdf.xacro", search=[up], display_root=up))
    assert [link.name for link in trusted.robot.links][3] == f"find_{up / 'arm'}"


# --- report size -----------------------------------------------------------------------


def test_many_unjoined_links_make_a_report_of_linear_size(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    links = "".join(f'<link name="l{i}"/>' for i in range(1200))  # one line, as a minified file
    root = tmp_path / "unjoined.urdf"
    root.write_text(f'<robot name="r">{links}</robot>\n')
    status = main(["check", str(root), "--format", "json", "--no-sweep"])
    out, err = capsys.readouterr()
    assert (status, err) == (1, "")
    report = json.loads(out)
    found = [d for d in report["diagnostics"] if d["code"] == "GC115"]
    assert len(found) == 500
    assert {
        "check": "findings",
        "subject": "GC115",
        "reason": "699 more GC115 findings left out (at most 500 per rule)",
    } in (report["skipped"])
    assert found[0]["message"].endswith("(1200 root links: l0, l1, l2, l3, l4, l5, l6, l7, l8, l9 and 1190 more)")
    assert found[0]["data"]["root_count"] == 1200 and len(found[0]["data"]["roots"]) == 10
    assert max(len(text) for d in found for _, text in d["excerpt"]) <= 246
    # about 875 bytes a link: 485 of findings, 155 of the links section, 105 of the model section
    assert len(out) < 1_200_000
