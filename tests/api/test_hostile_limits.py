"""Regression tests of the service's 500s and bypasses found by hostile uploads: deeply nested
options JSON, tar archives of chained extended headers, and a configuration file in the
upload that asks for more than the API allows."""

from __future__ import annotations

import io
import tarfile
from pathlib import Path

import pytest
from apitools import TWO_LINKS, post_zip, zip_bytes
from fastapi.testclient import TestClient

from api.checks.options import MAX_JSON_DEPTH, RawOptions, check_options, json_depth
from api.errors import UploadError
from api.uploads.archives import unpack_tar
from api.uploads.tree import UploadLimits, UploadTree
from geomcheck.errors import UsageError
from geomcheck.option_spec import read_options


def test_deeply_nested_options_json_is_a_400_not_a_500(client: TestClient) -> None:
    nested = "[" * 30_000 + "]" * 30_000  # within the 64 KB form-part limit, far beyond the recursion limit
    answer = client.post(
        "/v1/checks",
        files={"description": ("two_links.urdf", TWO_LINKS, "application/xml")},
        data={"options": nested},
    )
    assert answer.status_code == 400
    assert answer.json() == {"detail": f"options field nests 30000 levels deep; at most {MAX_JSON_DEPTH} are allowed"}


@pytest.mark.parametrize(
    ("text", "depth"),
    [('{"samples": 5}', 1), ('{"args": {"a": "[[[{"}}', 2), ('{"a": "\\"[["}', 1), ("[[[]]]", 3), ('"x"', 0)],
)
def test_json_depth_skips_strings(text: str, depth: int) -> None:
    assert json_depth(text) == depth


def test_ordinary_options_json_still_parses() -> None:
    raw = RawOptions()
    raw.add_json('{"samples": 500, "args": {"NAME": "VALUE"}, "select": ["GC1", "fit"]}')
    assert raw.values == {"samples": ["500"], "args": ["NAME=VALUE"], "select": ["GC1", "fit"]}


def chained_long_names(levels: int) -> bytes:
    """A tar whose first member is preceded by ``levels`` GNU long-name headers, each naming the next."""
    out = io.BytesIO()
    block = tarfile.BLOCKSIZE
    for _ in range(levels):
        info = tarfile.TarInfo("././@LongLink")
        info.type = tarfile.GNUTYPE_LONGNAME
        name = b"a" * 10 + b"\0"
        info.size = len(name)
        out.write(info.tobuf(format=tarfile.GNU_FORMAT))
        out.write(name + b"\0" * (block - len(name)))
    final = tarfile.TarInfo("robot.urdf")
    final.size = len(TWO_LINKS)
    out.write(final.tobuf(format=tarfile.GNU_FORMAT))
    out.write(TWO_LINKS + b"\0" * (-len(TWO_LINKS) % block))
    out.write(b"\0" * block * 2)
    return out.getvalue()


def test_tar_of_chained_long_name_headers_is_refused(tmp_path: Path) -> None:
    archive = tmp_path / "bomb.tar"
    archive.write_bytes(chained_long_names(20_000))
    limits = UploadLimits(max_files=2000, max_unpacked_bytes=256 << 20, max_ratio=100.0, max_path_length=512)
    tree = UploadTree(tmp_path / "tree", limits)
    with pytest.raises(UploadError, match="extended headers chained too deeply"):
        unpack_tar(archive, tree, gzipped=False)
    assert tree.files == []


def test_uploaded_configuration_is_held_to_the_api_limits(client: TestClient) -> None:
    body = zip_bytes({"robot/two_links.urdf": TWO_LINKS, "robot/geomcheck.toml": b"samples = 5000000\nmatrix = true\n"})
    answer = post_zip(client, body, root="robot/two_links.urdf")
    assert answer.status_code == 400, answer.text
    assert "samples must be between 1 and 200000, got 5000000" in answer.json()["detail"]


def test_count_thresholds_in_an_upload_are_capped(tmp_path: Path) -> None:
    config = read_options({"thresholds": {"fit": {"surface_samples": 5_000_000}}}, tmp_path, "geomcheck.toml")
    with pytest.raises(UsageError, match=r"thresholds.fit.surface_samples must be at most 20000 in the service"):
        check_options(config, max_samples=200_000)
    fine = read_options({"thresholds": {"fit": {"surface_samples": 4000}}, "samples": 500}, tmp_path, "x")
    assert check_options(fine, max_samples=200_000).thresholds.fit.surface_samples == 4000


NESTED_REPLICATES = (
    b'<mujoco><worldbody><replicate count="20" offset="1 0 0"><replicate count="20" offset="0 1 0">'
    b'<replicate count="20" offset="0 0 1"><replicate count="20" offset="1 1 0"><body><geom size=".1"/></body>'
    b"</replicate></replicate></replicate></replicate></worldbody></mujoco>"
)


def include_fan_out() -> dict[str, bytes]:
    """Six SDFormat files, each level including the next ten times: 111,111 models and links."""
    files = {}
    for level in range(5):
        includes = "".join(
            f"<include><uri>../m{level + 1}/model.sdf</uri><name>c{i}</name></include>" for i in range(10)
        )
        files[f"m{level}/model.sdf"] = (
            f'<sdf version="1.7"><model name="m{level}"><link name="l"/>{includes}</model></sdf>'
        ).encode()
    files["m5/model.sdf"] = b'<sdf version="1.7"><model name="leaf"><link name="l"/></model></sdf>'
    return files


def frame_chain(frames: int) -> bytes:
    chain = "".join(
        f'<frame name="f{i}" attached_to="{"base" if i == 0 else f"f{i - 1}"}">'
        f'<pose relative_to="{"base" if i == 0 else f"f{i - 1}"}">0.001 0 0 0 0 0.001</pose></frame>'
        for i in range(frames)
    )
    return (
        f'<sdf version="1.7"><model name="chain"><link name="base"/>{chain}<link name="tip">'
        f'<pose relative_to="f{frames - 1}"/></link><joint name="j" type="fixed"><parent>f{frames - 1}</parent>'
        "<child>tip</child></joint></model></sdf>"
    ).encode()


@pytest.mark.parametrize(
    ("files", "root", "status", "fragment"),
    [
        # was: 35-50 s and 2 GiB, once "the check process died with SIGSEGV"
        ({"robot.xml": NESTED_REPLICATES}, "robot.xml", 413, "<replicate> expands to"),
        # was: 111,111 links built for 234 s, then the memory limit
        (include_fan_out(), "m0/model.sdf", 413, "(max_sdf_elements)"),
        # was: "the check recursed too deeply (an endlessly recursive macro?)" for legal SDFormat
        ({"chain.sdf": frame_chain(900)}, "chain.sdf", 201, ""),
    ],
    ids=["nested-replicates", "include-fan-out", "frame-chain"],
)
def test_amplifying_uploads_are_answered_within_10_s(
    client: TestClient, files: dict[str, bytes], root: str, status: int, fragment: str
) -> None:
    import time

    started = time.monotonic()
    answer = post_zip(client, zip_bytes(files), root=root, cache="false")
    assert time.monotonic() - started < 10
    assert answer.status_code == status, answer.text
    if fragment:
        assert fragment in answer.json()["detail"]
    else:
        assert answer.json()["report"]["robot"]["links"] == 2
