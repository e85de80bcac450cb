"""Hostile uploads: each gets a 4xx with a one-line reason (never a 500, a hang or a leak),
and the service still answers afterwards with no upload left on disk."""

from __future__ import annotations

import io
import stat
import tarfile
import time
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from apitools import EXPONENTIAL, TWO_LINKS, XACRO, tar_gz_bytes, zip_bytes
from fastapi.testclient import TestClient

MiB = 1024 * 1024
BILLION_LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<robot name="&lol9;"><link name="a"/></robot>
"""


@pytest.fixture(scope="module")
def hostile(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[TestClient, Path]]:
    """One service with small limits for every hostile upload of this module."""
    from api.http.app import create_app
    from api.settings import Settings

    data = tmp_path_factory.mktemp("hostile") / "data"
    settings = Settings(
        data_dir=data,
        max_body_bytes=2 * MiB,
        max_files=20,
        max_unpacked_bytes=8 * MiB,
        check_timeout_s=6,
        check_cpu_s=3,
    )
    with TestClient(create_app(settings)) as client:
        yield client, data


def refused(hostile: tuple[TestClient, Path], response: Any, status: int | tuple[int, ...], *fragments: str) -> str:
    """Assert a 4xx ``status`` with a one-line detail holding ``fragments`` and no server path; the
    service still answers and has no upload left on disk."""
    client, data = hostile
    statuses = (status,) if isinstance(status, int) else status
    assert response.status_code in statuses, response.text
    detail = response.json()["detail"]
    assert isinstance(detail, str) and "\n" not in detail and len(detail) <= 500
    assert str(data) not in detail and "/tmp/" not in detail
    for fragment in fragments:
        assert fragment in detail, detail
    assert client.get("/healthz").json()["status"] == "ok"
    deadline = time.monotonic() + 5
    while any((data / "work").iterdir()) and time.monotonic() < deadline:
        time.sleep(0.02)
    assert not any((data / "work").iterdir()), "an upload folder was left behind"
    return str(detail)


def post(client: TestClient, body: bytes, content_type: str, **params: Any) -> Any:
    return client.post("/v1/checks", content=body, headers={"content-type": content_type}, params=params)


def test_zip_bomb_by_ratio(hostile: tuple[TestClient, Path]) -> None:
    bomb = zip_bytes({"meshes/zeros.stl": bytes(64 * MiB), "robot.urdf": TWO_LINKS})
    assert len(bomb) < 200_000
    response = post(hostile[0], bomb, "application/zip", root="robot.urdf")
    refused(hostile, response, 413, "times its")


def test_zip_bomb_by_absolute_size(hostile: tuple[TestClient, Path]) -> None:
    import os

    big = zip_bytes({f"m{i}.bin": os.urandom(MiB) for i in range(9)}, compression=zipfile.ZIP_STORED)
    refused(hostile, post(hostile[0], big, "application/zip"), 413)


@pytest.mark.parametrize(("method", "name"), [(zipfile.ZIP_BZIP2, "bzip2"), (zipfile.ZIP_LZMA, "LZMA")])
def test_zip_members_decompressed_without_a_bound_are_refused_unread(
    hostile: tuple[TestClient, Path], method: int, name: str
) -> None:
    import resource

    # 256 MiB of zeros in a few hundred bytes: zipfile would inflate it in one read
    bomb = zip_bytes({"robot.urdf": TWO_LINKS, "meshes/zeros.stl": bytes(256 * MiB)}, compression=method)
    assert len(bomb) < 100_000
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    response = post(hostile[0], bomb, "application/zip", root="robot.urdf")
    detail = refused(hostile, response, 400, f"is compressed with {name}; only stored and deflated")
    assert "robot.urdf" in detail  # the first entry already says it
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 64 * 1024  # [KiB]: nothing inflated


def test_gzip_bomb(hostile: tuple[TestClient, Path]) -> None:
    info = tarfile.TarInfo("zeros.stl")
    bomb = tar_gz_bytes([(info, bytes(64 * MiB))])
    refused(hostile, post(hostile[0], bomb, "application/gzip"), 413)


@pytest.mark.parametrize("name", ["../../evil.urdf", "robots/../../../evil.urdf", "/etc/evil.urdf"])
def test_archive_paths_escaping_the_bundle(hostile: tuple[TestClient, Path], name: str) -> None:
    response = post(hostile[0], zip_bytes({name: TWO_LINKS}), "application/zip")
    refused(hostile, response, 400, "upload path")
    tar = tar_gz_bytes([(tarfile.TarInfo(name), TWO_LINKS)])
    refused(hostile, post(hostile[0], tar, "application/x-tar+gzip"), 400, "upload path")


def test_symlinks_and_hardlinks(hostile: tuple[TestClient, Path]) -> None:
    info = zipfile.ZipInfo("robot.urdf")
    info.external_attr = (stat.S_IFLNK | 0o777) << 16
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as archive:
        archive.writestr(info, "/etc/passwd")
    refused(hostile, post(hostile[0], buf.getvalue(), "application/zip"), 400, "is a symbolic link")
    for kind in (tarfile.SYMTYPE, tarfile.LNKTYPE):
        link = tarfile.TarInfo("robot.urdf")
        link.type, link.linkname = kind, "/etc/passwd"
        refused(hostile, post(hostile[0], tar_gz_bytes([(link, None)]), "application/gzip"), 400, "is a link")


def test_billion_laughs(hostile: tuple[TestClient, Path]) -> None:
    response = post(hostile[0], BILLION_LAUGHS, "application/xml")
    refused(hostile, response, 422, "GC101", "entit")


@pytest.mark.parametrize(
    "include",
    [
        b'<xacro:include filename="/etc/passwd"/>',
        b'<xacro:include filename="file:///etc/passwd"/>',
        b'<xacro:include filename="../../../../../../etc/passwd"/>',
    ],
)
def test_xacro_including_a_file_outside_the_upload(hostile: tuple[TestClient, Path], include: bytes) -> None:
    response = post(hostile[0], XACRO % include, "application/xml", root="robot.urdf.xacro")
    detail = refused(hostile, response, (403, 404, 422))
    assert "root:" not in detail  # nothing of /etc/passwd came back


@pytest.mark.parametrize(
    "expression",
    [b"$(env HOME)", b"${''.__class__.__mro__[1].__subclasses__()}", b"${__import__('os')}"],
)
def test_xacro_reaching_the_environment_or_the_interpreter(hostile: tuple[TestClient, Path], expression: bytes) -> None:
    body = XACRO % (b'<link name="%s"/>' % expression)
    refused(hostile, post(hostile[0], body, "application/xml", root="robot.urdf.xacro"), 422)


def test_xacro_optenv_takes_its_default_not_the_servers_variable(hostile: tuple[TestClient, Path]) -> None:
    body = XACRO % b'<link name="$(optenv HOME nothing)"/>'
    response = post(hostile[0], body, "application/xml", root="robot.urdf.xacro")
    assert response.status_code == 201, response.text
    assert "nothing" in [entry["link"] for entry in response.json()["report"]["sections"]["links"]]


def test_infinite_macro_recursion(hostile: tuple[TestClient, Path]) -> None:
    body = XACRO % b'<xacro:macro name="loop"><xacro:loop/></xacro:macro><xacro:loop/>'
    started = time.monotonic()
    refused(hostile, post(hostile[0], body, "application/xml", root="robot.urdf.xacro"), (413, 422))
    assert time.monotonic() - started < 15


def test_exponential_macro_expansion_is_stopped_at_its_limits(hostile: tuple[TestClient, Path]) -> None:
    client, _ = hostile
    started = time.monotonic()
    response = post(client, EXPONENTIAL, "application/xml", root="robot.urdf.xacro")
    refused(hostile, response, (413, 422))
    assert time.monotonic() - started < 20
    failed = client.get("/v1/checks", params={"status": "failed", "limit": 1}).json()["items"][0]
    assert failed["reason"] == response.json()["detail"]


def test_oversized_body_by_content_length(hostile: tuple[TestClient, Path]) -> None:
    response = post(hostile[0], b"<robot>" + b" " * (3 * MiB) + b"</robot>", "application/xml")
    refused(hostile, response, 413, "exceeds the limit of 2097152 bytes")


def test_oversized_body_streamed_without_length(hostile: tuple[TestClient, Path]) -> None:
    def chunks() -> Iterator[bytes]:
        for _ in range(64):
            yield b" " * 65536

    response = hostile[0].post("/v1/checks", content=chunks(), headers={"content-type": "application/zip"})
    refused(hostile, response, 413, "request body exceeds the limit of 2097152 bytes")


def test_too_many_files(hostile: tuple[TestClient, Path]) -> None:
    files = [("files", (f"meshes/m{i}.stl", b"x")) for i in range(25)]
    refused(hostile, hostile[0].post("/v1/checks", files=files), 413)
    archive = zip_bytes({f"meshes/m{i}.stl": b"x" for i in range(25)})
    refused(hostile, post(hostile[0], archive, "application/zip"), 413, "more than 20 entries")


@pytest.mark.parametrize(
    "params", [{"root": "../../../etc/passwd"}, {"root": "/etc/passwd"}, {"srdf": "../../etc/passwd"}]
)
def test_parameters_naming_files_outside_the_upload(hostile: tuple[TestClient, Path], params: dict[str, str]) -> None:
    archive = zip_bytes({"robot.urdf": TWO_LINKS})
    refused(hostile, post(hostile[0], archive, "application/zip", **params), 400)


def test_configuration_in_the_upload_cannot_point_outside(hostile: tuple[TestClient, Path]) -> None:
    archive = zip_bytes({"robot.urdf": TWO_LINKS, "geomcheck.toml": b'search = ["../../../../.."]\n'})
    detail = refused(hostile, post(hostile[0], archive, "application/zip", root="robot.urdf"), (400, 422))
    assert "outside the upload" in detail or "not a directory" in detail


def test_garbage_bodies(hostile: tuple[TestClient, Path]) -> None:
    client = hostile[0]
    refused(hostile, post(client, b"PK\x03\x04garbage", "application/zip"), 400)
    refused(hostile, post(client, b"\x1f\x8bgarbage", "application/gzip"), 400)
    refused(hostile, post(client, b"", "application/zip"), 400)
    broken = b'--b\r\nContent-Disposition: form-data; name="files"; filename="a"\r\n\r\nx'
    refused(hostile, post(client, broken, "multipart/form-data; boundary=b"), 400)


def test_a_sphere_of_radius_1e_minus_20_is_a_finding_not_a_500(hostile: tuple[TestClient, Path]) -> None:
    client, _ = hostile
    body = TWO_LINKS.replace(b'<box size="0.2 0.2 0.2"/>', b'<sphere radius="1e-20"/>')
    answer = post(client, body, "application/xml")
    assert answer.status_code == 201, answer.text
    found = [(d["code"], d["about"]) for d in answer.json()["report"]["diagnostics"] if d["code"] == "GC126"]
    assert found == [("GC126", "collision[0].sphere.radius")]


@pytest.mark.parametrize("filename", ["file://m.stl", "file:///m.stl", "m.stl", "file://../m.stl"])
def test_a_mesh_outside_the_upload_names_no_server_folder(hostile: tuple[TestClient, Path], filename: str) -> None:
    client, data = hostile
    body = TWO_LINKS.replace(b'<box size="0.2 0.2 0.2"/>', f'<mesh filename="{filename}"/>'.encode())
    answer = post(client, body, "application/xml")
    assert answer.status_code == 201, answer.text
    assert str(data) not in answer.text and str(data.resolve()) not in answer.text  # was: .../data/work/<id>/m.stl
    codes = {d["code"] for d in answer.json()["report"]["diagnostics"]}
    assert codes & {"GC201", "GC203"}, codes


ATTACHED_OUTSIDE = b"""<mujoco><asset><model name="s" file="sub.xml"/></asset>
<worldbody><body name="b"><attach model="s" body="p" prefix="s_"/></body></worldbody></mujoco>"""
SUB_MODEL = b"""<mujoco><asset><mesh name="m" file="%s"/></asset>
<worldbody><body name="p"><geom type="mesh" mesh="m"/></body></worldbody></mujoco>"""


@pytest.mark.parametrize("target", [b"/etc/hostname", b"/etc/no-such-file.stl", b"../../../etc/passwd"])
def test_mjcf_files_outside_the_upload_are_refused_before_mujoco_reads_them(
    hostile: tuple[TestClient, Path], target: bytes
) -> None:
    # was: MuJoCo opened them itself ("no decoder found" for a file that exists, "Error opening
    # file" for one that does not: an oracle of the server's paths)
    client, _ = hostile
    body = zip_bytes({"robot.xml": ATTACHED_OUTSIDE, "sub.xml": SUB_MODEL % target})
    answer = post(client, body, "application/zip", root="robot.xml")
    detail = refused(hostile, answer, 422, "access outside the uploaded bundle refused")
    assert "decoder" not in detail and "opening" not in detail


@pytest.mark.parametrize(
    "body",
    [
        b'<mujoco><worldbody><body><geom type="box" size="1e308 1 1"/></body></worldbody></mujoco>',
        b'<mujoco><worldbody><body pos="1e300 0 0"><geom type="sphere" size="1"/></body></worldbody></mujoco>',
        b'<mujoco><worldbody><body><geom type="sphere" size="1" mass="1e300"/></body></worldbody></mujoco>',
    ],
)
def test_mjcf_numbers_beyond_the_load_limits_are_refused_naming_the_element(
    hostile: tuple[TestClient, Path], body: bytes
) -> None:
    client, _ = hostile
    answer = post(client, body, "application/xml")  # was: 500 "Out of range float values are not JSON compliant"
    refused(hostile, answer, 422, "beyond the limit of", "<")
