"""Reading the three kinds of ``POST /v1/checks`` body into an upload tree.

* ``application/xml`` / ``text/xml``: one URDF or xacro document (``root`` names it, default
  ``robot.urdf``); whatever it references is absent.
* ``multipart/form-data``: ``description`` (the root file) and ``files`` parts, each part's
  filename being its path in the package tree, plus option fields.
* ``application/zip``, gzip'd tar, tar: the package tree; ``root`` names the root file.
"""

from __future__ import annotations

import hashlib
import shutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from fastapi import Request
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import UploadFile
from starlette.exceptions import HTTPException

from api.checks.options import OPTION_NAMES, RawOptions
from api.errors import UnsupportedMediaType, UploadError, UploadTooLarge
from api.uploads.archives import ARCHIVE_TYPES, SNIFF_BYTES, sniffed_type, unpack
from api.uploads.tree import UploadTree

XML_TYPES = frozenset({"application/xml", "text/xml"})
MULTIPART = "multipart/form-data"
SUPPORTED_TYPES = (*sorted(XML_TYPES), MULTIPART, *sorted(ARCHIVE_TYPES))
DEFAULT_ROOT = "robot.urdf"
FILE_FIELDS = ("description", "files", "srdf")
TEXT_FIELDS = ("root", "cache", "options", *OPTION_NAMES)
MAX_FIELD_BYTES = 64 * 1024  # one non-file form field [bytes]
# a document or archive up to this size is held in memory until it must be unpacked [bytes]
MEMORY_BODY_BYTES = 1024 * 1024


@dataclass
class Upload:
    """What a request brought: files written into ``tree``, the root file and SRDF paths it named."""

    tree: UploadTree
    root: str | None
    srdf: str | None


def media_type(request: Request) -> str:
    """The request's media type, lower-case, without parameters."""
    return request.headers.get("content-type", "").split(";", 1)[0].strip().lower()


async def save_body(request: Request, spill: Path) -> tuple[bytes | None, int, str]:
    """Read the body: (its bytes, or None when it was written to ``spill``; its size [bytes];
    its sha256, hex). A body up to :data:`MEMORY_BODY_BYTES` stays in memory, so a request
    answered from the result cache touches no disk; the size cap is enforced by the
    body-limit middleware."""
    size = 0
    digest = hashlib.sha256()
    held = bytearray()
    out: BinaryIO | None = None
    try:
        async for chunk in request.stream():
            size += len(chunk)
            digest.update(chunk)
            if out is None and size <= MEMORY_BODY_BYTES:
                held += chunk
                continue
            if out is None:
                spill.parent.mkdir(parents=True, exist_ok=True)
                out = spill.open("wb")
                out.write(held)
                held = bytearray()
            out.write(chunk)
    finally:
        if out is not None:
            out.close()
    return (bytes(held) if out is None else None), size, digest.hexdigest()


@dataclass
class Received:
    """A request body that has arrived: an XML document or archive (``body_bytes`` in memory,
    or saved whole as ``body``, with its ``sha256``), or a form already written into a tree
    (``form``). ``cache`` is the form's ``cache`` field when it had one."""

    kind: str
    body: Path | None = None
    body_bytes: bytes | None = None
    sha256: str | None = None
    form: Upload | None = None
    cache: str | None = None


async def receive(
    request: Request, folder: Path, make_tree: Callable[[], UploadTree], raw: RawOptions, root: str | None
) -> Received:
    """Read the body: XML documents and archives are kept whole (in memory, or in ``folder``
    when large; unpacked later by :func:`unpack_received`), forms are read into the tree
    ``make_tree`` makes, with their option fields added to ``raw``."""
    kind = media_type(request)
    if kind in XML_TYPES or kind in ARCHIVE_TYPES:
        spill = folder / "body"
        data, size, digest = await save_body(request, spill)
        if size == 0:
            raise UploadError(
                "empty request body; send a URDF or xacro document (application/xml), "
                "or an archive of the description with its meshes"
            )
        kind = sniffed_type(data[:SNIFF_BYTES] if data is not None else _head(spill), kind)
        return Received(kind, body=spill, body_bytes=data, sha256=digest)
    if kind == MULTIPART:
        form, cache = await _read_form(request, make_tree(), raw, root)
        return Received(kind, form=form, cache=cache)
    shown = kind or "none"
    raise UnsupportedMediaType(f"unsupported Content-Type {shown!r}; use one of {', '.join(SUPPORTED_TYPES)}")


