"""A bundle: the root file of a description plus the ROS packages it may refer to."""

from __future__ import annotations

import contextlib
import functools
import os
import re
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from geomcheck.errors import InputError, SandboxViolation, UsageError

# audit events (PEP 578) for what records a check's reads (geomcheck.check_cache): a path a
# loader looks at, whether or not it exists; an environment variable an expansion reads; the
# folder an expansion runs in, when it reads it ($(cwd)); a result that depends on more than
# files and variables
PROBE_EVENT = "geomcheck.probe"
ENV_EVENT = "geomcheck.env"
LOCATION_EVENT = "geomcheck.location"
VOLATILE_EVENT = "geomcheck.volatile"
FOLDER_SEARCH_DEPTH = 4  # how deep under a search root a folder named like a package is looked for [levels]


@dataclass(frozen=True)
class Confinement:
    """Process-wide confinement of every bundle (the untrusted CLI mode): ``allowed_env``
    names the environment variables ``$(env)``/``$(optenv)`` may still read."""

    allowed_env: frozenset[str] = frozenset()


_CONFINEMENT: list[Confinement] = []


def confine_process(confinement: Confinement) -> None:
    """Make every bundle built from now on in this process confined (never undone: the
    untrusted mode runs in a child process that exits after one command)."""
    _CONFINEMENT[:] = [confinement]


def process_confinement() -> Confinement | None:
    """The process-wide confinement, when :func:`confine_process` was called."""
    return _CONFINEMENT[0] if _CONFINEMENT else None


