"""The collision matrix cache: same robot, meshes and settings give the stored matrix (equal
to a fresh one); any of them changed computes anew."""

from __future__ import annotations

import json
import shutil
from dataclasses import replace
from pathlib import Path

import pytest

from geomcheck.cache import Store, using_store
from geomcheck.checks.matrix import matrix_of
from geomcheck.cli import main
from geomcheck.load import load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.selfcollision.matrix import MatrixStats
from geomcheck.selfcollision.matrix_cache import NAMESPACE, decode_matrix, encode_matrix

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base"
OPTIONS = CheckOptions(matrix=True, sweep=False, samples=300, workers=1)


@pytest.fixture
def example(tmp_path: Path) -> Path:
    shutil.copytree(EXAMPLE, tmp_path / "pr2_base")
    return tmp_path / "pr2_base" / "robots" / "pr2_base.urdf.xacro"


def entries(store: Store) -> list[Path]:
    folder = store.root / NAMESPACE
    return sorted(p for p in folder.rglob("*") if p.is_file()) if folder.is_dir() else []


def matrix(root: Path, store: Store | None, options: CheckOptions = OPTIONS):  # type: ignore[no-untyped-def]
    loaded = load_description(make_bundle(root, display_root=root.parents[1]))
    with using_store(store):
        return matrix_of(loaded, options)


def test_encoding_round_trips_every_field_but_the_timing(example: Path) -> None:
    fresh = matrix(example, None)
    back = decode_matrix(encode_matrix(fresh))
    assert back == replace(fresh, stats=MatrixStats())
    assert back.to_section() == fresh.to_section()
    assert fresh.counts()["adjacent"] > 0 and len(back.pairs) == len(fresh.pairs)


def test_a_stored_matrix_equals_a_fresh_one(example: Path, tmp_path: Path) -> None:
    store = Store(tmp_path / "cache")
    fresh = matrix(example, None)
    cold = matrix(example, store)
    warm = matrix(example, store)
    assert (store.hits, store.misses) == (1, 1)
    assert warm.to_section() == cold.to_section() == fresh.to_section()
    assert warm.stats == MatrixStats() and cold.stats.narrow_phase_calls > 0
    assert len(entries(store)) == 1


def test_settings_geometry_and_mesh_bytes_are_in_the_key(example: Path, tmp_path: Path) -> None:
    store = Store(tmp_path / "cache")
    matrix(example, store)
    matrix(example, store, replace(OPTIONS, samples=301))
    matrix(example, store, replace(OPTIONS, semantics="pinocchio"))
    matrix(example, store, replace(OPTIONS, pose={"fl_caster_rotation_joint": 0.5}))
    mesh = example.parents[1] / "meshes" / "caster.stl"
    data = bytearray(mesh.read_bytes())
    data[100] ^= 0x01  # one byte of the header: the same triangles
    mesh.write_bytes(bytes(data))
    matrix(example, store)
    laser = example.parents[1] / "urdf" / "laser.urdf.xacro"
    laser.write_text(laser.read_text().replace('name="laser_size_x" value="', 'name="laser_size_x" value="1', 1))
    matrix(example, store)
    assert store.hits == 0 and len(entries(store)) == 6


def test_cli_matrix_and_check_cached_equal_uncached(
    example: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("GEOMCHECK_CACHE_DIR", str(tmp_path / "cache"))
    for command in (
        ["matrix", str(example), "--samples", "300"],
        ["check", str(example), "--matrix", "--samples", "300", "--no-sweep", "--format", "json", "--exit-zero"],
    ):
        outputs = []
        for extra in (["--no-cache"], [], []):
            assert main([*command, *extra]) == 0
            outputs.append(capsys.readouterr().out)
        assert outputs[0] == outputs[1] == outputs[2]
    report = json.loads(outputs[0])
    assert report["sections"]["matrix"]["samples"] == 300
    assert len(entries(Store(tmp_path / "cache"))) == 1  # matrix and check share the one entry


def test_a_missing_build_product_is_keyed_by_its_source(tmp_path: Path) -> None:
    import trimesh

    from geomcheck.cache.keys import file_sha256
    from geomcheck.load import MeshStore, load_description, make_bundle
    from geomcheck.selfcollision.matrix_cache import mesh_digests

    source = tmp_path / "meshes" / "arm" / "part.stl"
    source.parent.mkdir(parents=True)
    source.write_bytes(trimesh.creation.box((0.1, 0.1, 0.1)).export(file_type="stl"))
    root = tmp_path / "robot.urdf"
    root.write_text(
        '<robot name="r"><link name="a"><collision><geometry>'
        '<mesh filename="meshes/arm/convex/part_convex.stlb"/></geometry></collision></link></robot>'
    )
    bundle = make_bundle(root, display_root=tmp_path)
    robot = load_description(bundle).robot
    first = mesh_digests(robot, MeshStore(bundle))
    assert first == {"meshes/arm/convex/part_convex.stlb": f"source:{file_sha256(source)}"}
    source.write_bytes(trimesh.creation.box((0.2, 0.1, 0.1)).export(file_type="stl"))
    assert mesh_digests(robot, MeshStore(bundle)) != first
    source.unlink()
    assert mesh_digests(robot, MeshStore(bundle)) == {"meshes/arm/convex/part_convex.stlb": "problem:unreadable"}
