"""The collision matrix, cached by content.

A matrix follows from the robot model (every link, joint, limit and shape, as loaded), the
bytes of every mesh the model names, the default configuration, the matrix settings, the
collision backend and the load limits (which meshes are used), and geomcheck's code and the
libraries' versions (added by :func:`geomcheck.cache.cached`). On a hit neither the meshes
nor the collision scene are built; the matrix's ``stats`` are zero (no work was spent).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from geomcheck.cache import cached
from geomcheck.cache.keys import canonical, file_sha256
from geomcheck.cache.store import encode_json
from geomcheck.load import MeshStore
from geomcheck.load.meshes import generated_source
from geomcheck.model import Mesh, Robot
from geomcheck.selfcollision.compute import MatrixSettings
from geomcheck.selfcollision.matrix import CollisionMatrix, PairClass, PairResult, Witness, WitnessSource
from geomcheck.thresholds import LoadLimits

NAMESPACE = "matrix"
FORMAT = 1


def mesh_digests(robot: Robot, meshes: MeshStore) -> dict[str, str]:
    """``{filename: sha256 of the file}`` of every mesh the robot names (visual and collision);
    a missing build product analysed as its source is keyed by the source's (``source:SHA256``),
    another mesh that does not resolve to a readable file by why (``problem:KIND``)."""
    out: dict[str, str] = {}
    for link in robot.links:
        for shape in (*link.visuals, *link.collisions):
            geometry = shape.geometry
            if not isinstance(geometry, Mesh) or geometry.filename in out:
                continue
            found = meshes.resolve(geometry.filename)
            digest = file_sha256(found) if isinstance(found, Path) else None
            if digest is None and isinstance(found, Path):
                # a build product of a package that is not built is analysed as its source
                source = generated_source(found)
                source_digest = file_sha256(source) if source is not None else None
                digest = f"source:{source_digest}" if source_digest is not None else None
            out[geometry.filename] = digest or f"problem:{getattr(found, 'kind', 'unreadable')}"
    return dict(sorted(out.items()))


def matrix_key(
    robot: Robot,
    meshes: MeshStore,
    default_q: Any,
    settings: MatrixSettings,
    backend: str,
    limits: LoadLimits,
) -> list[Any]:
    """Key parts of the matrix of ``robot`` (``default_q``: the default configuration, (n_joints,))."""
    return [
        FORMAT,
        canonical(robot),
        mesh_digests(robot, meshes),
        [float(v) for v in default_q],
        canonical(settings),
        backend,
        canonical(limits),
    ]


def _witness(data: dict[str, Any] | None) -> Witness | None:
    if data is None:
        return None
    configuration = {str(k): float(v) for k, v in data["configuration"].items()}
    return Witness(configuration, float(data["depth"]), WitnessSource(data["source"]))


def _optional_float(value: Any) -> float | None:
    return None if value is None else float(value)


def encode_matrix(matrix: CollisionMatrix) -> bytes:
    """Every field at full precision (the report's section rounds), ``stats`` left out."""
    return encode_json(
        {
            "samples": matrix.samples,
            "seed": matrix.seed,
            "backend": matrix.backend,
            "always_fraction": float(matrix.always_fraction),
            "links": list(matrix.links),
            "default_configuration": {k: float(v) for k, v in matrix.default_configuration.items()},
            "semantics": matrix.semantics,
            "pairs": [
                {
                    "links": list(p.links),
                    "cls": p.cls.value,
                    "tested": int(p.tested),
                    "collisions": int(p.collisions),
                    "min_distance": _optional_float(p.min_distance),
                    "certified": bool(p.certified),
                    "clearance_bound": _optional_float(p.clearance_bound),
                    "witness": None
                    if p.witness is None
                    else {
                        "configuration": {k: float(v) for k, v in p.witness.configuration.items()},
                        "depth": float(p.witness.depth),
                        "source": p.witness.source.value,
                    },
                }
                for p in matrix.pairs
            ],
        }
    )


def decode_matrix(payload: bytes) -> CollisionMatrix:
    """A :class:`CollisionMatrix` from :func:`encode_matrix`'s bytes (``ValueError``,
    ``KeyError`` or ``TypeError`` when they are not one)."""
    data = json.loads(payload)
    pairs = []
    for p in data["pairs"]:
        a, b = p["links"]
        pairs.append(
            PairResult(
                links=(str(a), str(b)),
                cls=PairClass(p["cls"]),
                tested=int(p["tested"]),
                collisions=int(p["collisions"]),
                min_distance=_optional_float(p["min_distance"]),
                certified=bool(p["certified"]),
                clearance_bound=_optional_float(p["clearance_bound"]),
                witness=_witness(p["witness"]),
            )
        )
    return CollisionMatrix(
        samples=int(data["samples"]),
        seed=int(data["seed"]),
        backend=str(data["backend"]),
        always_fraction=float(data["always_fraction"]),
        links=tuple(str(link) for link in data["links"]),
        pairs=tuple(pairs),
        default_configuration={str(k): float(v) for k, v in data["default_configuration"].items()},
        semantics=str(data["semantics"]),
    )


def cached_matrix(key_parts: list[Any], compute: Callable[[], CollisionMatrix]) -> CollisionMatrix:
    """The matrix from the active store, else ``compute()``d and stored."""
    return cached(NAMESPACE, key_parts, compute, encode_matrix, decode_matrix)
