"""Tool failures.

Findings about a description are diagnostics (data); a failure of the tool to do what was
asked is an exception. Every exception the library raises on purpose is a
:class:`GeomcheckError`: the CLI turns it into a one-line message and exit code 2, the
HTTP service into a 4xx answer.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from geomcheck.diagnostics import Diagnostic


class GeomcheckError(Exception):
    """Base class of every deliberate tool failure; ``str(err)`` is one line."""

    exit_code: int = 2
    http_status: int = 400


class UsageError(GeomcheckError):
    """A bad option, argument or configuration value."""

    http_status = 400

    @classmethod
    def bad_choice(cls, what: str, value: object, choices: Iterable[object]) -> UsageError:
        """Error naming the bad ``value`` of ``what`` and the valid ``choices``."""
        valid = ", ".join(str(c) for c in choices)
        return cls(f"invalid {what} {value!r}; valid choices: {valid}")


class InputError(GeomcheckError):
    """The description cannot be read: missing file, malformed XML, xacro failure.

    ``diagnostic`` carries the GC1xx/GC2xx finding when the failure is one a rule names
    (malformed XML is GC101), so reports and one-line messages agree.
    """

    http_status = 422

    def __init__(self, message: str, diagnostic: Diagnostic | None = None) -> None:
        super().__init__(message)
        self.diagnostic = diagnostic


class LimitExceeded(InputError):
    """An input is larger or deeper than a configured limit (size, count, depth, time)."""

    http_status = 413


class SandboxViolation(InputError):
    """An uploaded description tried to reach outside its bundle or into the interpreter."""

    http_status = 422


__all__ = ["GeomcheckError", "InputError", "LimitExceeded", "SandboxViolation", "UsageError"]
