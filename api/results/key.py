"""The key of a whole check's result, for the service's result cache.

Two submissions get the same key exactly when they must get the same report (ids and
timestamps aside): the same canonical upload (every file's relative path and sha256, so a
``geomcheck.toml`` inside the upload counts with its bytes), the same root file, the same
effective options and thresholds, and the same geomcheck code and library versions.
``fail_on`` is left out: it only decides the verdict, so a service applies it to a stored
report after the lookup. The rule selection (with severity overrides and per-link ignores)
is in the key: it decides which analyses run at all (``--select GC1`` loads no mesh), so a
report of one selection is not a filter of another's.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path, PurePath
from typing import Any

from geomcheck.cache.keys import code_fingerprint, digest_key, file_sha256, library_versions
from geomcheck.config import Config
from geomcheck.diff_cache import options_key
from geomcheck.options import CheckOptions

FORMAT = 1
# options applied to a finished report (fail_on) or that only change how a run is shown or scheduled
AFTER_ANALYSIS_OPTIONS = frozenset({"fail_on", "workers"})


def upload_digests(folder: Path) -> dict[str, str]:
    """The canonical upload under ``folder``: ``{relative posix path: sha256}`` of every
    regular file, sorted by path (symbolic links are neither followed nor counted)."""
    found: dict[str, str] = {}
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames.sort()
        for name in filenames:
            path = Path(dirpath) / name
            if path.is_symlink() or not path.is_file():
                continue
            digest = file_sha256(path)
            if digest is not None:
                found[path.relative_to(folder).as_posix()] = digest
    return dict(sorted(found.items()))


def result_versions() -> dict[str, str]:
    """geomcheck's version (with a digest of its code) and those of the libraries whose results it reports."""
    return {"geomcheck": code_fingerprint(), **library_versions()}


def effective_options(options: CheckOptions) -> CheckOptions:
    """``options`` with the matrix's samples and seed as they will be used (unset means the
    thresholds' defaults), so asking for the default explicitly keys the same report."""
    sc = options.thresholds.self_collision
    return replace(
        options,
        samples=options.samples if options.samples is not None else sc.samples,
        seed=options.seed if options.seed is not None else sc.seed,
    )


def _upload_relative(upload_root: Path) -> Any:
    root = upload_root.resolve()

    def relative(path: PurePath) -> str:
        resolved = Path(path).resolve()
        if resolved.is_relative_to(root):
            return "upload:" + resolved.relative_to(root).as_posix()
        return Path(path).as_posix()

    return relative


def result_key(
    upload: Mapping[str, str],
    root: str,
    config: Config,
    upload_root: Path,
    versions: Mapping[str, str] | None = None,
) -> str:
    """The sha256 (hex) keying the report of one check.

    ``upload`` is :func:`upload_digests` of the extracted upload, ``root`` the root file's
    path relative to the upload, ``config`` the request's configuration (its paths under
    ``upload_root`` are keyed relative to it, so the folder the upload was unpacked in does
    not matter), ``versions`` :func:`result_versions` by default.
    """
    relative = _upload_relative(upload_root)
    options = effective_options(config.to_options())
    loading = {
        "packages": {name: relative(Path(d)) for name, d in sorted(config.packages.items())},
        "search": [relative(Path(d)) for d in config.search],
    }
    return digest_key(
        "result",
        FORMAT,
        dict(sorted(upload.items())),
        root,
        options_key(options, AFTER_ANALYSIS_OPTIONS, path=relative),
        loading,
        dict(versions if versions is not None else result_versions()),
    )
