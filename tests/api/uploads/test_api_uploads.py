"""Upload trees, archive unpacking and package layout, without a server."""

from __future__ import annotations

import asyncio
import gzip
import hashlib
import io
import os
import stat
import tarfile
import zipfile
from pathlib import Path, PurePosixPath
from typing import Any

import pytest
from apitools import tar_gz_bytes, zip_bytes

from api.errors import UploadError, UploadTooLarge
from api.uploads.archives import unpack
from api.uploads.body import MEMORY_BODY_BYTES, save_body
from api.uploads.layout import arrange
from api.uploads.tree import UploadLimits, UploadTree, clean_path

LIMITS = UploadLimits(max_files=50, max_unpacked_bytes=4 * 1024 * 1024, max_ratio=100.0, max_path_length=512)


def unpack_bytes(tmp_path: Path, data: bytes, content_type: str, limits: UploadLimits = LIMITS) -> UploadTree:
    tmp_path.mkdir(parents=True, exist_ok=True)
    body = tmp_path / "body"
    body.write_bytes(data)
    tree = UploadTree(tmp_path / "tree", limits)
    unpack(body, content_type, tree)
    return tree


def tar_member(name: str, kind: bytes = tarfile.REGTYPE, link: str = "") -> tarfile.TarInfo:
    info = tarfile.TarInfo(name)
    info.type = kind
    info.linkname = link
    info.mode = 0o644
    return info


@pytest.mark.parametrize(
    ("name", "expected"),
    [("robots/r.urdf", "robots/r.urdf"), ("./robots//r.urdf", "robots/r.urdf"), ("a/./b.stl", "a/b.stl")],
)
def test_clean_path_accepts_relative_paths(name: str, expected: str) -> None:
    assert clean_path(name, 512) == PurePosixPath(expected)


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("../evil.urdf", "escapes the bundle"),
        ("meshes/../../evil.urdf", "escapes the bundle"),
        ("/etc/passwd", "is absolute"),
        ("C:/Windows/evil", "is absolute"),
        ("meshes\\..\\evil", "backslash"),
        ("a\x00b", "control characters"),
        ("./", "names no file"),
        ("x" * 600, "longer than 512"),
    ],
)
def test_clean_path_refuses_escapes(name: str, reason: str) -> None:
    with pytest.raises(UploadError, match=reason):
        clean_path(name, 512)


def test_zip_unpacks_files_and_folders(tmp_path: Path) -> None:
    tree = unpack_bytes(
        tmp_path, zip_bytes({"pkg/package.xml": b"<package/>", "pkg/m/a.stl": b"solid"}), "application/zip"
    )
    assert sorted(p.as_posix() for p in tree.files) == ["pkg/m/a.stl", "pkg/package.xml"]
    assert (tmp_path / "tree/pkg/m/a.stl").read_bytes() == b"solid"
    assert tree.unpacked_bytes == len(b"<package/>") + len(b"solid")


def test_zip_refuses_traversal_and_absolute_entries(tmp_path: Path) -> None:
    with pytest.raises(UploadError, match=r"'\.\./\.\./x.urdf' escapes the bundle"):
        unpack_bytes(tmp_path / "a", zip_bytes({"../../x.urdf": b"<robot/>"}), "application/zip")
    with pytest.raises(UploadError, match="is absolute"):
        unpack_bytes(tmp_path / "b", zip_bytes({"/tmp/x.urdf": b"<robot/>"}), "application/zip")
    assert not (tmp_path / "x.urdf").exists()


def test_zip_refuses_symlink_entries(tmp_path: Path) -> None:
    info = zipfile.ZipInfo("meshes/link.stl")
    info.external_attr = (stat.S_IFLNK | 0o777) << 16
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as archive:
        archive.writestr(info, "/etc/passwd")
    with pytest.raises(UploadError, match=r"'meshes/link\.stl' is a symbolic link"):
        unpack_bytes(tmp_path, buf.getvalue(), "application/zip")


def test_zip_bomb_is_refused_by_ratio_while_unpacking(tmp_path: Path) -> None:
    bomb = zip_bytes({"zeros.stl": bytes(20 * 1024 * 1024)})
    assert len(bomb) < 50_000
    limits = UploadLimits(50, 1024**3, 100.0, 512)  # a generous size limit: the ratio must catch it
    with pytest.raises(UploadTooLarge, match="times its"):
        unpack_bytes(tmp_path, bomb, "application/zip", limits)
    written = (tmp_path / "tree/zeros.stl").stat().st_size
    assert written <= 100 * len(bomb) + 2 * 64 * 1024  # stopped at the ratio, not at the end


