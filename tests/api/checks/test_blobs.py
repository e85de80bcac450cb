"""Uploads packed for remote workers: the arranged tree and its spec come back as the same CheckJob."""

from __future__ import annotations

import io
import re
import tarfile
from pathlib import Path

import pytest

from api.checks.blobs import JobSpec, pack, unpack
from api.checks.job import CheckJob
from api.checks.options import RawOptions, request_config
from api.store import StorageError
from geomcheck.cli import main as cli_main


def arranged(workdir: Path) -> CheckJob:
    root = workdir / "ws" / "my_robot"
    (root / "robots").mkdir(parents=True)
    (root / "robots" / "r.urdf").write_text("<robot name='r'><link name='a'/></robot>")
    (root / "config").mkdir()
    (root / "config" / "r.srdf").write_text("<robot name='r'/>")
    (root / "meshes").mkdir()  # an empty folder travels too
    raw = RawOptions()
    raw.add("samples", "300", "query")
    raw.add("args", "arm=true", "query")
    config = request_config(raw, 1000, root, root / "config" / "r.srdf")
    return CheckJob("abc", root / "robots" / "r.urdf", root, workdir / "ws", config)


def test_pack_and_unpack_give_the_same_job(tmp_path: Path) -> None:
    job = arranged(tmp_path / "api")
    raw = RawOptions({"samples": ["300"], "args": ["arm=true"]})
    spec = JobSpec.of(job, raw, tmp_path / "api")
    assert spec.as_json() == {
        "root_file": "ws/my_robot/robots/r.urdf",
        "display_root": "ws/my_robot",
        "search_root": "ws",
        "srdf": "ws/my_robot/config/r.srdf",
        "options": {"samples": ["300"], "args": ["arm=true"]},
        "verify_fixes": True,
    }
    data = pack(tmp_path / "api")
    assert pack(tmp_path / "api") == data  # the same tree packs to the same bytes: stored once by digest
    unpack(data, tmp_path / "worker")
    again = JobSpec.from_json(spec.as_json()).job("abc", tmp_path / "worker", 1000)
    worker = (tmp_path / "worker").resolve()
    assert again.root_file == worker / "ws/my_robot/robots/r.urdf"
    assert (again.display_root, again.search_root) == (worker / "ws/my_robot", worker / "ws")
    assert again.config.srdf == worker / "ws/my_robot/config/r.srdf"
    assert (again.config.samples, dict(again.config.args)) == (300, {"arm": "true"})
    assert (worker / "ws/my_robot/meshes").is_dir()
    assert again.root_file.read_text() == job.root_file.read_text()


def tar_gz(members: list[tarfile.TarInfo]) -> bytes:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz") as archive:
        for member in members:
            archive.addfile(member, io.BytesIO(b"x" * member.size) if member.isfile() else None)
    return buffer.getvalue()


def test_a_tampered_stored_upload_is_refused(tmp_path: Path) -> None:
    link = tarfile.TarInfo("ws/evil")
    link.type, link.linkname = tarfile.SYMTYPE, "/etc/passwd"
    with pytest.raises(StorageError, match="holds 'ws/evil', which is neither a file nor a folder"):
        unpack(tar_gz([link]), tmp_path / "a")
    outside = tarfile.TarInfo("../outside.txt")
    outside.size = 1
    with pytest.raises(tarfile.OutsideDestinationError):
        unpack(tar_gz([outside]), tmp_path / "b")
    assert not (tmp_path / "outside.txt").exists()
    with pytest.raises(StorageError, match=re.escape("stored path '../../etc' leaves the work folder")):
        JobSpec("../../etc", "ws", "ws", None, {}).job("x", tmp_path / "b", 10)
    with pytest.raises(StorageError, match="stored check specification is malformed"):
        JobSpec.from_json({"root_file": "r.urdf"})


def test_worker_without_a_broker_is_a_one_line_error(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.delenv("GEOMCHECK_BROKER_URL", raising=False)
    assert cli_main(["worker", "--concurrency", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("geomcheck: error: invalid GEOMCHECK_BROKER_URL scheme in ''; valid choices: redis://")
    assert cli_main(["worker", "--concurrency", "0"]) == 2
    assert "--concurrency must be at least 1, got 0" in capsys.readouterr().err
