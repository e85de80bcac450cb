"""Reading a file of a description: a regular file, within a size limit, never anything else.

A FIFO named by a description blocks whoever opens it for reading until a writer comes (for
ever, in a check), and a device (``/dev/zero``, ``/dev/urandom``) never ends: neither is ever
opened. The file is looked at first (``stat``: only a regular file of at most the limit is
opened), opened without blocking, and looked at again through the open descriptor, so a file
swapped for a FIFO between the two is refused too.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from geomcheck.errors import InputError, LimitExceeded

_OPEN_FLAGS = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)


def read_regular_file(path: Path, display: str, max_bytes: int, limit_name: str) -> bytes:
    """The bytes of the regular file ``path`` (``display`` names it in messages).

    :class:`InputError` when it is missing, unreadable or not a regular file (a folder, a FIFO,
    a device, a socket); :class:`LimitExceeded` when it holds more than ``max_bytes`` (the
    limit ``limit_name`` of :class:`geomcheck.thresholds.LoadLimits`)."""
    try:
        found = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"no such file: {display}") from None
    except OSError as err:
        raise InputError(f"cannot read {display}: {err.strerror or err}") from None
    if not stat.S_ISREG(found.st_mode):
        raise InputError(f"not a regular file: {display}")
    if found.st_size > max_bytes:
        raise LimitExceeded(
            f"{display}: file of {found.st_size} bytes exceeds the limit of {max_bytes} bytes ({limit_name})"
        )
    try:
        descriptor = os.open(path, _OPEN_FLAGS)
    except OSError as err:
        raise InputError(f"cannot read {display}: {err.strerror or err}") from None
    with os.fdopen(descriptor, "rb") as handle:
        if not stat.S_ISREG(os.fstat(descriptor).st_mode):  # replaced since it was looked at
            raise InputError(f"not a regular file: {display}")
        try:
            data = handle.read(max_bytes + 1)
        except OSError as err:
            raise InputError(f"cannot read {display}: {err.strerror or err}") from None
    if len(data) > max_bytes:  # the file grew between stat and read
        raise LimitExceeded(f"{display}: file exceeds the limit of {max_bytes} bytes ({limit_name})")
    return data
