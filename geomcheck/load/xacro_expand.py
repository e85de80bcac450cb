"""xacro expansion in process with the real ``xacro`` library, without a ROS install.

xacro keeps its state in module globals (file and macro stacks, substitution arguments,
included files, the expression symbols). :func:`expand` runs one expansion under a lock with
those globals replaced by fresh ones and its hooks installed, and restores everything
afterwards, so one call never leaks into the next:

* every file (root, includes, YAML) is read through the hardened parser, inside the
  bundle's sandbox when it is confined, and legacy syntax is rewritten in memory;
* ``$(find pkg)`` resolves through the bundle's package map, ``$(arg)`` from ``args``;
* ``$(env)``/``$(optenv)`` take the values the user gave (``Bundle.env``); confined bundles
  read no other variable (``$(optenv)`` takes its default, ``$(env)`` is refused) and evaluate
  expressions with the sandbox of :mod:`geomcheck.load.xacro_eval`; every bundle evaluates them with its work
  budget (no expression runs for hours);
* macro nesting and the number of macro calls are limited;
* every non-xacro element is tagged with the file and line it was read from, so the
  elements of the expanded document can be traced back to their source.
"""

from __future__ import annotations

import contextlib
import re
import threading
import types
import xml.dom.minidom
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

import xacro
import xacro.substitution_args as subst

from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import LimitExceeded
from geomcheck.load.bundle import Bundle
from geomcheck.load.xacro_errors import failure
from geomcheck.load.xacro_files import ORIGIN_KEY, dom_elements
from geomcheck.load.xacro_substitutions import XacroSubstitutions
from geomcheck.model import SourceLocation
from geomcheck.rules.structure import XACRO_WARNING
from geomcheck.thresholds import LoadLimits

_LOCK = threading.RLock()
# xacro's and its substitutions' module globals an expansion replaces, restored after it
XACRO_GLOBALS = (
    "parse",
    "handle_macro_call",
    "safe_eval",
    "_global_symbols",
    "substitution_args_context",
    "all_includes",
    "filestack",
    "macrostack",
    "verbosity",
    "warning",
    "error",
    "message",
    "print_location",
    "glob",
    "eval_extension",
    "eval_all",
    "eval_text",
    "replace_node",
    "root_dir",
)
SUBSTITUTION_GLOBALS = ("_eval_find", "_eval_env", "_eval_optenv", "_eval")


@dataclass(frozen=True)
class Expansion:
    """The result of expanding one xacro document.

    ``origins`` holds, per element of ``text`` in document order, the ``(display file,
    line)`` it was read from, or ``None`` when xacro created it. What the result depends on,
    for caches: ``files_read`` maps every file the expansion opened or looked for (absolute
    path) to the sha256 of its bytes (``None``: it did not exist), ``packages_found`` every
    ``$(find)`` to its folder, ``location`` the folder ``$(cwd)`` gave when it was read (the
    result holds in that folder only); ``volatile`` says why the result depends on more than
    that (``$(env)``, a glob include), ``None`` when it does not.
    """

    text: str
    sources: Mapping[str, str]
    origins: list[tuple[str, int] | None]
    diagnostics: tuple[Diagnostic, ...]
    files_read: Mapping[str, str | None] = field(default_factory=dict)
    packages_found: Mapping[str, str] = field(default_factory=dict)
    volatile: str | None = None
    location: str | None = None


