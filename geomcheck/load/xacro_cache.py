"""The xacro expansion, cached by content.

What an expansion reads is only known once it ran, so lookups go in two steps (as ccache's
manifests do). The *context* — geomcheck's code, the xacro and lxml versions, the bundle
(root file, package map, folders, sandbox), the args and the load limits — keys a short list
of *variants*, each the files one earlier expansion read (path -> sha256, ``None`` for a
file it looked for and did not find) and the folders its ``$(find)`` calls resolved to. A
variant still holds when every one of those files has the same digest (or is still absent)
and every package resolves to the same folder; the expansion is then keyed by the context
and the variant. An expansion that read the environment or globbed includes
(:attr:`Expansion.volatile`) is never stored.

Every path in the keys, the variants and the stored ``files_read``/``packages_found`` is
relative to the bundle's display root, so the same files checked in another folder (the
service unpacks each upload in a folder of its own) hit the same entry. An expansion whose
output names an absolute folder (``$(find)`` in a filename, ``$(cwd)``) is bound to the
display root it was made under: its variant records that root (``at``); one that read
``$(cwd)`` at all (a branch on it names no folder) holds only in the folder ``$(cwd)`` gave
(``location``).
"""

from __future__ import annotations

import json
import logging
import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from geomcheck.cache import active_store
from geomcheck.cache.keys import (
    absolute,
    canonical,
    code_fingerprint,
    digest_key,
    file_sha256,
    library_versions,
    relative,
)
from geomcheck.cache.store import Store, encode_json
from geomcheck.diagnostics import diagnostic_from_dict, diagnostic_to_dict
from geomcheck.errors import GeomcheckError
from geomcheck.load.bundle import LOCATION_EVENT, Bundle
from geomcheck.load.xacro_expand import Expansion, expand
from geomcheck.thresholds import LoadLimits

log = logging.getLogger("geomcheck.cache")

NAMESPACE = "xacro"
VARIANTS_NAMESPACE = "xacro-variants"
MAX_VARIANTS = 8  # expansions kept per context (branches switched back and forth) [count]
FORMAT = 2  # 2: paths relative to the display root


def expansion_context(bundle: Bundle, args: Mapping[str, str], limits: LoadLimits) -> list[Any]:
    """Everything besides the files read that an expansion of ``bundle`` depends on; paths
    relative to the display root."""
    base = bundle.display_root
    return [
        FORMAT,
        code_fingerprint(),
        library_versions(("xacro", "lxml", "PyYAML")),
        canonical(bundle, path=lambda p: relative(p, base)),
        dict(sorted(args.items())),
        canonical(limits),
    ]


def variant_holds(variant: Mapping[str, Any], bundle: Bundle) -> bool:
    """Whether the files and packages an earlier expansion read are still as they were (and
    the display root the same, for an expansion bound to it)."""
    base = bundle.display_root
    at = variant.get("at")
    if at is not None and at != str(base.absolute()):
        return False
    location = variant.get("location")
    if location is not None and location != bundle.working_folder():
        return False
    for path, digest in variant["files"].items():
        if file_sha256(Path(absolute(path, base))) != digest:
            return False
    for name, folder in variant["packages"].items():
        try:
            directory = bundle.package_dir(name)
            if directory is None or relative(bundle.check_access(directory), base) != folder:
                return False
        except GeomcheckError:
            return False
    return True


def expansion_data(expansion: Expansion, base: Path) -> dict[str, Any]:
    """What :func:`encode_expansion` stores: the expansion with the paths it read relative to ``base``."""
    return {
        "text": expansion.text,
        "sources": dict(expansion.sources),
        "origins": [list(o) if o is not None else None for o in expansion.origins],
        "diagnostics": [diagnostic_to_dict(d) for d in expansion.diagnostics],
        "files_read": {relative(p, base): d for p, d in expansion.files_read.items()},
        "packages_found": {name: relative(folder, base) for name, folder in expansion.packages_found.items()},
        "location": expansion.location,
    }


def bound_to(expansion: Expansion, data: Mapping[str, Any], base: Path) -> str | None:
    """The absolute display root when the stored expansion names an absolute folder it read
    from (or the working folder, ``$(cwd)``), so it holds only there; else ``None``."""
    folders = {str(base.absolute()), str(base.resolve()), os.getcwd()}
    folders.update(expansion.packages_found.values())
    folders.update(os.path.dirname(p) for p in expansion.files_read)
    stored = "\n".join([data["text"], *data["sources"].values(), json.dumps(data["diagnostics"], ensure_ascii=False)])
    return str(base.absolute()) if any(f and f != os.sep and f in stored for f in folders) else None


