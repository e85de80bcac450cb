"""Uploads as they travel to remote workers: the arranged upload folder as one gzip'd tar.

An API replica unpacks and checks an upload on its own disk (limits, paths, layout), packs
the arranged folder with :func:`pack` and stores the bytes in the database under their
SHA-256 digest (:meth:`api.store.Store.put_blob`); a worker on any machine reads them back
and :func:`unpack` s them into its own work folder. The :class:`JobSpec` beside it says
where the root file, the upload root and the SRDF are, relative to that folder, and which
options the request gave, so the worker builds the same :class:`api.checks.job.CheckJob`.
"""

from __future__ import annotations

import io
import tarfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from api.checks.job import CheckJob
from api.checks.options import RawOptions, request_config
from api.store import StorageError

COMPRESS_LEVEL = 1  # meshes compress poorly; speed matters more than the last percent [gzip level]


@dataclass(frozen=True)
class JobSpec:
    """A check's layout relative to its work folder, and the request's raw options."""

    root_file: str
    display_root: str
    search_root: str
    srdf: str | None
    options: dict[str, list[str]]
    verify_fixes: bool = True

    @classmethod
    def of(cls, job: CheckJob, raw: RawOptions, workdir: Path) -> JobSpec:
        def rel(path: Path) -> str:
            return path.relative_to(workdir).as_posix()

        return cls(
            root_file=rel(job.root_file),
            display_root=rel(job.display_root),
            search_root=rel(job.search_root),
            srdf=rel(job.config.srdf) if job.config.srdf is not None else None,
            options={k: list(v) for k, v in raw.values.items()},
            verify_fixes=job.verify_fixes,
        )

    def as_json(self) -> dict[str, Any]:
        return {
            "root_file": self.root_file,
            "display_root": self.display_root,
            "search_root": self.search_root,
            "srdf": self.srdf,
            "options": self.options,
            "verify_fixes": self.verify_fixes,
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> JobSpec:
        try:
            return cls(
                root_file=str(data["root_file"]),
                display_root=str(data["display_root"]),
                search_root=str(data["search_root"]),
                srdf=str(data["srdf"]) if data.get("srdf") is not None else None,
                options={str(k): [str(x) for x in v] for k, v in dict(data["options"]).items()},
                verify_fixes=bool(data.get("verify_fixes", True)),  # absent in specs stored before
            )
        except (KeyError, TypeError, ValueError) as err:
            raise StorageError(f"stored check specification is malformed: {err}") from None

    def job(self, check_id: str, workdir: Path, max_samples: int) -> CheckJob:
        """The :class:`CheckJob` of this spec with the upload unpacked in ``workdir``."""
        display_root = inside(workdir, self.display_root)
        srdf = inside(workdir, self.srdf) if self.srdf is not None else None
        config = request_config(RawOptions(dict(self.options)), max_samples, display_root, srdf)
        root_file, search_root = inside(workdir, self.root_file), inside(workdir, self.search_root)
        return CheckJob(check_id, root_file, display_root, search_root, config, verify_fixes=self.verify_fixes)


def inside(folder: Path, relative: str) -> Path:
    """``folder / relative``, refusing any path that leaves ``folder``."""
    path = (folder / relative).resolve()
    if not path.is_relative_to(folder.resolve()):
        raise StorageError(f"stored path {relative!r} leaves the work folder")
    return path


def pack(folder: Path) -> bytes:
    """Every file and folder under ``folder`` as a gzip'd tar, names relative to it, sorted."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz", compresslevel=COMPRESS_LEVEL) as archive:
        for path in sorted(folder.rglob("*")):
            if path.is_symlink() or not (path.is_file() or path.is_dir()):
                continue  # upload trees hold neither; never follow one
            archive.add(path, arcname=path.relative_to(folder).as_posix(), recursive=False)
    return buffer.getvalue()


def unpack(data: bytes, folder: Path) -> None:
    """Extract :func:`pack` output into ``folder`` (created), refusing links and paths outside it."""
    folder.mkdir(parents=True, exist_ok=False)
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as archive:
        members = archive.getmembers()
        for member in members:
            if not (member.isfile() or member.isdir()):
                raise StorageError(f"stored upload holds {member.name!r}, which is neither a file nor a folder")
        archive.extractall(folder, members=members, filter="data")