class _Session(XacroSubstitutions):
    """State and hooks of one expansion."""

    def __init__(self, bundle: Bundle, args: Mapping[str, str], limits: LoadLimits) -> None:
        super().__init__(bundle, limits)
        self.args = dict(args)

    # installation ----------------------------------------------------------------------

    @contextlib.contextmanager
    def installed(self) -> Iterator[None]:
        """xacro's globals replaced by this session's, restored on exit."""
        saved_xacro = {name: getattr(xacro, name) for name in XACRO_GLOBALS}
        saved_subst = {name: getattr(subst, name) for name in SUBSTITUTION_GLOBALS}
        saved_eval_dict = dict(subst._eval_dict)
        try:
            self.install()
            yield
        finally:
            for name, value in saved_xacro.items():
                setattr(xacro, name, value)
            for name, value in saved_subst.items():
                setattr(subst, name, value)
            subst._eval_dict.clear()
            subst._eval_dict.update(saved_eval_dict)

    def install(self) -> None:
        """Put this session's hooks and fresh state into xacro's globals."""
        for name, function in self.message_functions().items():
            function.__name__ = name  # xacro's message adapter keys on the name
            setattr(xacro, name, function)
        xacro.parse = self.parse
        xacro.handle_macro_call = self.handle_macro_call
        xacro.eval_all = self.eval_all
        xacro.eval_text = self.eval_text
        xacro.replace_node = self.replace_node
        xacro.glob = types.SimpleNamespace(glob=self.glob)  # type: ignore[assignment]
        xacro.eval_extension = self.eval_extension
        xacro.substitution_args_context = {}
        xacro.all_includes = []
        xacro.verbosity = 1
        xacro._global_symbols = self.global_symbols()
        subst._eval_find = self.find
        subst._eval_env = self.env
        subst._eval_optenv = self.optenv
        subst._eval_dict.update(find=self.find, env=self.env, optenv=self.optenv)
        if self.bundle.confined:
            xacro.safe_eval = self.safe_eval
            subst._eval = self.substitution_eval
            xacro.root_dir = str(self.bundle.display_root)  # $(cwd): the upload, not the server's folder
        else:
            xacro.safe_eval = self.budgeted_eval
            subst._eval = self.budgeted_substitution_eval

    # the run ---------------------------------------------------------------------------

    def run(self) -> Expansion:
        root = self.bundle.root_file
        root_display = self.display(root)
        xacro.init_stacks(str(root))
        doc = self.parse(None, str(root))
        xacro.process_doc(doc, mappings=dict(self.args), verbosity=1)
        origins = self.collect_origins(doc)
        banner = [
            xml.dom.minidom.Comment(c)
            for c in [
                f" {'=' * 83} ",
                f" |    This document was autogenerated by xacro from {re.sub(r'-+', '-', root_display):<30} | ",
                f" |    EDITING THIS FILE BY HAND IS NOT RECOMMENDED  {'':<30} | ",
                f" {'=' * 83} ",
            ]
        ]
        first = doc.firstChild
        for comment in banner:
            doc.insertBefore(comment, first)
        # $(find pkg), $(cwd) and xacro.abs_filename() give absolute paths: those of a confined
        # bundle are written relative to the root file's folder, as URDF reads relative filenames
        text = self.bundle.scrub(doc.toprettyxml(indent="  "), self.bundle.root_file.parent)
        if len(text) > self.limits.max_expanded_bytes:
            raise LimitExceeded(
                f"xacro output of {len(text)} bytes exceeds the limit of {self.limits.max_expanded_bytes} bytes"
            )
        return Expansion(
            text,
            dict(self.sources),
            origins,
            tuple(self.diagnostics()),
            files_read=dict(self.files_read),
            packages_found=dict(self.packages_found),
            volatile=self.volatile,
            location=self.location,
        )

    def collect_origins(self, doc: xml.dom.minidom.Document) -> list[tuple[str, int] | None]:
        """Per element of the expanded document, the (file, line) it was read from."""
        return [element.getUserData(ORIGIN_KEY) for element in dom_elements(doc.documentElement)]

    def diagnostics(self) -> list[Diagnostic]:
        out = [use.diagnostic(self.called_macros) for use in self.legacy.values() if use.found]
        seen: set[tuple[str, str]] = set()
        for file, text in self.warnings:
            if (file, text) in seen:
                continue
            seen.add((file, text))
            out.append(
                XACRO_WARNING.diagnose(
                    f"xacro: {' '.join(text.split())}",
                    about=f"{self.bundle.identity(file)}: {text}",
                    location=SourceLocation(file),
                    data={"file": file},
                )
            )
        return out


def expand(bundle: Bundle, args: Mapping[str, str], limits: LoadLimits) -> Expansion:
    """Expand the bundle's root xacro file.

    Raises :class:`InputError` with a GC101 (malformed file) or GC102 (xacro failure)
    diagnostic, :class:`LimitExceeded` or :class:`SandboxViolation`.
    """
    with _LOCK:
        session = _Session(bundle, args, limits)
        with session.installed():
            try:
                return session.run()
            except Exception as err:  # xacro raises many kinds: all become GC102 (ours pass through)
                root = session.display(bundle.root_file)
                raise failure(err, session.sources, session.display, root, bundle.scrub) from None


__all__ = ["Expansion", "expand"]