@dataclass(frozen=True)
class Bundle:
    """Root file, package map and file-access policy of one check.

    ``packages`` maps ROS package names to absolute directories. ``display_root`` is the
    directory report paths are relative to. When ``confined`` (uploads, untrusted CI runs),
    every file the loader opens must lie under one of ``allowed_roots`` and the environment
    is read only for the names in ``allowed_env``: ``$(optenv NAME default)`` takes its
    default, as on a fresh machine, and ``$(env NAME)`` is refused. ``env`` holds the values
    the user gave for variables (``--env``, the service's ``env`` option): they win in every
    mode, and are all a confined expansion sees besides ``allowed_env``.
    """

    root_file: Path
    packages: Mapping[str, Path] = field(default_factory=dict)
    display_root: Path = field(default_factory=Path.cwd)
    confined: bool = False
    allowed_roots: tuple[Path, ...] = ()
    search_roots: tuple[Path, ...] = ()
    allowed_env: frozenset[str] = frozenset()
    env: Mapping[str, str] = field(default_factory=dict)
    uploaded: bool = False  # an upload to the service: advice names the upload, not CLI flags

    def package_advice(self, package: str) -> str:
        """How the user of this bundle makes ``package`` known: command-line flags, or, for
        an upload, the package folder in the upload (the service has no flags)."""
        if self.uploaded:
            return (
                f"add the package to the upload: a folder holding its package.xml (<name>{package}</name>) "
                "and the files the description takes from it"
            )
        return f"pass --package {package}=DIR or --search DIR"

    def env_advice(self, name: str) -> str:
        """How the user of this bundle gives a value for environment variable ``name``."""
        if self.uploaded:
            return f"give its value with the env option (env={name}=VALUE)"
        return f"give its value with --env {name}=VALUE (or let the run read it: --allow-env {name})"

    def display(self, path: str | os.PathLike[str]) -> str:
        """``path`` relative to ``display_root`` with posix separators (absolute if on another drive)."""
        p = Path(path)
        try:
            rel = os.path.relpath(p, self.display_root)
        except ValueError:
            return p.as_posix()
        return Path(rel).as_posix()

    def own_folders(self) -> tuple[Path, ...]:
        """The machine's folders this bundle lives in (display root, root file's folder,
        packages, allowed roots; for a confined bundle also the process's current folder, the
        service's work folder of the check, which ``file://m.stl`` is resolved against),
        longest first: what a confined report never shows."""
        folders = {self.display_root, self.root_file.parent, *self.packages.values(), *self.allowed_roots}
        if self.confined:
            with contextlib.suppress(OSError):
                folders.add(Path.cwd())
        return tuple(sorted(folders, key=lambda f: (-len(str(f)), str(f))))

    def shown(self, path: str | os.PathLike[str]) -> str:
        """``path`` as a message may name it: relative to ``display_root`` when it is written
        under one of :meth:`own_folders`, else as given (a path the description wrote)."""
        text = os.fspath(path)
        if any(text == str(f) or text.startswith(f"{f}{os.sep}") for f in self.own_folders()):
            return self.display(text)
        return Path(text).as_posix()

    def scrub(self, text: str, base: Path | None = None) -> str:
        """``text`` with every one of :meth:`own_folders` written relative to ``base`` (by
        default ``display_root``) when the bundle is confined: an upload's report never holds
        the server's folders (``$(find pkg)``, ``$(cwd)``, messages of failed reads). Text of
        an unconfined bundle is returned as it is."""
        if not self.confined or not text:
            return text
        start = base or self.display_root
        folders = tuple(f for f in self.own_folders() if len(f.parts) > 1)  # never '/' itself
        if not folders:
            return text
        pattern = re.compile("|".join(re.escape(str(f)) for f in folders))
        relative = {str(f): Path(os.path.relpath(f, start)).as_posix() for f in folders}
        return pattern.sub(lambda m: relative[m.group(0)], text)

    def identity(self, display_path: str) -> str:
        """Location-independent name of a file given by its display path, for fingerprints:
        ``package://NAME/REL`` inside a known package (the deepest one), else the path relative
        to the root file's folder. Unlike display paths it does not change with the folder
        geomcheck runs in, nor between two checkouts of one repository."""
        path = Path(os.path.normpath(self.display_root / display_path))
        owners = [(len(d.parts), n, d) for n, d in self.packages.items() if path.is_relative_to(d)]
        if owners:
            _, name, directory = max(owners)
            return f"package://{name}/{path.relative_to(directory).as_posix()}"
        return Path(os.path.relpath(path, self.root_file.parent)).as_posix()

    def check_access(self, path: Path) -> Path:
        """``path`` resolved; :class:`SandboxViolation` when confined and outside ``allowed_roots``.
        Every path the loaders look at passes here: it is announced as :data:`PROBE_EVENT`."""
        resolved = path.resolve()
        sys.audit(PROBE_EVENT, str(resolved))
        if self.confined and not any(resolved.is_relative_to(r) for r in self.allowed_roots):
            raise SandboxViolation(f"access outside the uploaded bundle refused: {self.shown(path)}")
        return resolved

    def working_folder(self) -> str:
        """The folder ``$(cwd)`` names: the display root of a confined bundle (never the server's
        folder), the process's working folder otherwise."""
        return str(self.display_root) if self.confined else os.path.abspath(os.curdir)

    def package_dir(self, name: str) -> Path | None:
        """Directory of package ``name``: from the package map, else a folder of that name.

        Descriptions are often shipped without their package.xml (example-robot-data
        refers to ``package://example-robot-data/...``): as a fallback, a search root named
        ``name``, a folder named ``name`` under a search root, or the nearest ancestor of the
        root file named ``name`` is taken, inside ``allowed_roots`` when confined.
        """
        found = self.packages.get(name)
        if found is not None or not name or "/" in name or name in (".", ".."):
            return found
        ancestors = tuple(p for p in self.root_file.parents if p.name == name)
        candidate = _folder_named(name, self.search_roots, ancestors[:1])
        if candidate is not None and self.confined and not any(candidate.is_relative_to(r) for r in self.allowed_roots):
            return None
        return candidate