def test_zip_over_unpacked_size_is_refused(tmp_path: Path) -> None:
    data = zip_bytes({"a.bin": os.urandom(3 * 1024 * 1024), "b.bin": os.urandom(3 * 1024 * 1024)})
    with pytest.raises(UploadTooLarge, match="more than the limit of 4194304 bytes"):
        unpack_bytes(tmp_path, data, "application/zip")


def test_zip_with_a_lying_size_header_is_refused(tmp_path: Path) -> None:
    data = bytearray(zip_bytes({"a.bin": bytes(2 * 1024 * 1024)}))
    central = data.rfind(b"PK\x01\x02")
    data[central + 24 : central + 28] = (10).to_bytes(4, "little")  # declared uncompressed size: 10 bytes
    with pytest.raises(UploadError):
        unpack_bytes(tmp_path, bytes(data), "application/zip")


def test_zip_entry_count_is_limited_before_unpacking(tmp_path: Path) -> None:
    data = zip_bytes({f"f{i}.txt": b"x" for i in range(60)})
    with pytest.raises(UploadTooLarge, match="more than 50 entries"):
        unpack_bytes(tmp_path, data, "application/zip")
    assert not any((tmp_path / "tree").iterdir())


def test_zip_duplicate_entries_are_refused(tmp_path: Path) -> None:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as archive:
        archive.writestr("a.urdf", b"1")
        with pytest.warns(UserWarning):
            archive.writestr("a.urdf", b"2")
    with pytest.raises(UploadError, match=r"'a\.urdf' occurs twice"):
        unpack_bytes(tmp_path, buf.getvalue(), "application/zip")


def test_not_a_zip_is_a_bad_request(tmp_path: Path) -> None:
    with pytest.raises(UploadError, match="not a zip archive"):
        unpack_bytes(tmp_path, b"<robot/>", "application/zip")


def test_tar_gz_unpacks(tmp_path: Path) -> None:
    data = tar_gz_bytes([(tar_member("pkg", tarfile.DIRTYPE), None), (tar_member("pkg/r.urdf"), b"<robot/>")])
    tree = unpack_bytes(tmp_path, data, "application/gzip")
    assert [p.as_posix() for p in tree.files] == ["pkg/r.urdf"]


@pytest.mark.parametrize(
    ("member", "reason"),
    [
        (tar_member("meshes/a.stl", tarfile.SYMTYPE, "/etc/passwd"), "is a link"),
        (tar_member("meshes/a.stl", tarfile.LNKTYPE, "/etc/passwd"), "is a link"),
        (tar_member("dev", tarfile.CHRTYPE), "special file"),
        (tar_member("fifo", tarfile.FIFOTYPE), "special file"),
    ],
)
def test_tar_refuses_links_and_devices(tmp_path: Path, member: tarfile.TarInfo, reason: str) -> None:
    with pytest.raises(UploadError, match=reason):
        unpack_bytes(tmp_path, tar_gz_bytes([(member, None)]), "application/gzip")


def test_tar_refuses_traversal(tmp_path: Path) -> None:
    with pytest.raises(UploadError, match="escapes the bundle"):
        unpack_bytes(tmp_path, tar_gz_bytes([(tar_member("../../evil"), b"x")]), "application/gzip")


def test_gzip_bomb_is_refused_while_decompressing(tmp_path: Path) -> None:
    tar = io.BytesIO()
    with tarfile.open(fileobj=tar, mode="w") as archive:
        info = tar_member("zeros.stl")
        info.size = 64 * 1024 * 1024
        archive.addfile(info, io.BytesIO(bytes(info.size)))
    bomb = gzip.compress(tar.getvalue(), compresslevel=9)
    limits = UploadLimits(50, 1024**3, 100.0, 512)
    with pytest.raises(UploadTooLarge, match="times its size"):
        unpack_bytes(tmp_path, bomb, "application/gzip", limits)


def test_tar_member_over_the_size_limit_is_refused_from_its_header(tmp_path: Path) -> None:
    info = tar_member("big.bin")
    data = tar_gz_bytes([(info, os.urandom(5 * 1024 * 1024))])
    with pytest.raises(UploadTooLarge, match="exceeds the unpacked-size limit"):
        unpack_bytes(tmp_path, data, "application/gzip")


