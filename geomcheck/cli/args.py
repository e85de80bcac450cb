"""Argument definitions shared by the commands: the option flags declared once in
:mod:`geomcheck.option_spec`, source, configuration and cache flags, and the flags' configuration.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from geomcheck.option_spec import BY_KEY, OPTIONS, Config, Group, Option, from_texts, options_where, read_options

if TYPE_CHECKING:  # loading and checking are imported by the commands that run them (a fast cold start)
    from geomcheck.cache.store import Store


DEFAULT_FORMAT = "full"

LINE_FORMATS = ("full", "text", "concise", "github")


# --- arguments ---------------------------------------------------------------------------


def add_option_flags(p: argparse.ArgumentParser | argparse._ArgumentGroup, options: Sequence[Option]) -> None:
    """The flags of ``options`` (:data:`geomcheck.option_spec.OPTIONS`): help, metavar and
    action from their declaration; values are validated as configuration keys (:func:`flags_config`)."""
    for option in options:
        assert option.flag is not None
        kwargs: dict[str, Any] = {"help": option.description()}
        if option.kind == "bool":
            kwargs["action"] = argparse.BooleanOptionalAction
        elif option.repeatable:
            kwargs.update(action="append", metavar=option.metavar)
        elif option.kind == "int":
            kwargs["type"] = int
        elif option.metavar:
            kwargs["metavar"] = option.metavar
        p.add_argument(option.flag, **kwargs)


def flags_of(group: Group, command: str = "check") -> list[Option]:
    """The options of flag group ``group`` on ``command`` (``check`` or ``matrix``)."""
    return [o for o in options_where("matrix" if command == "matrix" else "check") if o.group == group]


def add_source_options(p: argparse.ArgumentParser) -> None:
    add_option_flags(p, flags_of("sources"))


def add_load_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", help="root URDF or xacro file")
    add_source_options(p)


def add_check_options(p: argparse.ArgumentParser) -> None:
    """Output, failing, selection, configuration and check options (all default to the
    configuration file, then to the built-in defaults)."""
    out = p.add_argument_group("output")
    add_option_flags(out, flags_of("output"))
    out.add_argument("-o", "--output", metavar="FILE", help="write the report to FILE")
    out.add_argument("--statistics", action="store_true", help="print the number of findings per rule instead")
    gate = p.add_argument_group("exit status")
    add_option_flags(gate, flags_of("exit status"))
    gate.add_argument("--exit-zero", action="store_true", help="exit 0 even when findings fail")
    sel = p.add_argument_group("rule selection (codes, prefixes such as GC3, family names such as fit, or ALL)")
    add_option_flags(sel, flags_of("rule selection"))
    add_config_options(p.add_argument_group("configuration"))
    add_option_flags(p.add_argument_group("checks"), flags_of("checks"))


def add_quiet_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        help="no progress on stderr (a bar on a terminal; elsewhere, as in CI logs, one line per stage once "
        "the run takes more than a few seconds)",
    )


def add_config_options(p: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
    p.add_argument("--config", metavar="FILE", help="use this geomcheck.toml or pyproject.toml")
    p.add_argument("--no-config", action="store_true", help="ignore configuration files")


def add_cache_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--no-cache",
        action="store_true",
        help="neither read nor write the cache (GEOMCHECK_CACHE_DIR, default $XDG_CACHE_HOME/geomcheck)",
    )


def cache_store(ns: argparse.Namespace) -> Store | None:
    """The cache store for this command: none for commands that compute nothing or with ``--no-cache``."""
    if getattr(ns, "no_cache", True):
        return None
    from geomcheck.cache import open_store

    return open_store()


def add_check_arguments(p: argparse.ArgumentParser) -> None:
    """One description and every check option (``ns.path``)."""
    add_load_arguments(p)
    add_check_options(p)


def flags_config(ns: argparse.Namespace) -> Config:
    """The flags that were given, read as every source's values are (:func:`read_options`, each
    by its option's own validator)."""
    flagged = [o for o in OPTIONS if o.flag is not None]
    given = {o.key: getattr(ns, o.dest, None) for o in flagged}  # subcommands define subsets of the flags
    texts = {key: value if BY_KEY[key].repeatable else [value] for key, value in given.items() if value is not None}
    flags = {o.key: str(o.flag) for o in flagged}
    data = from_texts(texts, lambda option: flags[option.key])
    return read_options(data, Path.cwd(), "command line", label=lambda k: flags[k])