@functools.lru_cache(maxsize=256)
def _folder_named(name: str, search_roots: tuple[Path, ...], ancestors: tuple[Path, ...]) -> Path | None:
    """First directory called ``name``: a search root, one under a search root, an ancestor."""
    for root in search_roots:
        if root.name == name and root.is_dir():
            return root
    for root in search_roots:
        for dirpath, dirnames, _ in os.walk(root):
            dirnames.sort()
            dirnames[:] = [d for d in dirnames if not d.startswith(".")]
            if name in dirnames:
                return (Path(dirpath) / name).resolve()
            if len(Path(dirpath).parts) - len(root.parts) >= FOLDER_SEARCH_DEPTH:
                dirnames[:] = []
    return ancestors[0] if ancestors else None


def read_package_name(directory: Path) -> str:
    """Package name of ``directory``: ``<name>`` of its package.xml, else the folder name."""
    manifest = directory / "package.xml"
    if manifest.is_file():
        from geomcheck.load.xmlsafe import parse_bytes, read_file_bytes

        try:
            root = parse_bytes(read_file_bytes(manifest, str(manifest)), str(manifest))
        except InputError:
            return directory.name
        name = root.findtext("name")
        if name and name.strip():
            return name.strip()
    return directory.name


def discover_packages(search_roots: Iterable[Path], max_depth: int = 8) -> dict[str, Path]:
    """Every directory under ``search_roots`` (the roots included) holding package.xml or
    manifest.xml, by package name; the first found wins, in sorted walk order."""
    found: dict[str, Path] = {}
    for root in search_roots:
        root = root.resolve()
        if not root.is_dir():
            raise UsageError(f"search path is not a directory: {root}")
        base_depth = len(root.parts)
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames.sort()
            dirnames[:] = [d for d in dirnames if not d.startswith(".")]
            if len(Path(dirpath).parts) - base_depth >= max_depth:
                dirnames[:] = []
            if "package.xml" in filenames or "manifest.xml" in filenames:
                directory = Path(dirpath)
                found.setdefault(read_package_name(directory), directory)
    return found


def make_bundle(
    root_file: str | os.PathLike[str],
    packages: Mapping[str, str | os.PathLike[str]] | None = None,
    search: Iterable[str | os.PathLike[str]] = (),
    display_root: str | os.PathLike[str] | None = None,
    confined: bool = False,
    uploaded: bool = False,
    env: Mapping[str, str] | None = None,
) -> Bundle:
    """Bundle for ``root_file``: explicit ``packages`` win over those discovered under
    ``search``; the package holding the root file (nearest ancestor with a manifest) is
    always known; every bundle is confined once :func:`confine_process` was called. ``env``:
    the values the user gave for environment variables (:class:`Bundle`).
    :class:`InputError` when the root file does not exist."""
    forced = process_confinement()
    confined = confined or forced is not None
    root = Path(root_file)
    if not root.is_file():
        raise InputError(f"no such file: {root}")
    root = root.resolve()
    search_paths = [Path(s) for s in search]
    found = discover_packages(search_paths)
    for parent in root.parents:
        if (parent / "package.xml").is_file() or (parent / "manifest.xml").is_file():
            found.setdefault(read_package_name(parent), parent)
            break
    for name, directory in (packages or {}).items():
        path = Path(directory)
        if not path.is_dir():
            raise UsageError(f"package {name}: not a directory: {directory}")
        found[name] = path.resolve()
    disp = Path(display_root).resolve() if display_root is not None else Path.cwd()
    allowed = (disp, *found.values()) if confined else ()
    return Bundle(
        root_file=root,
        packages=dict(sorted(found.items())),
        display_root=disp,
        confined=confined,
        allowed_roots=tuple(p.resolve() for p in allowed),
        search_roots=tuple(p.resolve() for p in search_paths),
        allowed_env=forced.allowed_env if forced is not None else frozenset(),
        env=dict(sorted((env or {}).items())),
        uploaded=uploaded,
    )
