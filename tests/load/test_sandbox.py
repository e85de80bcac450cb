"""Confined bundles (uploads): files, substitutions and expressions stay inside the sandbox;
limits stop recursion and expansion bombs quickly."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from geomcheck.errors import InputError, LimitExceeded, SandboxViolation
from geomcheck.load import LoadedMesh, MeshProblem, MeshStore, make_bundle
from geomcheck.model import Mesh
from geomcheck.thresholds import LoadLimits

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def doc(body: str) -> str:
    return f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n  <link name="base"/>\n  {body}\n</robot>\n'


@pytest.mark.parametrize(
    ("body", "error", "fragment"),
    [
        ('<xacro:include filename="/etc/hostname"/>', SandboxViolation, "refused: /etc/hostname"),
        ('<xacro:include filename="../../outside.xacro"/>', SandboxViolation, "outside.xacro"),
        ('<link name="$(env HOME)"/>', SandboxViolation, "$(env HOME) is refused"),
        ('<link name="$(eval open)"/>', InputError, "name 'open' is not defined"),
        ('<link name="${(1).__class__}"/>', SandboxViolation, "may not contain '__'"),
        ("<link name=\"${'x'.format}\"/>", SandboxViolation, "attribute .format"),
        ('<link name="${(x for x in (1,)).gi_frame}"/>', SandboxViolation, "attribute .gi_frame"),
        ('<link name="${python.type(1)}"/>', InputError, "name 'type' is not defined"),
        ('<link name="${10**10**10}"/>', LimitExceeded, "is too large"),
        ("<link name=\"${'x' * 10**9}\"/>", LimitExceeded, "sequence of 1000000000 items"),
        ('<link name="${len(python.list(python.range(10**9)))}"/>', LimitExceeded, "range of 1000000000 items"),
        (
            '<xacro:property name="y" value="${xacro.load_yaml(\'/etc/hostname\')}"/><link name="${y}"/>',
            SandboxViolation,
            "refused: /etc/hostname",
        ),
    ],
)
def test_confined_refusals(load, body: str, error: type[Exception], fragment: str) -> None:
    started = time.perf_counter()
    with pytest.raises(error) as info:
        load(doc(body), "up/r.xacro", confined=True)
    assert time.perf_counter() - started < 2.0
    assert fragment in str(info.value)
    diagnostic = getattr(info.value, "diagnostic", None)
    assert diagnostic is not None and diagnostic.code == "GC102"
    assert diagnostic.location.file == "up/r.xacro" and diagnostic.location.line == 4


def test_confined_expressions_that_are_harmless_still_work(load) -> None:
    body = (
        '<xacro:property name="w" value="${2**8 * 0.5}"/><link name="a${w}"/>'
        '<link name="${\'ab\' * 2}"/><link name="$(eval 2**3)"/><link name="${math.pi > 3}"/>'
    )
    loaded = load(doc(body), "r.xacro", confined=True)
    assert [link.name for link in loaded.robot.links] == ["base", "a128.0", "abab", "8", "True"]


def test_confined_optenv_takes_its_default_and_reads_no_variable(load, monkeypatch: pytest.MonkeyPatch) -> None:
    """What a fresh machine expands: ``$(optenv NAME default)`` the default, ``$(optenv NAME)``
    nothing, whatever the server's environment holds."""
    monkeypatch.setenv("GEOMCHECK_TEST_PREFIX", "server")
    body = '<link name="$(optenv GEOMCHECK_TEST_PREFIX left)_arm"/><link name="x$(optenv GEOMCHECK_TEST_PREFIX)y"/>'
    loaded = load(doc(body), "r.xacro", confined=True)
    assert [link.name for link in loaded.robot.links] == ["base", "left_arm", "xy"]


