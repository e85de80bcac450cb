"""The narrow phase of a pose's contacts, and of a pair's sampled poses, kept across runs,
backed by the active store.

Which candidate pairs of one pose collide, how deep and how close
(:func:`geomcheck.selfcollision.default_pose.contacts_at`), and in which sampled poses two
links collide (:func:`geomcheck.selfcollision.default_pose.pair_occupancy`), is a function
of the collision backend, each link's shapes (what each engine object is made of: a mesh file's sha256 and
scale, or the primitive; its place on the link) and the two links' world poses, exactly as
given to the engine. The key holds all of them for every candidate pair, in order; the
store adds geomcheck's code and the libraries' versions. A warm check then builds no mesh
BVH for the default pose and its findings. A shape of unknown content (no digest) is never stored.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from geomcheck.cache import active_store, cached
from geomcheck.collision.scene import CollisionScene

NAMESPACE = "pose-contacts"
COLLISIONS_NAMESPACE = "pose-collisions"
FORMAT = 1

# (link a, world-from-a (4, 4), link b, world-from-b (4, 4)) as given to the engine
Candidate = tuple[str, np.ndarray, str, np.ndarray]
# per candidate: (collide, depth [m], distance [m], shape index in a, shape index in b)
Narrow = list[tuple[bool, float, float, int, int]]


def _link_shapes(scene: CollisionScene, link: str) -> list[Any] | None:
    shapes = []
    for s in scene.scene_shapes(link):
        if not s.content:
            return None
        shapes.append([s.content, s.pose.tolist()])
    return shapes


def contacts_key(scene: CollisionScene, candidates: Sequence[Candidate]) -> list[Any] | None:
    """The key parts of the narrow phase of ``candidates``, ``None`` when a shape's content is unknown."""
    links: dict[str, Any] = {}
    for a, _, b, _ in candidates:
        for link in (a, b):
            if link not in links:
                shapes = _link_shapes(scene, link)
                if shapes is None:
                    return None
                links[link] = shapes
    return [
        FORMAT,
        getattr(scene.backend, "name", type(scene.backend).__name__),
        links,
        [[a, ta.tolist(), b, tb.tolist()] for a, ta, b, tb in candidates],
    ]


def encode_narrow(value: Narrow) -> bytes:
    return json.dumps([list(row) for row in value], separators=(",", ":")).encode("utf-8")


def decode_narrow(payload: bytes) -> Narrow:
    rows = json.loads(payload)
    return [(bool(hit), float(depth), float(distance), int(sa), int(sb)) for hit, depth, distance, sa, sb in rows]


def stored_narrow_phase(
    scene: CollisionScene, candidates: Sequence[Candidate], compute: Callable[[], Narrow]
) -> Narrow:
    """``compute()`` (the narrow phase of ``candidates``), read from the active store when it holds it."""
    if active_store() is None or not candidates:
        return compute()
    key = contacts_key(scene, candidates)
    if key is None:
        return compute()
    found = cached(NAMESPACE, key, compute, encode_narrow, decode_narrow)
    if len(found) != len(candidates):
        return compute()  # an entry that does not answer these candidates
    return found


def stored_collisions(
    scene: CollisionScene, candidates: Sequence[Candidate], compute: Callable[[], list[bool]]
) -> list[bool]:
    """``compute()`` (whether each of ``candidates`` collides, as
    :meth:`geomcheck.collision.scene.CollisionScene.pair_collide` says), read from the active
    store when it holds it."""
    if active_store() is None or not candidates:
        return compute()
    key = contacts_key(scene, candidates)
    if key is None:
        return compute()
    found = cached(
        COLLISIONS_NAMESPACE,
        key,
        compute,
        lambda hits: json.dumps([bool(h) for h in hits]).encode("utf-8"),
        lambda payload: [bool(h) for h in json.loads(payload)],
    )
    if len(found) != len(candidates):
        return compute()  # an entry that does not answer these candidates
    return found


__all__ = ["COLLISIONS_NAMESPACE", "NAMESPACE", "stored_collisions", "stored_narrow_phase"]
