"""Each pair's sweep result, cached by what it depends on, so a re-check after an edit only
sweeps the pairs the edit touched.

A pair's search (:mod:`geomcheck.selfcollision.sweep`) is independent of every other pair's:
its result is a function of the two links' collision shapes (each engine object's content: a
mesh file's sha256 and scale, or the primitive; and its pose in the link), of how each link
moves (the joints from the root down to it, with the variable driving each and its value at
the default pose), of the swept dimensions, of the pair's plan (speed bound, adjacency) and
of the sweep's settings and collision engine. Those are the key (with geomcheck's code and
the libraries' versions, as every cached stage); a shape whose content is unknown makes the
pair uncacheable. Joint limits, names of files and source locations are not in it.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import asdict
from typing import Any

import numpy as np

from geomcheck.cache import active_store, stage_parts
from geomcheck.cache.keys import canonical, digest_key
from geomcheck.collision.scene import CollisionScene
from geomcheck.kinematics import Kinematics
from geomcheck.selfcollision.sweep_plan import PairPlan, SweepGroup

NAMESPACE = "sweep-pair"
FORMAT = 2


def _link_shapes(scene: CollisionScene, link: str) -> list[Any] | None:
    parts = []
    for s in scene.scene_shapes(link):
        if not s.content:
            return None
        parts.append([s.content, canonical(s.shape.origin)])
    return parts


def _link_motion(kin: Kinematics, q0: np.ndarray, link: str) -> list[Any]:
    parts = []
    for joint in kin.root_path(link):
        driver = kin.driver(joint)
        value = float(q0[kin.index(driver[0])]) if driver is not None else None
        parts.append(
            [
                joint.name,
                joint.type,
                canonical(joint.origin),
                list(joint.axis),
                canonical(joint.mimic),
                list(driver) if driver is not None else None,
                value,
            ]
        )
    return parts


def pair_key(
    kin: Kinematics, scene: CollisionScene, q0: np.ndarray, settings: Any, group: SweepGroup, plan: PairPlan
) -> list[Any] | None:
    """The key of ``plan``'s search in ``group``'s sweep, or None when it cannot be keyed."""
    shapes = [_link_shapes(scene, link) for link in plan.links]
    if any(s is None for s in shapes):
        return None
    return [
        FORMAT,
        scene.backend.name,
        canonical(settings),
        group.joint.name,
        list(group.dimensions),
        bool(group.round),
        list(plan.links),
        bool(plan.adjacent),
        bool(plan.both_move),
        [float(v) for v in plan.speed],
        shapes,
        [_link_motion(kin, q0, link) for link in plan.links],
    ]


def _encode(result: Any) -> bytes:
    return json.dumps(asdict(result), separators=(",", ":"), allow_nan=True).encode("utf-8")


def _decoder(kind: type) -> Callable[[bytes], Any]:
    def decode(payload: bytes) -> Any:
        data = json.loads(payload)
        for name in ("links", "shapes", "chart_angles", "chart_clearance", "deepest"):
            data[name] = tuple(data[name])
        data["colliding_ranges"] = tuple(tuple(r) for r in data["colliding_ranges"])
        return kind(**data)

    return decode


def cached_pairs(
    keys: Sequence[list[Any] | None],
    compute: Callable[[list[int]], dict[int, Any]],
    kind: type,
) -> list[Any]:
    """Each pair's result: from the active store where ``keys[i]`` is stored, the rest from one
    ``compute(indices)`` call (``{index: result}``), which are then stored. An entry that does
    not decode is discarded and its pair computed again."""
    store = active_store()
    digests = [digest_key(NAMESPACE, stage_parts(key)) if key is not None and store else None for key in keys]
    decode = _decoder(kind)
    found: dict[int, Any] = {}
    if store is not None:
        for i, digest in enumerate(digests):
            hit = store.get_decoded(NAMESPACE, digest, decode) if digest is not None else None
            if hit is not None:
                found[i] = hit
    missing = [i for i in range(len(keys)) if i not in found]
    if missing:
        computed = compute(missing)
        for i in missing:
            found[i] = computed[i]
            digest = digests[i]
            if store is not None and digest is not None:
                store.put_bytes(NAMESPACE, digest, _encode(computed[i]))
    return [found[i] for i in range(len(keys))]
