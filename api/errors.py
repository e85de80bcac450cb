"""Failures of the service: uploads that cannot be accepted, a full queue.

Like the library's :class:`geomcheck.errors.GeomcheckError` they carry their ``http_status``;
:mod:`api.http.handlers` turns each into ``{"detail": one line}``.
"""

from __future__ import annotations

from geomcheck.errors import GeomcheckError


class UploadError(GeomcheckError):
    """A request body that cannot be accepted as an upload (bad archive, path, field)."""

    http_status = 400


class UploadTooLarge(UploadError):
    """An upload over a size or count limit, or a compression bomb."""

    http_status = 413


class UploadTimeout(UploadError):
    """A request body that did not arrive within the body timeout (a slow or stalled client)."""

    http_status = 408


class UnsupportedMediaType(UploadError):
    http_status = 415


class Overloaded(GeomcheckError):
    """Too many checks are waiting for a worker."""

    http_status = 503


def one_line(text: object, limit: int = 500) -> str:
    """``text`` as a single line of at most ``limit`` characters."""
    line = " ".join(str(text).split())
    return line if len(line) <= limit else line[: limit - 3] + "..."
