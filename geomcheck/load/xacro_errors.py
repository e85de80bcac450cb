"""xacro failures as GC102 findings: xacro's message, cleaned, at the file and line it is about.

xacro reports errors without line numbers; the location is found by searching the files
read for the text the error names (the expression, macro call, include or substitution),
trying the files of the macros being expanded first, then the include stack.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import xacro
import xacro.substitution_args as subst

from geomcheck.errors import GeomcheckError, InputError, LimitExceeded
from geomcheck.load.locations import TextPosition, search_sources
from geomcheck.model import SourceLocation
from geomcheck.rules.structure import XACRO_ERROR


class XacroFailure(Exception):
    """A failure inside one of our xacro hooks: becomes GC102 with this message.

    ``pattern`` finds the offending text in the sources for the location.
    """

    def __init__(self, message: str, pattern: re.Pattern[str] | None = None) -> None:
        super().__init__(message)
        self.pattern = pattern


def _inner(err: BaseException) -> BaseException:
    """The exception xacro wrapped (it wraps ours in XacroException, sometimes twice)."""
    current: BaseException = err
    for _ in range(16):
        nested = getattr(current, "exc", None)
        if isinstance(nested, BaseException) and isinstance(current, xacro.XacroException):
            if isinstance(nested, GeomcheckError | XacroFailure | RecursionError):
                return nested
            current = nested
            continue
        break
    return err


def _patterns(err: BaseException, inner: BaseException, macro_names: list[str]) -> list[re.Pattern[str]]:
    """Patterns that find the text an xacro error is about, most specific first."""
    text = str(err)
    out: list[re.Pattern[str]] = []
    if isinstance(inner, XacroFailure) and inner.pattern is not None:
        out.append(inner.pattern)
    ends = r"(?=\s*$|\s+when evaluating|\s*\n)"
    for expression in re.findall(rf"when evaluating expression '(.*?)'{ends}", text, re.S):
        out.append(re.compile(re.escape("${" + expression.strip() + "}")))
    for name in re.findall(r"name '(\w+)' is not defined", text):
        out.append(re.compile(rf"\$[{{(][^}})]*\b{re.escape(name)}\b"))
    if isinstance(inner, subst.ArgException) or "Undefined substitution argument" in text:
        name = str(getattr(err, "exc", "") or "").strip() or text.rsplit(" ", 1)[-1]
        out.append(re.compile(rf"\$\(arg\s+{re.escape(name)}\s*\)"))
    unknown = re.search(r"unknown macro name: (?:xacro:)?([\w.]+)", text)
    if unknown:
        out.append(re.compile(rf"<(?:xacro:)?{re.escape(unknown.group(1))}[\s/>]"))
    for command, argument in re.findall(r"\$\((\w+)\s+([^)\s]+)", f"{text} {inner}"):
        out.append(re.compile(rf"\$\({re.escape(command)}\s+{re.escape(argument)}"))
    condition = re.search(r'Xacro conditional "(.*?)" evaluated', text)
    if condition:
        out.append(re.compile(rf"value\s*=\s*[\"']{re.escape(condition.group(1))}[\"']"))
    block = re.search(r'Undefined block "(\w+)"', text)
    if block:
        out.append(re.compile(rf"insert_block\s+name\s*=\s*[\"']{re.escape(block.group(1))}[\"']"))
    missing = re.search(r"(?:No such file or directory|bundle refused): (\S+)", f"{text} {inner}")
    if missing:
        out.append(re.compile(rf"filename\s*=\s*[\"'][^\"']*{re.escape(Path(missing.group(1)).name)}[\"']"))
    for name in macro_names:
        out.append(re.compile(rf"<(?:xacro:)?{re.escape(name)}[\s/>]"))
    return out


def _macro_names(err: BaseException, stack: list[Any]) -> list[str]:
    names: list[str] = []
    for macro in [*getattr(err, "macros", []), *reversed(stack)]:
        body = getattr(macro, "body", None)
        if body is not None and body.getAttribute("name"):
            names.append(body.getAttribute("name"))
    return list(dict.fromkeys(names))


def _error_location(
    err: BaseException, inner: BaseException, sources: Mapping[str, str], display: Callable[[str], str], root: str
) -> SourceLocation:
    """Best-effort file and line of an xacro failure (inside macros: the macro's file first)."""
    macro_stack = list(xacro.macrostack or [])
    file_stack = [f for f in (xacro.filestack or []) if f]
    files = [display(m.history[-1][-1]) for m in reversed(macro_stack) if m.history and m.history[-1][-1]] + [
        display(f) for f in reversed(file_stack)
    ]
    found: TextPosition | None = search_sources(sources, _patterns(err, inner, _macro_names(err, macro_stack)), files)
    if found is not None:
        return SourceLocation(found.file, found.line, found.column)
    return SourceLocation(files[0] if files else root)


def _xacro_message(err: BaseException) -> str:
    """xacro's message for ``err`` without the repetitions and ``<class ...>`` noise it adds."""
    if not isinstance(err, xacro.XacroException):
        return f"{type(err).__name__}: {err}"
    own = Exception.__str__(err)
    nested = "" if err.exc is None else str(err.exc)
    parts = [own, "" if own.endswith(f": {nested}") else nested, "" if err.suffix is None else str(err.suffix)]
    text = " ".join(p for p in parts if p and p != "None")
    text = re.sub(r"<class '(?:[\w.]+\.)?(\w+)'>", r"\1", text)
    return text or type(err).__name__


def failure(
    err: BaseException,
    sources: Mapping[str, str],
    display: Callable[[str], str],
    root: str,
    scrub: Callable[[str], str] = str,
) -> GeomcheckError:
    """The :class:`InputError` (GC102) an exception raised during expansion becomes.

    Called while xacro's file and macro stacks still hold the state at the failure;
    ``sources`` are the files read so far, ``display`` maps paths to display names,
    ``root`` is the display name of the root file and ``scrub`` removes the machine's
    folders from the message (of a confined bundle).
    """
    inner = _inner(err)
    if isinstance(inner, GeomcheckError) and getattr(inner, "diagnostic", None) is not None:
        return inner
    location = _error_location(err, inner, sources, display, root)
    if isinstance(inner, RecursionError):
        inner = LimitExceeded("xacro recursion too deep (recursive macro or property?)")
    reason = str(inner) if isinstance(inner, GeomcheckError | XacroFailure) else _xacro_message(err)
    macros = _macro_names(err, list(xacro.macrostack or []))
    if macros:
        reason += f" (in macro {macros[0]})"
    reason = scrub(" ".join(reason.split()))
    diagnostic = XACRO_ERROR.diagnose(reason, location=location, data={"macros": macros})
    message = f"{location}: {XACRO_ERROR.code} {XACRO_ERROR.name}: {reason}"
    cls = type(inner) if isinstance(inner, InputError) else InputError
    return cls(message, diagnostic)
