"""Configuration: ``[tool.geomcheck]`` in a pyproject.toml, or the same keys at the top level
of a geomcheck.toml.

The file is found from the description's folder upwards (``geomcheck.toml`` wins over
``pyproject.toml`` in one folder; a pyproject.toml without ``[tool.geomcheck]`` is passed
over); the search stops at the root of the git work tree or of the file system. Relative
paths in a file are relative to the file's folder. Command-line flags, request options and
the library's keywords are read into a :class:`Config` by the same function
(:func:`geomcheck.option_spec.read_options`) and :func:`merge`d on top: they win.

Every key and rule code is checked: an unknown one is a :class:`UsageError` naming it.
"""

from __future__ import annotations

import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

from geomcheck.errors import UsageError
from geomcheck.option_spec import OPTIONS, Config, did_you_mean, edit_distance, merge, read_options, resolve_selector

CONFIG_FILES = ("geomcheck.toml", "pyproject.toml")
__all__ = [  # Config, merge and the validation live with the options' declaration (geomcheck.option_spec)
    "CONFIG_FILES",
    "KEYS",
    "Config",
    "did_you_mean",
    "discover_config",
    "edit_distance",
    "find_config",
    "load_config",
    "merge",
    "read_toml",
    "resolve_selector",
]


# --- reading -----------------------------------------------------------------------------


def find_config(start: Path, within: Path | None = None) -> Path | None:
    """The configuration file that applies to ``start`` (a file or folder), or ``None``.

    The search goes upwards and stops at a git root, and never leaves ``within`` when given
    (an uploaded bundle's own configuration must not come from outside it)."""
    folder = start if start.is_dir() else start.parent
    for directory in (folder.resolve(), *folder.resolve().parents):
        if within is not None and not directory.is_relative_to(within.resolve()):
            return None
        own = directory / "geomcheck.toml"
        if own.is_file():
            return own
        project = directory / "pyproject.toml"
        if project.is_file() and "geomcheck" in read_toml(project).get("tool", {}):
            return project
        if (directory / ".git").exists():
            return None
    return None


def read_toml(path: Path) -> dict[str, Any]:
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise UsageError(f"cannot read configuration {path}: {err.strerror}") from None
    except tomllib.TOMLDecodeError as err:
        raise UsageError(f"{path}: invalid TOML: {err}") from None


def load_config(path: Path) -> Config:
    """Settings of the file ``path``: its ``[tool.geomcheck]`` table for a pyproject.toml,
    its top level otherwise."""
    data = read_toml(path)
    if path.name == "pyproject.toml":
        data = data.get("tool", {}).get("geomcheck", {})
    return read_options(data, base_dir=path.parent.resolve(), where=str(path), path=path.resolve())


def discover_config(description: Path) -> Config:
    """Settings of the file that applies to ``description``; defaults when there is none."""
    found = find_config(description)
    return load_config(found) if found else Config()


# --- validation --------------------------------------------------------------------------

Parser = Callable[[Any, str, Path], Any]

# key as written in a file -> (Config field, the option's validator): every option of
# geomcheck.option_spec, nothing else
KEYS: dict[str, tuple[str, Parser]] = {o.key: (o.name, o.validate) for o in OPTIONS}
