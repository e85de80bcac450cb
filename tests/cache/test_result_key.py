"""The service's result key: what changes a report changes the key, what is applied after
the analyses (fail_on) does not."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import pytest

from api.results.key import result_key, result_versions, upload_digests
from geomcheck.cache.keys import code_fingerprint, library_versions
from geomcheck.config import Config
from geomcheck.option_spec import read_options

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base"
ROOT = "pr2_base/robots/pr2_base.urdf.xacro"


@pytest.fixture
def upload(tmp_path: Path) -> Path:
    """The bundled example as an unpacked upload (the folder ``pr2_base`` inside the upload root)."""
    root = tmp_path / "upload"
    shutil.copytree(EXAMPLE, root / "pr2_base")
    return root


def request(data: dict[str, Any], base: Path) -> Config:
    return read_options(data, base, "request")


def key_of(upload: Path, data: dict[str, Any] | None = None, versions: dict[str, str] | None = None) -> str:
    return result_key(upload_digests(upload), ROOT, request(data or {}, upload), upload, versions)


def test_upload_digests_are_sorted_relative_paths(upload: Path) -> None:
    digests = upload_digests(upload)
    assert list(digests) == sorted(digests)
    assert "pr2_base/meshes/base.stl" in digests and "pr2_base/robots/pr2_base.urdf.xacro" in digests
    assert all(len(d) == 64 for d in digests.values())
    (upload / "link").symlink_to(upload / "pr2_base" / "package.xml")
    assert "link" not in upload_digests(upload)


def test_same_upload_anywhere_has_the_same_key(upload: Path, tmp_path: Path) -> None:
    elsewhere = tmp_path / "another" / "folder"
    shutil.copytree(upload, elsewhere)
    data = {"search": ["pr2_base"], "samples": 500}
    assert key_of(upload, data) == key_of(elsewhere, data)
    assert len(key_of(upload)) == 64


def test_one_mesh_byte_changes_the_key(upload: Path) -> None:
    before = key_of(upload)
    mesh = upload / "pr2_base" / "meshes" / "caster.stl"
    data = bytearray(mesh.read_bytes())
    data[-1] ^= 0x01
    mesh.write_bytes(bytes(data))
    assert key_of(upload) != before


def test_a_renamed_file_changes_the_key(upload: Path) -> None:
    before = key_of(upload)
    (upload / "pr2_base" / "README.md").rename(upload / "pr2_base" / "README.txt")
    assert key_of(upload) != before


@pytest.mark.parametrize(
    "option",
    [
        {"samples": 501},
        {"seed": 1},
        {"matrix": True},
        {"sweep": False},
        {"backend": "fcl"},
        {"semantics": "pinocchio"},
        {"args": {"use_laser": "false"}},
        {"pose": {"fl_caster_rotation_joint": 0.5}},
        {"search": ["pr2_base"]},
    ],
    ids=lambda o: next(iter(o)),
)
def test_one_option_changes_the_key(upload: Path, option: dict[str, Any]) -> None:
    assert key_of(upload, option) != key_of(upload)


def test_options_spelled_out_at_their_defaults_key_the_same_report(upload: Path) -> None:
    assert key_of(upload, {"samples": 10000, "seed": 0, "sweep": True, "backend": "coal"}) == key_of(upload)


def test_one_threshold_changes_the_key(upload: Path) -> None:
    base = key_of(upload)
    assert key_of(upload, {"thresholds": {"fit": {"min_coverage": 0.91}}}) != base
    assert key_of(upload, {"thresholds": {"fit": {"min_coverage": 0.90}}}) == base  # the default, spelled out


def test_a_configuration_file_in_the_upload_changes_the_key(upload: Path) -> None:
    base = key_of(upload)
    config = upload / "pr2_base" / "geomcheck.toml"
    config.write_text("[thresholds.fit]\nmin_coverage = 0.8\n")
    with_file = key_of(upload)
    assert with_file != base
    config.write_text("[thresholds.fit]\nmin_coverage = 0.7\n")
    assert key_of(upload) not in (base, with_file)


def test_versions_change_the_key(upload: Path) -> None:
    versions = result_versions()
    assert versions["geomcheck"] == code_fingerprint() and versions["geomcheck"].startswith("0.")
    assert set(library_versions()) <= set(versions) and versions["xacro"] != "absent"
    base = key_of(upload, versions=versions)
    assert base == key_of(upload)  # the running versions by default
    assert key_of(upload, versions={**versions, "geomcheck": "9.9.9"}) != base
    assert key_of(upload, versions={**versions, "coal": "0.0.1"}) != base


def test_fail_on_applies_after_the_analyses_and_is_not_in_the_key(upload: Path) -> None:
    assert key_of(upload, {"fail-on": "warning"}) == key_of(upload) == key_of(upload, {"fail-on": "info"})


@pytest.mark.parametrize(
    "selection",
    [
        {"select": ["GC3"]},
        {"ignore": ["GC501"]},
        {"extend-select": ["GC4"]},
        {"severity": {"GC301": "info"}},
        {"per-link-ignores": {"base_link": ["GC3"]}},
    ],
    ids=lambda o: next(iter(o)),
)
def test_the_selection_is_in_the_key(upload: Path, selection: dict[str, Any]) -> None:
    # the selection decides which analyses run, so the report of one is not a filter of another
    assert key_of(upload, selection) != key_of(upload)


def test_root_is_in_the_key(upload: Path) -> None:
    digests = upload_digests(upload)
    config = request({}, upload)
    other = "pr2_base/urdf/base.urdf.xacro"
    assert result_key(digests, ROOT, config, upload) != result_key(digests, other, config, upload)
