"""Closest approach and witness search for pairs that sampling never saw in collision.

*Closest approach*: exact distances at the samples whose broad-phase score (a lower bound
of the distance) is lowest, best first, stopping as soon as the next score cannot beat the
best distance found. *Witness search*: from the closest samples, drive the pair's
distance below zero over the variables on the path between the two links (the only ones
that change their relative pose) with Newton steps on its gradient; a configuration where
the links collide is a witness that the pair is not *Never*.

Both run in the matrix's workers (:func:`geomcheck.selfcollision.workers.shared` is the
:class:`~geomcheck.selfcollision.sampling.SamplingState`); everything is deterministic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geomcheck.selfcollision.descent import DEGENERATE_M, PairDistance, descend
from geomcheck.selfcollision.paths import PairPath
from geomcheck.selfcollision.sampling import SamplingState
from geomcheck.selfcollision.workers import shared

SEARCH_STARTS = 2  # closest samples the search starts from [count]
RANDOM_CANDIDATES = 256  # seeded random path configurations scored by their hulls' distance [count]
RANDOM_STARTS = 2  # of which the search also starts from the closest [count]
LOCAL_CANDIDATES = 64  # seeded random perturbations of a closest sample screened at once [count]
LOCAL_SPREAD = 0.02  # their standard deviation, as a share of each joint's range [fraction]
SEARCH_OVERSHOOT_M = 0.002  # the search aims at this penetration depth, past contact [m]


@dataclass(frozen=True)
class ApproachTask:
    pair: int
    samples: np.ndarray  # (K,) candidate samples, by increasing score
    scores: np.ndarray  # (K,) their scores [m]
    first: np.ndarray  # (K, 4, 4) world-from-link of the pair's first link at those samples
    second: np.ndarray  # (K, 4, 4) and of its second link


@dataclass(frozen=True)
class Approach:
    """Closest distance [m] found among the candidate samples, and those samples ordered by
    their exact distance (closest first); ``queries`` distance queries were made."""

    distance: float
    closest: tuple[int, ...]
    queries: int


def approach_tasks(
    state: SamplingState, pairs: list[int], samples: np.ndarray, scores: np.ndarray
) -> list[ApproachTask]:
    """Closest-approach tasks of ``pairs`` with their candidate ``samples``/``scores`` (K, P)
    (-1 for no sample), the transforms computed here in one batch."""
    chosen = samples[:, pairs]
    wanted = np.unique(chosen[chosen >= 0])
    frames = state.transforms(state.samples[wanted]) if len(wanted) else np.zeros((0, len(state.links), 4, 4))
    where = {int(s): i for i, s in enumerate(wanted)}
    tasks = []
    for p in pairs:
        ok = samples[:, p] >= 0
        idx = [where[int(s)] for s in samples[ok, p]]
        a, b = int(state.first[p]), int(state.second[p])
        tasks.append(ApproachTask(p, samples[ok, p], scores[ok, p], frames[idx, a], frames[idx, b]))
    return tasks


def closest_approach(task: ApproachTask) -> Approach:
    state: SamplingState = shared()
    a, b = int(state.first[task.pair]), int(state.second[task.pair])
    found: list[tuple[float, int]] = []
    best = np.inf
    for i, (sample, score) in enumerate(zip(task.samples, task.scores, strict=True)):
        if score >= best:
            break
        d = state.scene.pair_distance(state.links[a], task.first[i], state.links[b], task.second[i])
        found.append((d, int(sample)))
        best = min(best, d)
    found.sort()
    return Approach(float(best), tuple(s for _, s in found), len(found))


@dataclass(frozen=True)
class WitnessTask:
    pair: int
    starts: tuple[int, ...]  # samples to start from
    seed: int  # of the random starts


@dataclass(frozen=True)
class Found:
    """A colliding configuration (n_joints,) and its penetration depth [m]."""

    configuration: np.ndarray
    depth: float
    queries: int


class _Hit(Exception):
    def __init__(self, q: np.ndarray, depth: float) -> None:
        self.q = q
        self.depth = depth


def search_witness(task: WitnessTask) -> Found | None:
    """A configuration where the pair collides, or ``None``.

    A Newton descent of the pair's distance (:func:`~geomcheck.selfcollision.descent.descend`)
    over the path variables, within their limits, from each of the closest samples. Where
    that fails: from each of them, ``LOCAL_CANDIDATES`` seeded random perturbations of its
    path variables are screened at once (a collision query wherever the links' convex hulls
    overlap) and the descent starts from the one whose hulls come closest; then the same from
    the ``RANDOM_STARTS`` best of ``RANDOM_CANDIDATES`` seeded random configurations of the
    path variables."""
    state: SamplingState = shared()
    a, b = int(state.first[task.pair]), int(state.second[task.pair])
    path = state.path(task.pair)
    variables = np.array([v for v in path.variables if v not in state.symmetric], dtype=int)
    if not len(variables) or not task.starts:
        return None
    search = _WitnessSearch(state, (state.links[a], state.links[b]), path, variables)
    rng = np.random.default_rng([task.seed, task.pair])
    try:
        for start in task.starts:
            search.descend_from(state.samples[start])
        for start in task.starts:
            search.around(state.samples[start], rng)
        search.far_from(state.samples[task.starts[0]], rng)
    except _Hit as hit:
        return Found(hit.q, hit.depth, search.queries)
    return None


class _WitnessSearch:
    """One pair's witness search over its path ``variables``: every query counted, the first
    colliding configuration raised as :class:`_Hit`."""

    def __init__(self, state: SamplingState, names: tuple[str, str], path: PairPath, variables: np.ndarray) -> None:
        self.scene = state.scene
        self.names = names
        self.path = path
        self.variables = variables
        self.lower, self.upper = state.kin.lower[variables], state.kin.upper[variables]
        self.distance = PairDistance(state.scene, names, path, variables)
        self.queries = 0

    def check(self, q: np.ndarray, ta: np.ndarray, tb: np.ndarray) -> None:
        hit, depth = self.scene.pair_collide(self.names[0], ta, self.names[1], tb)
        if hit:
            raise _Hit(q, depth)

    def hull_bounds(self, ta: np.ndarray, tb: np.ndarray) -> np.ndarray:
        """Lower bounds (m,) of the distance at the pair's poses ``ta``, ``tb`` (m, 4, 4): their hulls'."""
        name_a, name_b = self.names
        return np.array([self.scene.pair_distance_bound(name_a, ta[i], name_b, tb[i]) for i in range(len(ta))])

    def screen(self, q: np.ndarray) -> np.ndarray:
        """Check the configurations (m, n_joints) whose hulls overlap; the one closest to contact."""
        self.queries += len(q)
        ta, tb = self.path.transforms(q)
        hull = self.hull_bounds(ta, tb)
        order = np.argsort(hull, kind="stable")
        for i in order[hull[order] <= 0.0]:
            self.check(q[i], ta[i], tb[i])
        return q[order[0]]

    def measure(self, q: np.ndarray, hull: bool) -> tuple[float, np.ndarray | None]:
        self.queries += 1
        d, gradient, ta, tb = self.distance.measure(q, hull)
        if d < DEGENERATE_M:
            self.check(q, ta, tb)
        return d, gradient

    def descend_from(self, base: np.ndarray) -> None:
        """Descend the pair's distance from ``base`` (n_joints,), its path variables clipped to their limits."""
        q = base.copy()
        q[self.variables] = np.clip(base[self.variables], self.lower, self.upper)
        overlap = descend(self.measure, q, self.variables, self.lower, self.upper, True, SEARCH_OVERSHOOT_M)
        if overlap is not None:
            descend(self.measure, overlap, self.variables, self.lower, self.upper, False, SEARCH_OVERSHOOT_M)

    def around(self, sample: np.ndarray, rng: np.random.Generator) -> None:
        """Descend from the closest of ``LOCAL_CANDIDATES`` random perturbations of ``sample``."""
        variables, lower, upper = self.variables, self.lower, self.upper
        spread = LOCAL_SPREAD * (upper - lower)
        local = np.repeat(sample[None, :], LOCAL_CANDIDATES, axis=0)
        local[:, variables] = np.clip(
            local[:, variables] + rng.normal(0.0, 1.0, (LOCAL_CANDIDATES, len(variables))) * spread, lower, upper
        )
        self.descend_from(self.screen(local))

    def far_from(self, sample: np.ndarray, rng: np.random.Generator) -> None:
        """Descend from the ``RANDOM_STARTS`` closest of ``RANDOM_CANDIDATES`` random configurations of
        the path variables (the others as in ``sample``)."""
        far = np.repeat(sample[None, :], RANDOM_CANDIDATES, axis=0)
        far[:, self.variables] = rng.uniform(self.lower, self.upper, (RANDOM_CANDIDATES, len(self.variables)))
        ta, tb = self.path.transforms(far)
        hull = self.hull_bounds(ta, tb)
        for i in np.argsort(hull, kind="stable")[:RANDOM_STARTS]:
            self.descend_from(self.screen(far[i : i + 1]))