async def unpack_received(
    received: Received, make_tree: Callable[[], UploadTree], raw: RawOptions, root: str | None
) -> Upload:
    """The upload of a received body: a document or archive is written into the tree ``make_tree`` makes."""
    if received.form is not None:
        return received.form
    assert received.body is not None
    tree = make_tree()
    if received.body_bytes is not None:
        await run_in_threadpool(received.body.write_bytes, received.body_bytes)
        received.body_bytes = None
    if received.kind in XML_TYPES:
        root = root or DEFAULT_ROOT
        tree.count_entry(root)
        await run_in_threadpool(_copy_into, tree, root, received.body)
    else:
        await run_in_threadpool(unpack, received.body, received.kind, tree)
    received.body.unlink()
    return Upload(tree, root, raw.one("srdf"))


async def read_upload(request: Request, tree: UploadTree, raw: RawOptions, root: str | None) -> Upload:
    """Fill ``tree`` from the request body; option form fields are added to ``raw``."""
    received = await receive(request, tree.root.parent, lambda: tree, raw, root)
    return await unpack_received(received, lambda: tree, raw, root)


def _head(path: Path) -> bytes:
    with path.open("rb") as fp:
        return fp.read(SNIFF_BYTES)


def _copy_into(tree: UploadTree, name: str, source: Path) -> None:
    with source.open("rb") as fp:
        tree.add_file(name, iter(lambda: fp.read(64 * 1024), b""))


def _copy_part(tree: UploadTree, name: str, part: UploadFile) -> str:
    part.file.seek(0)
    return tree.add_file(name, iter(lambda: part.file.read(64 * 1024), b"")).as_posix()


@dataclass
class _FormFields:
    """What a multipart form's parts name as they are read: the description and SRDF files'
    paths in the tree, ``root`` and ``cache``; option fields go to ``raw``."""

    tree: UploadTree
    raw: RawOptions
    root: str | None
    description: str | None = None
    srdf: str | None = None
    cache: str | None = None

    async def add_file(self, field: str, part: UploadFile) -> None:
        if field not in FILE_FIELDS:
            raise UploadError(f"unknown file field {field!r}; file fields: {', '.join(FILE_FIELDS)}")
        name = part.filename or ("srdf.srdf" if field == "srdf" else DEFAULT_ROOT)
        self.tree.count_entry(name)
        path = await run_in_threadpool(_copy_part, self.tree, name, part)
        if field == "description":
            if self.description is not None:
                raise UploadError("more than one 'description' file; send the others as 'files'")
            self.description = path
        elif field == "srdf":
            self.srdf = path

    def add_text(self, field: str, value: str) -> None:
        if field not in TEXT_FIELDS:
            raise UploadError(f"unknown form field {field!r}; fields: {', '.join((*FILE_FIELDS, *TEXT_FIELDS))}")
        if field == "root":
            if self.root is not None and self.root != value:
                raise UploadError(f"root given twice with different values ({self.root!r}, {value!r})")
            self.root = value
        elif field == "cache":
            self.cache = value
        elif field == "options":
            self.raw.add_json(value)
        else:
            self.raw.add(field, value, "form")

    def upload(self) -> Upload:
        """The upload the form made: an SRDF file part is the ``srdf`` option; a description
        file part is the root, which a ``root`` given as well must name."""
        if self.srdf is not None:
            self.raw.add("srdf", self.srdf, "form")
        root = self.root
        if self.description is not None:
            if root is not None and root.strip("/").removeprefix("./") != self.description:
                raise UploadError(
                    f"root {root!r} differs from the description file {self.description!r}; give one of them"
                )
            root = self.description
        return Upload(self.tree, root, self.raw.one("srdf"))


async def _read_form(
    request: Request, tree: UploadTree, raw: RawOptions, root: str | None
) -> tuple[Upload, str | None]:
    limits = tree.limits
    try:
        form = await request.form(max_files=limits.max_files, max_fields=1000, max_part_size=MAX_FIELD_BYTES)
    except HTTPException as err:
        detail = str(err.detail)
        raise (UploadTooLarge if "Too many" in detail else UploadError)(f"multipart body: {detail}") from None
    fields = _FormFields(tree, raw, root)
    try:
        for field, value in form.multi_items():
            if isinstance(value, UploadFile):
                await fields.add_file(field, value)
            else:
                fields.add_text(field, value)
    finally:
        await form.close()
    return fields.upload(), fields.cache


def discard(folder: Path) -> None:
    shutil.rmtree(folder, ignore_errors=True)
