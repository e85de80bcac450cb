"""Sampling the collision matrix: random configurations, broad phase, narrow phase, tallies.

Samples are processed in fixed chunks, a fixed number of chunks per round; the chunks of a
round run in parallel and are merged in order, and pairs whose class is settled (seen in
collision *and* free too often to be Always) leave the sampling between rounds. Chunking
does not depend on the number of workers, so the result is the same with one or many.

Per chunk: forward kinematics for every sample at once; bounding-sphere gaps for every
(sample, pair), then sphere-cover gaps where the bounds overlap, all numpy; collision
queries only where the covers overlap. The cover gap is a lower bound of the distance, kept
as a *score* for choosing where to measure the closest approach of never-colliding pairs.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from geomcheck.collision.scene import CollisionScene
from geomcheck.kinematics import Kinematics
from geomcheck.selfcollision.paths import PairPath, pair_path
from geomcheck.selfcollision.spheres import LinkSpheres, bound_gaps, cover_gaps, world_bounds, world_covers
from geomcheck.selfcollision.workers import Workers, shared

CHUNK_SAMPLES = 500  # samples per chunk [count]
ROUND_CHUNKS = 2  # chunks per round, run in parallel [count]
TOP_K = 8  # lowest-score free samples kept per pair for the closest-approach search [count]


@dataclass(frozen=True)
class SamplingState:
    """What every worker needs: the robot's kinematics and collision scene, link covers
    (rows in ``links`` order), each link's row in the kinematics, the candidate pairs as
    link rows ``first``/``second`` (P,), and the samples (N, n_joints)."""

    kin: Kinematics
    scene: CollisionScene
    spheres: LinkSpheres
    links: tuple[str, ...]
    kin_rows: np.ndarray
    first: np.ndarray
    second: np.ndarray
    samples: np.ndarray
    free_limit: int  # a pair free in more samples than this cannot be Always
    symmetric: frozenset[int] = frozenset()  # variables that change no distance (paths.symmetric_variables)
    driven: Mapping[str, tuple[str, float, float]] = field(default_factory=dict)  # paths.drivers
    _paths: dict[int, PairPath] = field(default_factory=dict, init=False, repr=False, compare=False)

    def path(self, pair: int) -> PairPath:
        """The :class:`PairPath` of candidate pair ``pair`` (built once per process)."""
        found = self._paths.get(pair)
        if found is None:
            names = self.links[self.first[pair]], self.links[self.second[pair]]
            found = self._paths[pair] = pair_path(self.kin, *names, self.driven or None)
        return found

    def transforms(self, q: np.ndarray) -> np.ndarray:
        """World-from-link (b, n_links, 4, 4) of the scene links for ``q`` (b, n_joints)."""
        return self.kin.link_rows_transforms(q, self.kin_rows)


@dataclass(frozen=True)
class ChunkTask:
    start: int
    stop: int
    pairs: np.ndarray  # (P',) candidate pair ids still sampled
    prior_free: np.ndarray  # (P',) free samples before this round
    prior_hit: np.ndarray  # (P',) bool: seen in collision before this round


@dataclass(frozen=True)
class ChunkResult:
    """Tallies of one chunk for the task's pairs (P',): ``tested`` samples (fewer when the
    pair settled inside the chunk), ``collisions``, the first colliding sample (-1) and its
    depth [m], the largest depth seen [m], the ``TOP_K`` lowest scores [m] of the chunk and their samples, and the
    number of collision queries made."""

    tested: np.ndarray
    collisions: np.ndarray
    first_hit: np.ndarray
    first_depth: np.ndarray
    max_depth: np.ndarray
    top_scores: np.ndarray  # (TOP_K, P')
    top_samples: np.ndarray  # (TOP_K, P')
    queries: int
    overlap: np.ndarray  # (P',) samples with overlapping covers


def scores(
    state: SamplingState,
    transforms: np.ndarray,
    pairs: np.ndarray,
    bounds: np.ndarray | None = None,
    gaps: np.ndarray | None = None,
) -> np.ndarray:
    """Lower bounds [m] of each pair's distance in each configuration: the bounding-sphere
    gap, refined by the cover gap where the bounding spheres overlap; shape (b, P').
    ``bounds`` (:func:`world_bounds` of ``transforms``) and ``gaps`` (their
    :func:`bound_gaps` for ``pairs``, refined in place) are computed unless given."""
    fa, fb = state.first[pairs], state.second[pairs]
    if bounds is None:
        bounds = world_bounds(transforms, state.spheres)
    out = bound_gaps(bounds, state.spheres, fa, fb) if gaps is None else gaps
    s, p = np.nonzero(out <= 0)
    if len(s):
        a, b = fa[p], fb[p]
        covers = world_covers(transforms, bounds, state.spheres, np.unique(np.concatenate([a, b])))
        out[s, p] = cover_gaps(covers, bounds, state.spheres, s, a, b)
    return out


def evaluate_chunk(task: ChunkTask) -> ChunkResult:
    """Tally one chunk of samples for the task's pairs (runs in a worker)."""
    state: SamplingState = shared()
    q = state.samples[task.start : task.stop]
    b, n = q.shape[0], len(task.pairs)
    transforms = state.transforms(q)
    score = scores(state, transforms, task.pairs)
    candidate = score <= 0
    k = min(TOP_K, b)
    if k < b:
        part = np.argpartition(score, k - 1, axis=0)[:k]
        order = np.take_along_axis(part, np.argsort(np.take_along_axis(score, part, axis=0), axis=0), axis=0)
    else:
        order = np.argsort(score, axis=0, kind="stable")
    top_scores = np.full((TOP_K, n), np.inf)
    top_samples = np.full((TOP_K, n), -1, dtype=int)
    top_scores[:k] = np.take_along_axis(score, order, axis=0)
    top_samples[:k] = order + task.start
    tested = np.full(n, b, dtype=int)
    collisions = np.zeros(n, dtype=int)
    first_hit = np.full(n, -1, dtype=int)
    first_depth = np.zeros(n)
    max_depth = np.zeros(n)
    queries = 0
    collide = state.scene.pair_collide
    for col in np.nonzero(candidate.any(axis=0))[0]:
        pair = task.pairs[col]
        a, bl = int(state.first[pair]), int(state.second[pair])
        name_a, name_b = state.links[a], state.links[bl]
        free_candidates = 0
        hit_before = bool(task.prior_hit[col])
        for idx, s in enumerate(np.nonzero(candidate[:, col])[0]):
            queries += 1
            hit, depth = collide(name_a, transforms[s, a], name_b, transforms[s, bl])
            if hit:
                collisions[col] += 1
                max_depth[col] = max(max_depth[col], depth)
                if first_hit[col] < 0:
                    first_hit[col], first_depth[col] = task.start + s, depth
            else:
                free_candidates += 1
            free = int(task.prior_free[col]) + (s - idx) + free_candidates
            if (hit_before or collisions[col] > 0) and free > state.free_limit:
                tested[col] = s + 1
                break
    return ChunkResult(
        tested, collisions, first_hit, first_depth, max_depth, top_scores, top_samples, queries, candidate.sum(axis=0)
    )


@dataclass
class Tally:
    """Running totals per candidate pair (P,)."""

    tested: np.ndarray
    collisions: np.ndarray
    first_hit: np.ndarray
    first_depth: np.ndarray
    max_depth: np.ndarray
    top_scores: np.ndarray  # (TOP_K, P)
    top_samples: np.ndarray
    active: np.ndarray  # bool: still sampled
    overlaps: np.ndarray  # samples in which the covers overlapped (collision-query candidates)
    queries: int = 0

    @classmethod
    def empty(cls, n: int) -> Tally:
        return cls(
            tested=np.zeros(n, dtype=int),
            collisions=np.zeros(n, dtype=int),
            first_hit=np.full(n, -1, dtype=int),
            first_depth=np.zeros(n),
            max_depth=np.zeros(n),
            top_scores=np.full((TOP_K, n), np.inf),
            top_samples=np.full((TOP_K, n), -1, dtype=int),
            active=np.ones(n, dtype=bool),
            overlaps=np.zeros(n, dtype=int),
        )

    def merge(self, pairs: np.ndarray, result: ChunkResult, free_limit: int) -> None:
        """Add one chunk's tallies for ``pairs``; chunks are merged in sample order, and a pair
        that settled in an earlier chunk of the round ignores the later ones."""
        self.queries += result.queries
        live = self.active[pairs]
        p = pairs[live]
        self.tested[p] += result.tested[live]
        hits = result.collisions[live]
        new_first = (self.first_hit[p] < 0) & (result.first_hit[live] >= 0)
        self.first_hit[p] = np.where(new_first, result.first_hit[live], self.first_hit[p])
        self.first_depth[p] = np.where(new_first, result.first_depth[live], self.first_depth[p])
        self.collisions[p] += hits
        self.overlaps[p] += result.overlap[live]
        self.max_depth[p] = np.maximum(self.max_depth[p], result.max_depth[live])
        both_s = np.concatenate([self.top_scores[:, p], result.top_scores[:, live]])
        both_i = np.concatenate([self.top_samples[:, p], result.top_samples[:, live]])
        keep = np.lexsort((both_i, both_s), axis=0)[:TOP_K]
        self.top_scores[:, p] = np.take_along_axis(both_s, keep, axis=0)
        self.top_samples[:, p] = np.take_along_axis(both_i, keep, axis=0)
        free = self.tested[p] - self.collisions[p]
        self.active[p] = ~((self.collisions[p] > 0) & (free > free_limit))


def run_sampling(
    workers: Workers,
    state: SamplingState,
    candidates: np.ndarray,
    progress: Callable[[int], None] | None = None,
) -> Tally:
    """Sample every pair in ``candidates`` (pair ids) over all of ``state.samples``."""
    n_pairs = len(state.first)
    tally = Tally.empty(n_pairs)
    tally.active[:] = False
    tally.active[candidates] = True
    total = state.samples.shape[0]
    starts = list(range(0, total, CHUNK_SAMPLES))
    for r in range(0, len(starts), ROUND_CHUNKS):
        pairs = np.nonzero(tally.active)[0]
        if not len(pairs):
            break
        prior_free = tally.tested[pairs] - tally.collisions[pairs]
        prior_hit = tally.collisions[pairs] > 0
        tasks = [
            ChunkTask(s, min(s + CHUNK_SAMPLES, total), pairs, prior_free, prior_hit)
            for s in starts[r : r + ROUND_CHUNKS]
        ]
        for task, result in zip(tasks, workers.map(evaluate_chunk, tasks), strict=True):
            tally.merge(pairs, result, state.free_limit)
            if progress is not None:
                progress(task.stop - task.start)
    return tally
