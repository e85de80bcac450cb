"""The base revision's findings in ``geomcheck diff --base REV``, cached.

A commit fixes every file of the repository, so the base side's findings are keyed by the
commit hash, where the description and the configured folders lie in the repository, the
folder geomcheck runs in (report paths are relative to it), the options (selection and
thresholds included: the cached findings are the selected ones) and geomcheck's code and
libraries. A base that depends on folders outside the repository (``--package``,
``--search`` or ``--srdf`` outside it) could change without the commit changing: it is
never cached. Files outside the repository that the description names by absolute path,
and environment variables it reads with ``$(env)``, are assumed unchanged.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Iterable, Mapping
from dataclasses import fields
from pathlib import Path, PurePath
from typing import Any

from geomcheck.cache import active_store
from geomcheck.cache.keys import canonical, code_fingerprint, library_versions
from geomcheck.cache.store import encode_json
from geomcheck.diagnostics import Diagnostic, diagnostic_from_dict, diagnostic_to_dict
from geomcheck.options import CheckOptions

NAMESPACE = "diff-base"
FORMAT = 1
# options that change how a run is shown or scheduled, not what it finds
PRESENTATION_OPTIONS = frozenset({"workers"})

BaseFindings = tuple[tuple[Diagnostic, ...] | None, str | None]  # findings (None: no such file), note


def _in_repository(path: Path, root: Path) -> str | None:
    resolved = path.resolve()
    return resolved.relative_to(root).as_posix() if resolved.is_relative_to(root) else None


def options_key(
    options: CheckOptions,
    without: Iterable[str] = PRESENTATION_OPTIONS,
    path: Callable[[PurePath], str] = PurePath.as_posix,
) -> dict[str, Any]:
    """The options as canonical data (paths as ``path(p)``), minus the fields named in ``without``."""
    skip = frozenset(without)
    return {f.name: canonical(getattr(options, f.name), path) for f in fields(options) if f.name not in skip}


def base_revision_key(
    root: Path,
    label: str,
    commit: str,
    head_path: Path,
    packages: Mapping[str, Path],
    search: Iterable[Path],
    options: CheckOptions,
) -> list[Any] | None:
    """Key parts of the base side of ``head_path`` at ``commit`` of the repository at ``root``
    (``label`` names the revision in notes); ``None`` when that side depends on folders
    outside the repository."""
    head = _in_repository(head_path, root)
    package_parts = {name: _in_repository(Path(d), root) for name, d in sorted(packages.items())}
    search_parts = [_in_repository(Path(d), root) for d in search]
    srdf = _in_repository(options.srdf, root) if options.srdf is not None else ""
    if head is None or srdf is None or None in package_parts.values() or None in search_parts:
        return None
    return [
        FORMAT,
        code_fingerprint(),
        library_versions(),
        commit,
        label,
        head,
        package_parts,
        search_parts,
        srdf,
        os.path.relpath(Path.cwd().resolve(), root),
        options_key(options, PRESENTATION_OPTIONS | {"srdf"}),
    ]


def encode_findings(found: BaseFindings) -> bytes:
    diagnostics, note = found
    return encode_json(
        {
            "exists": diagnostics is not None,
            "diagnostics": [diagnostic_to_dict(d) for d in diagnostics or ()],
            "note": note,
        }
    )


def decode_findings(payload: bytes) -> BaseFindings:
    data = json.loads(payload)
    note = data["note"]
    if note is not None and not isinstance(note, str):
        raise ValueError("note must be a string")
    if not data["exists"]:
        return None, note
    return tuple(diagnostic_from_dict(d) for d in data["diagnostics"]), note


def cached_base_findings(key_parts: list[Any] | None, compute: Callable[[], BaseFindings]) -> BaseFindings:
    """The base side's findings from the active store, else ``compute()``d and stored (no
    store active, or no key: computed every time)."""
    store = active_store()
    if store is None or key_parts is None:
        return compute()
    return store.get_or_compute(NAMESPACE, key_parts, compute, encode_findings, decode_findings)
