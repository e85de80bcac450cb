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
import errno
import glob as globmodule
import hashlib
import re
import sys
import threading
import types
import xml.dom
import xml.dom.minidom
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import xacro
import xacro.substitution_args as subst
from lxml import etree

from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError, LimitExceeded, SandboxViolation
from geomcheck.load.bundle import ENV_EVENT, LOCATION_EVENT, VOLATILE_EVENT, Bundle
from geomcheck.load.legacy import (
    MACRO_CALL,
    UNBOUND_PREFIX_NOTE,
    LegacyUse,
    declare_xacro_namespace,
    enclosing_macro,
    legacy_tag,
    namespace_problem,
)
from geomcheck.load.locations import search_sources
from geomcheck.load.urdf_spec import SPEC
from geomcheck.load.xacro_errors import XacroFailure, failure
from geomcheck.load.xacro_eval import (
    DENIED_SYMBOLS,
    GUARD_NAME,
    bounded_range,
    compile_budgeted,
    compile_guarded,
    make_guard,
)
from geomcheck.load.xmlsafe import decode_text, parse_bytes, read_file_bytes
from geomcheck.model import SourceLocation
from geomcheck.rules.structure import XACRO_WARNING
from geomcheck.thresholds import LoadLimits

ORIGIN_KEY = "geomcheck.origin"
# Elements a bare (legacy) macro call may never be mistaken for.
URDF_CORE_TAGS = frozenset({*SPEC, "gazebo", "transmission"})

_LOCK = threading.RLock()


class _OriginHandler:
    """Carries an element's origin over to its copies (xacro clones macro bodies and blocks)."""

    def handle(self, operation: int, key: str, data: Any, src: Any, dst: Any) -> None:
        if dst is not None and operation in (
            xml.dom.UserDataHandler.NODE_CLONED,
            xml.dom.UserDataHandler.NODE_IMPORTED,
        ):
            dst.setUserData(key, data, self)


_ORIGIN_HANDLER = _OriginHandler()


class _MissingInclude(FileNotFoundError):
    """An include that does not exist (an ``IOError`` so ``optional="true"`` includes work)."""

    def __str__(self) -> str:  # xacro appends str(exc) to its own message
        return ""


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


def _dom_elements(node: xml.dom.minidom.Node | None) -> Iterator[xml.dom.minidom.Element]:
    """Elements under ``node`` (itself included) in document order."""
    stack = [node] if node is not None else []
    while stack:
        current = stack.pop()
        if current.nodeType == xml.dom.Node.ELEMENT_NODE:
            yield current  # type: ignore[misc]
        stack.extend(reversed(current.childNodes))