def test_given_values_win_in_every_mode(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A value the user gives (``--env``, the service's ``env`` option) is what $(env) and
    $(optenv) read, confined or not; the environment's own value is never preferred."""
    from geomcheck.load import load_description

    monkeypatch.setenv("GEOMCHECK_TEST_PREFIX", "server")
    root = tmp_path / "r.xacro"
    body = '<link name="$(env GEOMCHECK_TEST_PREFIX)_a"/><link name="$(optenv GEOMCHECK_TEST_PREFIX x)_b"/>'
    root.write_text(doc(body))
    for confined in (False, True):
        bundle = make_bundle(root, display_root=tmp_path, confined=confined, env={"GEOMCHECK_TEST_PREFIX": "given"})
        assert [link.name for link in load_description(bundle).robot.links] == ["base", "given_a", "given_b"]


def test_env_refusal_says_how_to_give_the_value(tmp_path: Path) -> None:
    from geomcheck.load import load_description

    root = tmp_path / "r.xacro"
    root.write_text(doc('<link name="$(env ROBOT_NAME)"/>'))
    with pytest.raises(SandboxViolation, match=r"give its value with --env ROBOT_NAME=VALUE"):
        load_description(make_bundle(root, display_root=tmp_path, confined=True))
    with pytest.raises(SandboxViolation, match=r"give its value with the env option \(env=ROBOT_NAME=VALUE\)"):
        load_description(make_bundle(root, display_root=tmp_path, confined=True, uploaded=True))


def test_env_works_unconfined(load, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GEOMCHECK_TEST_PREFIX", "left")
    loaded = load(doc('<link name="$(env GEOMCHECK_TEST_PREFIX)_arm"/>'), "r.xacro")
    assert loaded.robot.links[1].name == "left_arm"


def test_symlink_out_of_the_bundle_is_refused(load, tmp_path: Path) -> None:
    secret = tmp_path / "secret.xacro"
    secret.write_text(doc(""))
    (tmp_path / "up").mkdir()
    os.symlink(secret, tmp_path / "up" / "link.xacro")
    root = tmp_path / "up" / "r.xacro"
    root.write_text(doc('<xacro:include filename="link.xacro"/>'))
    bundle = make_bundle(root, display_root=tmp_path / "up", confined=True)
    from geomcheck.load import load_description

    with pytest.raises(SandboxViolation, match=r"link\.xacro"):
        load_description(bundle)


def test_root_file_outside_the_upload_is_refused(tmp_path: Path) -> None:
    root = tmp_path / "r.urdf"
    root.write_text('<robot name="r"><link name="a"/></robot>')
    (tmp_path / "up").mkdir()
    from geomcheck.load import load_description

    with pytest.raises(SandboxViolation):
        load_description(make_bundle(root, display_root=tmp_path / "up", confined=True))


def test_mesh_outside_the_bundle_is_a_problem_not_a_read(tmp_path: Path) -> None:
    (tmp_path / "up").mkdir()
    root = tmp_path / "up" / "r.urdf"
    root.write_text('<robot name="r"/>')
    store = MeshStore(make_bundle(root, display_root=tmp_path / "up", confined=True))
    result = store.get(Mesh("/etc/hostname"))
    assert isinstance(result, MeshProblem) and "outside the uploaded bundle" in result.message
    assert store.files_read == 0


def test_build_product_source_outside_the_bundle_is_not_named(tmp_path: Path) -> None:
    import trimesh

    up = tmp_path / "convex"  # an upload whose own folder is named like a build-product folder
    (up / "meshes" / "convex").mkdir(parents=True)
    root = up / "r.urdf"
    root.write_text('<robot name="r"/>')
    box = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    box.export(tmp_path / "secret.stl")  # beside the upload: its existence must not leak
    box.export(up / "meshes" / "base.stl")
    store = MeshStore(make_bundle(root, display_root=up, confined=True))
    outside = store.get(Mesh("secret_convex.stlb"))
    assert isinstance(outside, MeshProblem) and outside.generated_from is None
    assert outside.message == "mesh file not found: secret_convex.stlb"
    inside = store.get(Mesh("meshes/convex/base_convex.stlb"))  # stands in for the build product
    assert isinstance(inside, LoadedMesh) and inside.path == "meshes/base.stl"
    assert inside.stands_for == "meshes/convex/base_convex.stlb"


def test_recursive_macro_is_stopped_quickly(load) -> None:
    body = '<xacro:macro name="loop" params="n"><xacro:loop n="${n+1}"/></xacro:macro><xacro:loop n="0"/>'
    started = time.perf_counter()
    with pytest.raises(LimitExceeded) as info:
        load(doc(body), "r.xacro")
    assert time.perf_counter() - started < 2.0
    assert "macro 'loop' nests deeper than the limit of 100 levels" in str(info.value)
    assert info.value.diagnostic is not None and info.value.diagnostic.location.line == 4


def test_exponential_macros_are_stopped(load) -> None:
    macros = ['<xacro:macro name="m0"><link name="x"/></xacro:macro>']
    macros += [f'<xacro:macro name="m{i}"><xacro:m{i - 1}/><xacro:m{i - 1}/></xacro:macro>' for i in range(1, 30)]
    started = time.perf_counter()
    with pytest.raises(LimitExceeded, match="more than 500 macro calls"):
        load(doc("".join(macros) + "<xacro:m29/>"), "r.xacro", limits=LoadLimits(max_macro_calls=500))
    assert time.perf_counter() - started < 2.0


def test_recursive_include_is_stopped(load) -> None:
    with pytest.raises(LimitExceeded, match="includes nest deeper than the limit of 5 levels"):
        load(doc('<xacro:include filename="r.xacro"/>'), "r.xacro", limits=LoadLimits(max_include_depth=5))


def test_expanded_size_limit(load) -> None:
    body = '<xacro:macro name="m" params="i"><link name="l${i}"/></xacro:macro>' + "".join(
        f'<xacro:m i="{i}"/>' for i in range(200)
    )
    with pytest.raises(LimitExceeded, match=r"xacro output of \d+ bytes exceeds the limit of 2000 bytes"):
        load(doc(body), "r.xacro", limits=LoadLimits(max_expanded_bytes=2000))