def write_files(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def test_top_level_package_xml_is_named_by_its_name(tmp_path: Path) -> None:
    tree = tmp_path / "tree"
    write_files(
        tree,
        {"package.xml": "<package><name>my_robot</name></package>", "robots/r.urdf": "<robot name='r'/>"},
    )
    layout = arrange(tree, "robots/r.urdf", None, 512)
    assert layout.display_root == tmp_path / "ws" / "my_robot"
    assert layout.root_file == tmp_path / "ws/my_robot/robots/r.urdf"
    assert layout.search_root == tmp_path / "ws"


def test_top_level_legacy_package_is_named_after_the_package_its_root_refers_to(tmp_path: Path) -> None:
    tree = tmp_path / "tree"
    write_files(
        tree,
        {
            "manifest.xml": "<package/>",
            "robots/r.urdf.xacro": '<robot><include filename="$(find pr2_description)/urdf/a.xacro"/>'
            '<mesh filename="package://pr2_description/meshes/b.stl"/></robot>',
            "urdf/a.xacro": "<robot/>",
        },
    )
    layout = arrange(tree, "robots/r.urdf.xacro", None, 512)
    assert layout.display_root.name == "pr2_description"
    assert layout.root_relative == "robots/r.urdf.xacro"


def test_ambiguous_legacy_package_keeps_its_folder(tmp_path: Path) -> None:
    tree = tmp_path / "tree"
    write_files(
        tree,
        {"manifest.xml": "<package/>", "r.urdf": "<robot><a f='$(find one)'/><b f='package://two/x'/></robot>"},
    )
    assert arrange(tree, None, None, 512).display_root == tree


def test_packages_inside_the_upload_stay_where_they_are(tmp_path: Path) -> None:
    tree = tmp_path / "tree"
    write_files(tree, {"pr2_description/manifest.xml": "<package/>", "pr2_description/robots/r.urdf": "<robot/>"})
    layout = arrange(tree, "pr2_description/robots/r.urdf", None, 512)
    assert layout.display_root == tree
    assert layout.root_file == tree / "pr2_description/robots/r.urdf"


def test_root_file_is_chosen_or_must_be_named(tmp_path: Path) -> None:
    tree = tmp_path / "tree"
    write_files(tree, {"robots/only.urdf": "<robot/>", "meshes/a.stl": ""})
    assert arrange(tree, None, None, 512).root_relative == "robots/only.urdf"
    write_files(tree, {"robots/other.urdf.xacro": "<robot/>"})
    with pytest.raises(UploadError, match=r"name the root file.*robots/only\.urdf, robots/other\.urdf\.xacro"):
        arrange(tree, None, None, 512)
    with pytest.raises(UploadError, match=r"root file 'robots/missing\.urdf' is not in the upload"):
        arrange(tree, "robots/missing.urdf", None, 512)
    with pytest.raises(UploadError, match="escapes the bundle"):
        arrange(tree, "../../etc/passwd", None, 512)
    with pytest.raises(UploadError, match=r"SRDF file 'x\.srdf' is not in the upload"):
        arrange(tree, "robots/only.urdf", "x.srdf", 512)


class _Streamed:
    """The part of a request :func:`save_body` reads: its body in chunks."""

    def __init__(self, data: bytes, chunk: int = 64 * 1024) -> None:
        self.chunks = [data[i : i + chunk] for i in range(0, len(data), chunk)]

    async def stream(self) -> Any:
        for chunk in self.chunks:
            yield chunk


@pytest.mark.parametrize("size", [0, 1000, MEMORY_BODY_BYTES, MEMORY_BODY_BYTES + 1, 3 * MEMORY_BODY_BYTES + 7])
def test_a_body_is_held_in_memory_up_to_the_bound_then_written_to_disk(tmp_path: Path, size: int) -> None:
    data = os.urandom(size)
    spill = tmp_path / "work" / "body.archive"
    held, length, digest = asyncio.run(save_body(_Streamed(data), spill))  # type: ignore[arg-type]
    assert (length, digest) == (size, hashlib.sha256(data).hexdigest())
    if size <= MEMORY_BODY_BYTES:  # answered from the cache, such a request touches no disk
        assert held == data and not spill.parent.exists()
    else:
        assert held is None and spill.read_bytes() == data