class _Session:
    """State and hooks of one expansion."""

    def __init__(self, bundle: Bundle, args: Mapping[str, str], limits: LoadLimits) -> None:
        self.bundle = bundle
        self.args = dict(args)
        self.limits = limits
        self.sources: dict[str, str] = {}
        self.displayed: dict[str, str] = {}  # display path of each path asked about
        self.legacy: dict[str, LegacyUse] = {}
        self.warnings: list[tuple[str, str]] = []
        self.macro_calls = 0
        self.called_macros: set[str] = set()  # names of the macros called (without include namespaces)
        self.files_read: dict[str, str | None] = {}
        self.packages_found: dict[str, str] = {}
        self.volatile: str | None = None
        self.location: str | None = None  # the folder $(cwd) gave
        self.guard = make_guard(limits.max_expanded_bytes, limits.max_expression_work)
        self.evaluated = 0
        self.sibling_work = 0
        self.original_eval_all: Callable[..., None] = xacro.eval_all
        self.original_eval_text: Callable[..., Any] = xacro.eval_text
        self.original_replace_node: Callable[..., None] = xacro.replace_node
        self.original_parse: Callable[..., Any] = xacro.parse
        self.original_handle_macro_call: Callable[..., bool] = xacro.handle_macro_call
        self.original_env: Callable[..., str] = subst._eval_env
        self.original_optenv: Callable[..., str] = subst._eval_optenv
        self.original_eval_extension: Callable[..., Any] = xacro.eval_extension

    # files -----------------------------------------------------------------------------

    def display(self, path: str | Path) -> str:
        key = str(path)
        shown = self.displayed.get(key)
        if shown is None:
            shown = self.displayed[key] = self.bundle.display(Path(path))
        return shown

    def current_file(self) -> str:
        stack = xacro.filestack or []
        return self.display(stack[-1]) if stack and stack[-1] else self.display(self.bundle.root_file)

    def read(self, path: Path) -> tuple[bytes, str]:
        """Bytes and display name of ``path``, checked against the sandbox and the size limit."""
        display = self.display(path)
        resolved = self.bundle.check_access(path)
        if not resolved.is_file():
            self.files_read.setdefault(str(resolved), None)
            raise _MissingInclude(errno.ENOENT, "No such file or directory", display)
        data = read_file_bytes(resolved, display, self.limits)
        self.files_read[str(resolved)] = hashlib.sha256(data).hexdigest()
        self.sources.setdefault(display, decode_text(data))
        return data, display

    def parse(self, inp: Any, filename: str | None = None) -> xml.dom.minidom.Document:
        """Replacement of ``xacro.parse``: hardened, sandboxed, legacy-aware, origin-tagging."""
        if inp is not None or filename is None:
            return self.original_parse(inp, filename)
        if len(xacro.filestack or []) > self.limits.max_include_depth + 1:
            raise LimitExceeded(
                f"xacro includes nest deeper than the limit of {self.limits.max_include_depth} levels "
                f"(recursive include of {self.display(filename)}?)"
            )
        path = Path(filename).absolute()
        try:
            data, display = self.read(path)
        except SandboxViolation:
            xacro.filestack.pop()  # the includer is the file in error
            raise
        except _MissingInclude as missing:
            xacro.filestack.pop()  # as xacro does: the includer is the file in error
            raise xacro.XacroException(f"No such file or directory: {self.display(path)}", exc=missing) from None
        first_read = display not in self.legacy
        root, data = self.parse_lxml(data, display)
        try:
            doc = xml.dom.minidom.parseString(data)
        except Exception as err:  # expat disagrees with lxml: report it as malformed
            raise InputError(f"{display}: GC101 malformed-xml: {err}") from None
        self.prepare(doc, root, display, first_read)
        return doc

    def parse_lxml(self, data: bytes, display: str) -> tuple[etree._Element, bytes]:
        try:
            return parse_bytes(data, display, self.limits), data
        except InputError as err:
            if "Namespace prefix xacro" not in str(err):
                raise
            fixed = declare_xacro_namespace(data)
            if fixed is None:
                raise
            root = parse_bytes(fixed, display, self.limits)
            self.legacy_use(display).namespace_note = UNBOUND_PREFIX_NOTE
            return root, fixed

    def legacy_use(self, display: str) -> LegacyUse:
        return self.legacy.setdefault(display, LegacyUse(display, self.bundle.identity(display)))

    def prepare(self, doc: xml.dom.minidom.Document, root: etree._Element, display: str, first_read: bool) -> None:
        """Rewrite legacy tags to ``xacro:`` and tag every other element with its origin.

        Legacy tags are counted on the ``first_read`` of a file only (files are often included
        several times)."""
        use = self.legacy_use(display)
        parsed = [e for e in root.iter() if isinstance(e.tag, str)]
        built = list(_dom_elements(doc.documentElement))
        if len(parsed) != len(built):  # cannot happen for documents both parsers accept
            return
        uses_xacro = False
        for lx, dom in zip(parsed, built, strict=True):
            tag = legacy_tag(lx)
            if tag is not None:
                dom.tagName = dom.nodeName = f"xacro:{tag}"
                uses_xacro = True
                if first_read:  # a file included several times is counted once
                    use.add(tag, lx.sourceline, enclosing_macro(lx))
            elif dom.tagName.startswith("xacro:"):
                uses_xacro = True
            else:
                dom.setUserData(ORIGIN_KEY, (display, lx.sourceline), _ORIGIN_HANDLER)
        # a plain URDF that merely declares the prefix (often with a wrong URI) is not legacy
        note = namespace_problem(root) if uses_xacro else None
        if note is not None:
            use.namespace_note = note
        if use.tags and "xacro" not in root.nsmap and use.namespace_note is None:
            use.namespace_note = "no xmlns:xacro declaration"

    # macros ----------------------------------------------------------------------------

    def eval_all(self, node: xml.dom.minidom.Node, macros: Any, symbols: Any) -> None:
        """Replacement of ``xacro.eval_all`` counting the elements evaluated: blocks inserted
        into blocks double without a macro call, so only this count bounds them."""
        self.evaluated += 1
        if self.evaluated > self.limits.max_xacro_elements:
            raise LimitExceeded(
                f"xacro evaluates more than {self.limits.max_xacro_elements} elements (max_xacro_elements): "
                "blocks inserted into blocks?"
            )
        self.original_eval_all(node, macros, symbols)

    def eval_text(self, text: str, symbols: Any) -> Any:
        """Replacement of ``xacro.eval_text`` holding each text's value to the expanded-size
        limit: ``value="${p}${p}"`` doubles outside any expression, 40 properties deep 2^40
        characters."""
        value = self.original_eval_text(text, symbols)
        if isinstance(value, str) and len(value) > self.limits.max_expanded_bytes:
            raise LimitExceeded(
                f"a xacro text evaluates to {len(value)} characters, beyond max_expanded_bytes "
                f"({self.limits.max_expanded_bytes})"
            )
        return value

    def replace_node(self, node: xml.dom.minidom.Node, by: Any, content_only: bool = False) -> None:
        """Replacement of ``xacro.replace_node`` counting the siblings minidom passes over
        (each insertion searches the parent's children): a block doubled into one parent
        costs the square of its size."""
        parent = node.parentNode
        if by is not None and parent is not None:
            moved = len(by) if isinstance(by, list) else len(by.childNodes) if content_only else 1
            self.sibling_work += moved * len(parent.childNodes)
            if self.sibling_work > self.limits.max_sibling_work:
                raise LimitExceeded(
                    f"xacro insertions exceed the work limit of {self.limits.max_sibling_work} steps "
                    "(max_sibling_work): a block doubled into one element?"
                )
        self.original_replace_node(node, by, content_only)

    def handle_macro_call(self, node: xml.dom.minidom.Element, macros: Any, symbols: Any) -> bool:
        """Replacement of ``xacro.handle_macro_call``: bare legacy calls, depth and count limits."""
        tag = node.tagName
        if not tag.startswith("xacro:"):
            if not self.bare_macro_call(node, macros, symbols):
                return False
            self.called_macros.add(tag.rsplit(".", 1)[-1])
        elif tag == "xacro:call":
            self.called_macros.add((node.getAttribute("macro") or "").rsplit(".", 1)[-1])
        else:
            self.called_macros.add(tag[6:].rsplit(".", 1)[-1])
            self.macro_calls += 1
            if self.macro_calls > self.limits.max_macro_calls:
                raise LimitExceeded(
                    f"more than {self.limits.max_macro_calls} macro calls (max_macro_calls): exponential expansion?"
                )
            if len(xacro.macrostack or []) >= self.limits.max_macro_depth:
                raise LimitExceeded(
                    f"macro {tag[6:]!r} nests deeper than the limit of {self.limits.max_macro_depth} levels "
                    "(recursive macro?)"
                )
        return self.original_handle_macro_call(node, macros, symbols)

    def bare_macro_call(self, node: xml.dom.minidom.Element, macros: Any, symbols: Any) -> bool:
        """Turn ``<name ...>`` into ``<xacro:name ...>`` when it calls a macro from a legacy file."""
        tag = node.tagName
        if ":" in tag or tag in URDF_CORE_TAGS:
            return False
        stack = xacro.macrostack or []
        defined_in = stack[-1].history[-1][-1] if stack and stack[-1].history else None
        display = self.display(defined_in) if defined_in else self.current_file()
        use = self.legacy.get(display)
        if use is None or not use.found:
            return False
        try:
            xacro.resolve_macro(tag, macros, symbols)
        except (KeyError, TypeError, AttributeError):
            return False
        node.tagName = node.nodeName = f"xacro:{tag}"
        found = search_sources({display: self.sources.get(display, "")}, [re.compile(rf"<{re.escape(tag)}[\s/>]")])
        use.add(MACRO_CALL, found.line if found else None)
        return True

    # substitutions and expressions -----------------------------------------------------

    def find(self, package: str) -> str:
        directory = self.bundle.package_dir(package)
        if directory is None:
            known = ", ".join(self.bundle.packages) or "none"
            raise XacroFailure(
                f"package {package!r} not found (known packages: {known}); {self.bundle.package_advice(package)}",
                re.compile(rf"\$\(find\s+{re.escape(package)}\s*\)"),
            )
        found = str(self.bundle.check_access(directory))
        self.packages_found[package] = found
        return found

    def env(self, name: str) -> str:
        """``$(env NAME)``: the value the user gave, else the environment's (only the names
        ``allowed_env`` lists when confined: an upload never reads the server's variables)."""
        given = self.bundle.env.get(name)
        if given is not None:
            return given
        if self.bundle.confined and name not in self.bundle.allowed_env:
            raise SandboxViolation(
                f"$(env {name}) is refused in untrusted descriptions (they read no environment variable): "
                f"{self.bundle.env_advice(name)}"
            )
        self.volatile = f"$(env {name})"
        sys.audit(ENV_EVENT, name)
        return self.original_env(name)

    def optenv(self, name: str, default: str = "") -> str:
        """``$(optenv NAME default)``: the value the user gave, else, when confined, the default
        (what a fresh machine expands, with no environment read), else the environment's."""
        given = self.bundle.env.get(name)
        if given is not None:
            return given
        if self.bundle.confined and name not in self.bundle.allowed_env:
            return default
        self.volatile = f"$(optenv {name})"
        sys.audit(ENV_EVENT, name)
        return self.original_optenv(name, default)

    def eval_extension(self, text: str) -> Any:
        """xacro's ``$(...)``, telling the caches when it reads the folder it runs in (``$(cwd)``)."""
        if text == "$(cwd)":
            self.location = self.bundle.working_folder()
            sys.audit(LOCATION_EVENT, self.location)
        return self.original_eval_extension(text)

    def glob(self, pattern: str) -> list[str]:
        """xacro's include globbing: its matches change when files appear, so the result is volatile."""
        self.volatile = f"include pattern {self.display(pattern)}"
        sys.audit(VOLATILE_EVENT, self.volatile)
        if not self.bundle.confined:
            return globmodule.glob(pattern)
        return confined_glob(self.bundle, pattern, self.display(pattern))

    def safe_eval(self, expr: str, globals: Any, locals: Any = None) -> Any:
        """Replacement of ``xacro.safe_eval`` for confined bundles."""
        code = compile_guarded(expr)
        dict.update(globals, {"__builtins__": {}, GUARD_NAME: self.guard})
        return eval(code, globals, locals)

    def substitution_eval(self, expression: str, context: dict[str, Any]) -> str:
        """Replacement of ``$(eval ...)`` for confined bundles (xacro's own keeps Python's builtins)."""
        args = context.setdefault("arg", {})
        functions: dict[str, Any] = {k: v for k, v in subst._eval_dict.items() if k != "__builtins__"}
        functions.update(
            arg=lambda name: subst.convert_value(subst._eval_arg(name, args), "auto"),
            env=self.env,
            optenv=self.optenv,
            find=self.find,
        )
        code = compile_guarded(expression)
        scope = subst._DictWrapper(args, functions)
        return str(eval(code, {"__builtins__": {}, GUARD_NAME: self.guard}, scope))  # type: ignore[arg-type]

    def budgeted_eval(self, expr: str, globals: Any, locals: Any = None) -> Any:
        """Replacement of ``xacro.safe_eval`` for trusted bundles: xacro's rules (no name
        starting with ``__``, no builtins) with the work budget."""
        code = compile_budgeted(expr)
        invalid = [n for n in code.co_names if n.startswith("__") and n != GUARD_NAME]
        if invalid:
            raise xacro.XacroException("Use of invalid name(s): ", ", ".join(invalid))
        dict.update(globals, {"__builtins__": {}, GUARD_NAME: self.guard})
        return eval(code, globals, locals)

    def budgeted_substitution_eval(self, expression: str, context: dict[str, Any]) -> str:
        """Replacement of ``$(eval ...)`` for trusted bundles: xacro's (Python's builtins kept,
        no ``__``) with the work budget."""
        if "__" in expression:
            raise subst.SubstitutionException("$(eval ...) may not contain double underscore expressions")
        args = context.setdefault("arg", {})
        functions: dict[str, Any] = {
            "arg": lambda name: subst.convert_value(subst._eval_arg(name, args), "auto"),
            "dirname": lambda: subst._eval_dirname(context["filename"]),
        }
        functions.update(subst._eval_dict)
        scope = subst._DictWrapper(args, functions)
        return str(eval(compile_budgeted(expression), {GUARD_NAME: self.guard}, scope))  # type: ignore[arg-type]

    def load_yaml(self, filename: str) -> Any:
        """Replacement of ``xacro.load_yaml``: reads through the sandbox and records the source."""
        import yaml

        for unit in xacro.ConstructUnits:
            yaml.SafeLoader.add_constructor(unit.value.tag, unit.constructor)
        path = Path(xacro.abs_filename_spec(filename)).absolute()
        try:
            data, _ = self.read(path)
        except _MissingInclude:
            raise XacroFailure(f"YAML file not found: {self.display(path)}") from None
        xacro.all_includes.append(str(path))
        return xacro.YamlListWrapper.wrap(yaml.safe_load(decode_text(data)))

    # messages --------------------------------------------------------------------------

    def message_functions(self) -> dict[str, Callable[..., None]]:
        """Stand-ins for xacro's printing functions (the library never prints)."""

        def warning(*args: Any, **kwargs: Any) -> None:
            self.warnings.append((self.current_file(), self.bundle.scrub(" ".join(str(a) for a in args))))

        def error(*args: Any, **kwargs: Any) -> None:
            warning(*args)

        def message(*args: Any, **kwargs: Any) -> None:
            return None

        def print_location() -> None:
            return None

        return {"warning": warning, "error": error, "message": message, "print_location": print_location}

    def global_symbols(self) -> dict[str, Any]:
        """A fresh symbol table (expressions can mutate xacro's namespaces), restricted when confined."""
        symbols: dict[str, Any] = xacro.create_global_symbols()
        namespace = symbols["xacro"]
        dict.__setitem__(namespace, "load_yaml", self.load_yaml)
        symbols["load_yaml"] = self.load_yaml
        if self.bundle.confined:
            python = symbols["python"]
            for name in DENIED_SYMBOLS:
                dict.pop(python, name, None)
                symbols.pop(name, None)
            dict.__setitem__(python, "range", bounded_range)
            symbols["range"] = bounded_range
        return symbols

    @contextlib.contextmanager
    def installed(self) -> Iterator[None]:
        """xacro's globals replaced by this session's, restored on exit."""
        saved_xacro = {
            name: getattr(xacro, name)
            for name in (
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
        }
        saved_subst = {name: getattr(subst, name) for name in ("_eval_find", "_eval_env", "_eval_optenv", "_eval")}
        saved_eval_dict = dict(subst._eval_dict)
        try:
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
            yield
        finally:
            for name, value in saved_xacro.items():
                setattr(xacro, name, value)
            for name, value in saved_subst.items():
                setattr(subst, name, value)
            subst._eval_dict.clear()
            subst._eval_dict.update(saved_eval_dict)

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
        return [element.getUserData(ORIGIN_KEY) for element in _dom_elements(doc.documentElement)]

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


def confined_glob(bundle: Bundle, pattern: str, shown: str) -> list[str]:
    """The matches of an include ``pattern`` of a confined bundle: its folder (the part before
    the first wildcard) must be inside the sandbox, a ``..`` after a wildcard is refused, and a
    match that leads outside (through a link) is left out. Were the folder listed wherever it
    is, the names of any folder's files would show (``/etc/pass*`` included ``/etc/passwd``,
    refused with its name; ``/etc/none*`` matched nothing)."""
    parts = Path(pattern).parts
    fixed = next((i for i, part in enumerate(parts) if globmodule.has_magic(part)), len(parts))
    if ".." in parts[fixed:]:
        raise SandboxViolation(f"include pattern {shown}: '..' after a wildcard is refused in untrusted descriptions")
    bundle.check_access(Path(*parts[:fixed]) if fixed else Path.cwd())
    inside = []
    for match in globmodule.glob(pattern):
        try:
            bundle.check_access(Path(match))
        except SandboxViolation:
            continue
        inside.append(match)
    return inside


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
