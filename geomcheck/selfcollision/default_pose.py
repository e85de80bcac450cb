"""Link pairs in collision at the default pose (GC403; the matrix's *Default* class)."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from geomcheck.collision.scene import CollisionScene
from geomcheck.geometry.broadphase import overlapping_spheres
from geomcheck.kinematics import Kinematics
from geomcheck.selfcollision.contacts_cache import Candidate, Narrow, stored_collisions, stored_narrow_phase


@dataclass(frozen=True)
class PairContact:
    """Two links in collision at one configuration."""

    links: tuple[str, str]  # sorted
    depth: float  # largest penetration depth [m] (convex hulls for meshes)
    distance: float  # signed distance [m] (0 when a mesh is involved)
    shapes: tuple[int, int]  # closest shapes: indices in the scene's shapes of each link


def world_spheres(kin: Kinematics, scene: CollisionScene, links: list[str], frames: np.ndarray) -> np.ndarray:
    """World bounding spheres of ``links`` at one configuration: (n, 4) rows of centre [m] and radius [m]."""
    out = np.zeros((len(links), 4))
    for i, link in enumerate(links):
        centre, radius = scene.bounding_sphere(link)
        world = frames[kin.link_index(link)]
        out[i, :3] = world[:3, :3] @ centre + world[:3, 3]
        out[i, 3] = radius
    return out


def contacts_at(
    kin: Kinematics,
    scene: CollisionScene,
    q: np.ndarray,
    skip: Iterable[tuple[str, str]] = (),
    keep: Callable[[str, str], bool] | None = None,
) -> list[PairContact]:
    """Pairs of scene links in collision at the configuration ``q`` (n_joints,), in document
    order of the links, except the sorted pairs in ``skip`` (adjacent pairs) and those ``keep``
    rejects. A bounding-sphere test drops far pairs before any narrow-phase query."""
    links = [link for link in scene.links if link in kin.link_names]
    if len(links) < 2:
        return []
    frames = kin.link_transforms(np.asarray(q, dtype=float)[None])[0]
    spheres = world_spheres(kin, scene, links, frames)
    skipped = set(skip)
    candidates: list[Candidate] = []
    for i, j in overlapping_spheres(spheres[:, :3], spheres[:, 3]):
        a, b = links[i], links[j]
        pair = (a, b) if a < b else (b, a)
        if pair in skipped or (keep is not None and not keep(a, b)):
            continue
        candidates.append((a, frames[kin.link_index(a)], b, frames[kin.link_index(b)]))

    def narrow() -> Narrow:
        rows: Narrow = []
        for a, ta, b, tb in candidates:
            hit, depth = scene.pair_collide(a, ta, b, tb)
            if hit:
                distance, sa, sb = scene.closest(a, ta, b, tb)
                rows.append((True, depth, distance, sa, sb))
            else:
                rows.append((False, 0.0, 0.0, -1, -1))
        return rows

    out = []
    found = stored_narrow_phase(scene, candidates, narrow)
    for (a, _, b, _), (hit, depth, distance, sa, sb) in zip(candidates, found, strict=True):
        if hit:
            pair = (a, b) if a < b else (b, a)
            shapes = (sa, sb) if pair[0] == a else (sb, sa)
            out.append(PairContact(pair, depth, min(distance, 0.0), shapes))
    return out


@dataclass(frozen=True)
class PairOccupancy:
    """In how many of ``tested`` sampled poses of the joints between two links they collide."""

    collisions: int
    tested: int

    @property
    def fraction(self) -> float:
        return self.collisions / self.tested if self.tested else 0.0


def pair_occupancy(
    kin: Kinematics, scene: CollisionScene, q: np.ndarray, links: tuple[str, str], samples: int, seed: int
) -> PairOccupancy:
    """Collide the two ``links`` in ``samples`` poses drawn uniformly within the limits of the
    variables between them (mimic joints follow their leaders; the other variables keep their
    values of ``q``, which do not change the pair's relative pose). The generator is seeded with
    ``seed`` for every pair and draws the variables in the order of their names, so a pair's
    count depends neither on the other pairs nor on the order of the joints in the document."""
    a, b = links
    variables = [kin.index(name) for name in sorted(kin.path_joints(a, b))]
    if not variables or samples < 1:
        return PairOccupancy(0, 0)
    poses = np.repeat(np.asarray(q, dtype=float)[None], samples, axis=0)
    rng = np.random.default_rng(seed)
    poses[:, variables] = rng.uniform(kin.lower[variables], kin.upper[variables], size=(samples, len(variables)))
    frames = kin.link_transforms(poses, [a, b])
    candidates = [(a, f[0], b, f[1]) for f in frames]
    hits = sum(stored_collisions(scene, candidates, lambda: [scene.pair_collide(*c)[0] for c in candidates]))
    return PairOccupancy(int(hits), samples)


AXES = np.vstack([np.eye(3), -np.eye(3)])  # the six shifts tried by only_touching


def only_touching(scene: CollisionScene, a: str, ta: np.ndarray, b: str, tb: np.ndarray, shift: float) -> bool:
    """Whether links ``a`` and ``b`` (world-from-link ``ta``, ``tb``) in collision come apart
    when ``b`` moves by ``shift`` [m] along one of the world axes: their penetration depth is
    then at most ``shift``, faces meeting flush (mated CAD parts, closed fingers) rather than
    an overlap. The hulls' depth cannot tell, being that of the convex hulls of the meshes."""
    candidates: list[Candidate] = []
    for axis in AXES:
        moved = tb.copy()
        moved[:3, 3] += shift * axis
        candidates.append((a, ta, b, moved))
    # all six shifts in one step the store keeps (a warm check builds no BVH for them)
    hits = stored_collisions(scene, candidates, lambda: [scene.pair_collide(*c)[0] for c in candidates])
    return not all(hits)


def has_mesh(scene: CollisionScene, link: str) -> bool:
    """Whether some collision shape of ``link`` is a mesh (collided as its triangles)."""
    return any(getattr(s.obj, "is_mesh", False) for s in scene.scene_shapes(link))


def separation_depth(
    scene: CollisionScene, a: str, ta: np.ndarray, b: str, tb: np.ndarray, upper: float, resolution: float
) -> float:
    """How far ``b`` must move along one of the world axes for links ``a`` and ``b`` (in collision)
    to part, to within ``resolution`` [m] and at most ``upper`` [m]: a bound of their penetration
    depth as the meshes' triangles collide, where the convex hulls' depth overstates it for hollow
    or concave parts (a shell grazing a shell whose hulls overlap by centimetres)."""

    def parted(axis: np.ndarray, shift: float) -> bool:
        moved = tb.copy()
        moved[:3, 3] += shift * axis
        return not scene.pair_collide(a, ta, b, moved)[0]

    best = upper
    for axis in AXES:
        if not parted(axis, best):
            continue
        lo, hi = 0.0, best
        while hi - lo > resolution:
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if parted(axis, mid) else (mid, hi)
        best = hi
    return best
