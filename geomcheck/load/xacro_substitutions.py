"""Substitutions and expressions of one xacro run: ``$(find)`` through the bundle's package
map, ``$(env)``/``$(optenv)`` from the values the user gave (confined bundles read no other
variable), expressions in the sandbox of :mod:`geomcheck.load.xacro_eval` when confined and
with the work budget always, YAML read through the sandbox, and xacro's messages collected."""

from __future__ import annotations

import glob as globmodule
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import xacro
import xacro.substitution_args as subst

from geomcheck.errors import SandboxViolation
from geomcheck.load.bundle import ENV_EVENT, LOCATION_EVENT, VOLATILE_EVENT, Bundle
from geomcheck.load.xacro_errors import XacroFailure
from geomcheck.load.xacro_eval import (
    DENIED_SYMBOLS,
    GUARD_NAME,
    bounded_range,
    compile_budgeted,
    compile_guarded,
    make_guard,
)
from geomcheck.load.xacro_files import MissingInclude
from geomcheck.load.xacro_macros import XacroMacros
from geomcheck.load.xmlsafe import decode_text
from geomcheck.thresholds import LoadLimits


class XacroSubstitutions(XacroMacros):
    """xacro's substitution, expression, YAML and message hooks."""

    def __init__(self, bundle: Bundle, limits: LoadLimits) -> None:
        super().__init__(bundle, limits)
        self.warnings: list[tuple[str, str]] = []
        self.packages_found: dict[str, str] = {}
        self.volatile: str | None = None
        self.location: str | None = None  # the folder $(cwd) gave
        self.guard = make_guard(limits.max_expanded_bytes, limits.max_expression_work)
        self.original_env: Callable[..., str] = subst._eval_env
        self.original_optenv: Callable[..., str] = subst._eval_optenv
        self.original_eval_extension: Callable[..., Any] = xacro.eval_extension

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
        except MissingInclude:
            raise XacroFailure(f"YAML file not found: {self.display(path)}") from None
        xacro.all_includes.append(str(path))
        return xacro.YamlListWrapper.wrap(yaml.safe_load(decode_text(data)))

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


__all__ = ["XacroSubstitutions", "confined_glob"]
