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
from dataclasses import dataclass
from pathlib import Path

from fastapi import Request
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import UploadFile
from starlette.exceptions import HTTPException

from api.archives import ARCHIVE_TYPES, unpack
from api.errors import UnsupportedMediaType, UploadError, UploadTooLarge
from api.options import OPTION_NAMES, RawOptions
from api.tree import UploadTree

XML_TYPES = frozenset({"application/xml", "text/xml"})
MULTIPART = "multipart/form-data"
SUPPORTED_TYPES = (*sorted(XML_TYPES), MULTIPART, *sorted(ARCHIVE_TYPES))
DEFAULT_ROOT = "robot.urdf"
FILE_FIELDS = ("description", "files", "srdf")
TEXT_FIELDS = ("root", "cache", "options", *OPTION_NAMES)
MAX_FIELD_BYTES = 64 * 1024  # one non-file form field [bytes]


@dataclass
class Upload:
    """What a request brought: files written into ``tree``, the root file and SRDF paths it named."""

    tree: UploadTree
    root: str | None
    srdf: str | None


def media_type(request: Request) -> str:
    """The request's media type, lower-case, without parameters."""
    return request.headers.get("content-type", "").split(";", 1)[0].strip().lower()


async def save_body(request: Request, target: Path) -> tuple[int, str]:
    """Stream the body into ``target``; returns its size [bytes] and sha256 (hex). The size cap
    is enforced by the body-limit middleware."""
    size = 0
    digest = hashlib.sha256()
    with target.open("wb") as out:
        async for chunk in request.stream():
            size += len(chunk)
            digest.update(chunk)
            out.write(chunk)
    return size, digest.hexdigest()


@dataclass
class Received:
    """A request body that has arrived: an XML document or archive saved whole as ``body``
    (with its ``sha256``), or a form already written into the tree (``form``). ``cache`` is
    the form's ``cache`` field when it had one."""

    kind: str
    body: Path | None = None
    sha256: str | None = None
    form: Upload | None = None
    cache: str | None = None


async def receive(request: Request, tree: UploadTree, raw: RawOptions, root: str | None) -> Received:
    """Read the body: XML documents and archives are saved whole next to ``tree`` (unpacked
    later by :func:`unpack_received`), forms are read into ``tree`` with their option fields
    added to ``raw``."""
    kind = media_type(request)
    if kind in XML_TYPES or kind in ARCHIVE_TYPES:
        body = tree.root.parent / ("body.xml" if kind in XML_TYPES else "body.archive")
        size, digest = await save_body(request, body)
        if size == 0 and kind in ARCHIVE_TYPES:
            raise UploadError("empty request body; send the archive")
        return Received(kind, body=body, sha256=digest)
    if kind == MULTIPART:
        form, cache = await _read_form(request, tree, raw, root)
        return Received(kind, form=form, cache=cache)
    shown = kind or "none"
    raise UnsupportedMediaType(f"unsupported Content-Type {shown!r}; use one of {', '.join(SUPPORTED_TYPES)}")


async def unpack_received(received: Received, tree: UploadTree, raw: RawOptions, root: str | None) -> Upload:
    """The upload of a received body: a saved document or archive is written into ``tree``."""
    if received.form is not None:
        return received.form
    assert received.body is not None
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
    return await unpack_received(await receive(request, tree, raw, root), tree, raw, root)


def _copy_into(tree: UploadTree, name: str, source: Path) -> None:
    with source.open("rb") as fp:
        tree.add_file(name, iter(lambda: fp.read(64 * 1024), b""))


def _copy_part(tree: UploadTree, name: str, part: UploadFile) -> str:
    part.file.seek(0)
    return tree.add_file(name, iter(lambda: part.file.read(64 * 1024), b"")).as_posix()


async def _read_form(
    request: Request, tree: UploadTree, raw: RawOptions, root: str | None
) -> tuple[Upload, str | None]:
    limits = tree.limits
    try:
        form = await request.form(max_files=limits.max_files, max_fields=1000, max_part_size=MAX_FIELD_BYTES)
    except HTTPException as err:
        detail = str(err.detail)
        raise (UploadTooLarge if "Too many" in detail else UploadError)(f"multipart body: {detail}") from None
    try:
        description: str | None = None
        srdf: str | None = None
        cache: str | None = None
        for field, value in form.multi_items():
            if isinstance(value, UploadFile):
                if field not in FILE_FIELDS:
                    raise UploadError(f"unknown file field {field!r}; file fields: {', '.join(FILE_FIELDS)}")
                name = value.filename or ("srdf.srdf" if field == "srdf" else DEFAULT_ROOT)
                tree.count_entry(name)
                path = await run_in_threadpool(_copy_part, tree, name, value)
                if field == "description":
                    if description is not None:
                        raise UploadError("more than one 'description' file; send the others as 'files'")
                    description = path
                elif field == "srdf":
                    srdf = path
                continue
            if field not in TEXT_FIELDS:
                raise UploadError(f"unknown form field {field!r}; fields: {', '.join((*FILE_FIELDS, *TEXT_FIELDS))}")
            if field == "root":
                if root is not None and root != value:
                    raise UploadError(f"root given twice with different values ({root!r}, {value!r})")
                root = value
            elif field == "cache":
                cache = value
            elif field == "options":
                raw.add_json(value)
            elif field == "srdf":
                raw.add("srdf", value, "form")
            else:
                raw.add(field, value, "form")
    finally:
        await form.close()
    if srdf is not None:
        raw.add("srdf", srdf, "form")
    if description is not None:
        if root is not None and root.strip("/").removeprefix("./") != description:
            raise UploadError(f"root {root!r} differs from the description file {description!r}; give one of them")
        root = description
    return Upload(tree, root, raw.one("srdf")), cache


def discard(folder: Path) -> None:
    shutil.rmtree(folder, ignore_errors=True)