def encode_expansion(expansion: Expansion, base: Path | None = None) -> bytes:
    """The bytes of ``expansion`` (paths read relative to ``base``, default the working folder)."""
    return encode_json(expansion_data(expansion, base or Path.cwd()))


def _origin(value: Any) -> tuple[str, int] | None:
    if value is None:
        return None
    file, line = value
    if not isinstance(file, str) or not isinstance(line, int):
        raise ValueError(f"bad origin {value!r}")
    return file, line


def _strings(value: Any, what: str) -> dict[str, str]:
    if not isinstance(value, dict) or not all(isinstance(k, str) and isinstance(v, str) for k, v in value.items()):
        raise ValueError(f"{what} must map strings to strings")
    return value


def decode_expansion(payload: bytes, base: Path | None = None) -> Expansion:
    """An :class:`Expansion` from :func:`encode_expansion`'s bytes, the paths read made
    absolute against ``base`` (default the working folder); :class:`ValueError`,
    ``KeyError`` or ``TypeError`` when they are not one."""
    data = json.loads(payload)
    text = data["text"]
    if not isinstance(text, str):
        raise ValueError("text must be a string")
    files = data["files_read"]
    if not isinstance(files, dict) or not all(v is None or isinstance(v, str) for v in files.values()):
        raise ValueError("files_read must map paths to digests")
    folder = base or Path.cwd()
    packages = _strings(data["packages_found"], "packages_found")
    return Expansion(
        text=text,
        sources=_strings(data["sources"], "sources"),
        origins=[_origin(o) for o in data["origins"]],
        diagnostics=tuple(diagnostic_from_dict(d) for d in data["diagnostics"]),
        files_read={absolute(p, folder): d for p, d in files.items()},
        packages_found={name: absolute(p, folder) for name, p in packages.items()},
        location=_location(data.get("location")),
    )


def _location(value: Any) -> str | None:
    if value is not None and not isinstance(value, str):
        raise ValueError("location must be a folder")
    return value


def _variants(store: Store, context_key: str) -> list[dict[str, Any]]:
    found = store.get_json(VARIANTS_NAMESPACE, context_key)
    if not isinstance(found, list):
        return []
    return [
        v
        for v in found
        if isinstance(v, dict) and isinstance(v.get("files"), dict) and isinstance(v.get("packages"), dict)
    ]


def cached_expand(bundle: Bundle, args: Mapping[str, str], limits: LoadLimits) -> Expansion:
    """:func:`geomcheck.load.xacro_expand.expand`, answered from the active store when an
    earlier expansion read the very same files (no store active: expanded every time)."""
    store = active_store()
    if store is None:
        return expand(bundle, args, limits)
    try:
        context_key = digest_key(NAMESPACE, expansion_context(bundle, args, limits))
    except TypeError as err:  # a bundle field no key can hold: never cached, never a failure
        log.debug("cache: xacro expansion not cached: %s", err)
        return expand(bundle, args, limits)
    variants = _variants(store, context_key)
    for variant in variants:
        if not variant_holds(variant, bundle):
            continue
        # an entry that is no expansion is discarded by the store and expanded again
        found = store.get_decoded(
            NAMESPACE,
            digest_key(NAMESPACE, context_key, variant),
            lambda payload: decode_expansion(payload, bundle.display_root),
        )
        if found is not None:
            if found.location is not None:  # what records a whole check's reads learns it as the expansion did
                sys.audit(LOCATION_EVENT, found.location)
            return found
    expansion = expand(bundle, args, limits)
    if expansion.volatile is None:
        base = bundle.display_root
        data = expansion_data(expansion, base)
        variant = {
            "files": data["files_read"],
            "packages": data["packages_found"],
            "at": bound_to(expansion, data, base),
            "location": expansion.location,  # $(cwd): the folder it was read in
        }
        store.put_bytes(NAMESPACE, digest_key(NAMESPACE, context_key, variant), encode_json(data))
        kept = [variant, *(v for v in variants if v != variant)][:MAX_VARIANTS]
        store.put_json(VARIANTS_NAMESPACE, context_key, kept)
    return expansion
