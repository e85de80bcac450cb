"""Computing the collision matrix (MoveIt Setup Assistant semantics, with proofs and witnesses).

Stages, cheapest first, each removing pairs from the next:

1. **Adjacent**: parent and child with geometry, or joined only through links without.
2. **Default**: in collision at the default configuration.
3. **Certified never** without any sample: rigidly joined pairs apart at the default pose
   (their distance never changes), and pairs whose sphere covers, swept over the whole
   ranges of the joints between them, stay apart.
4. **Certified never** with distance queries, for the pairs that a pilot on the first samples
   shows would be expensive to sample (covers often overlapping, no collision seen): exact
   distance at the centre of a box of joint values minus how far the links can move in it.
5. **Sampling** of the rest (:mod:`geomcheck.selfcollision.sampling`): Always (in collision
   in at least ``always_fraction`` of the samples), enabled (sometimes), or never seen.
6. For pairs never seen in collision: closest approach; a **witness search** where it is
   below ``witness_distance_m``; then a cheap attempt to certify the rest.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from geomcheck.collision.scene import CollisionScene
from geomcheck.collision.topology import SEMANTICS, adjacent_pairs, excluded_pairs
from geomcheck.errors import UsageError
from geomcheck.kinematics import Kinematics
from geomcheck.model import Joint
from geomcheck.options import CheckOptions
from geomcheck.selfcollision.certify import PairCertifier, ancestor_reach, reach_clearance
from geomcheck.selfcollision.matrix import (
    CollisionMatrix,
    MatrixStats,
    PairClass,
    PairResult,
    Witness,
    WitnessSource,
)
from geomcheck.selfcollision.paths import (
    ancestors,
    drivers,
    joint_ranges,
    symmetric_variables,
)
from geomcheck.selfcollision.sampling import SamplingState, Tally, run_sampling, scores
from geomcheck.selfcollision.spheres import bound_gaps, link_spheres, world_bounds
from geomcheck.selfcollision.witness import (
    SEARCH_STARTS,
    Approach,
    ApproachTask,
    Found,
    WitnessTask,
    approach_tasks,
    closest_approach,
    search_witness,
)
from geomcheck.selfcollision.workers import Workers, shared
from geomcheck.thresholds import SelfCollisionThresholds

PILOT_SAMPLES = 500  # first samples on which the pilot judges which pairs to prove [count]
PILOT_MIN_QUERIES = 100  # expected collision queries that make a pair worth a distance proof [count]
PILOT_MAX_BUDGET = 1000  # distance queries allowed for one such proof [count]
PILOT_CHECKS = 32  # pilot samples checked for a collision before a proof is tried [count]
PILOT_BOUND_RATE = 0.5  # share of pilot samples with overlapping bounding spheres [fraction]
PILOT_SMALL_BUDGET = 64  # distance queries for a pair with few joints between its links [count]
LATE_PROOF_BUDGET = 32  # distance queries to certify a never-seen pair after sampling [count]
LATE_PROOF_MAX_JOINTS = 2  # only pairs with at most this many joints between them get one [count]
NEVER_BUNDLE = 16  # never-seen pairs sent to a worker at once when no witness search can follow [count]


@dataclass(frozen=True)
class MatrixSettings:
    """How the matrix is computed: ``samples`` configurations drawn with ``seed``; Always at
    ``always_fraction`` of the samples or more; witness search below ``witness_distance``
    [m]; ``workers`` processes; which pairs exist by ``semantics``
    (:mod:`geomcheck.collision.topology`)."""

    samples: int = 10000
    seed: int = 0
    always_fraction: float = 0.95
    witness_distance: float = 0.05
    workers: int = 2
    semantics: str = "moveit"

    @classmethod
    def from_options(cls, options: CheckOptions) -> MatrixSettings:
        sc: SelfCollisionThresholds = options.thresholds.self_collision
        settings = cls(
            samples=options.samples if options.samples is not None else sc.samples,
            seed=options.seed if options.seed is not None else sc.seed,
            always_fraction=sc.always_fraction,
            witness_distance=sc.witness_distance_m,
            workers=options.workers,
            semantics=options.semantics,
        )
        settings.validate()
        return settings

    def validate(self) -> None:
        if self.samples < 1:
            raise UsageError(f"matrix samples must be at least 1, got {self.samples}")
        if not 0.0 < self.always_fraction <= 1.0:
            raise UsageError(f"always_fraction must be in (0, 1], got {self.always_fraction}")
        if self.semantics not in SEMANTICS:
            raise UsageError.bad_choice("semantics", self.semantics, SEMANTICS)


@dataclass(frozen=True)
class _ProofTask:
    pair: int
    budget: int


def _prove(task: _ProofTask) -> tuple[float | None, int]:
    """Distance proof (stage 4 and 6) for one pair, in a worker."""
    state: SamplingState = shared()
    a, b = int(state.first[task.pair]), int(state.second[task.pair])
    name_a, name_b = state.links[a], state.links[b]
    path = state.path(task.pair)
    if set(path.variables) <= state.symmetric:
        return None, 0
    covers = state.spheres.cover(a), state.spheres.cover(b)
    certifier = PairCertifier(path, state.kin.lower, state.kin.upper, *covers, held=state.symmetric)
    base = np.zeros(len(state.kin.joints))
    variables = list(path.variables)
    scene = state.scene

    def distance(values: np.ndarray) -> np.ndarray:
        # The hulls' distance is a lower bound of the exact one while positive, and much cheaper.
        q = np.repeat(base[None, :], len(values), axis=0)
        q[:, variables] = values
        ta, tb = path.transforms(q)
        out = np.empty(len(values))
        for i in range(len(values)):
            d = scene.pair_distance_bound(name_a, ta[i], name_b, tb[i])
            out[i] = d if d > 0 else scene.pair_distance(name_a, ta[i], name_b, tb[i])
        return out

    return certifier.distance_bound(distance, 0.0, task.budget)


@dataclass(frozen=True)
class _NeverTask:
    approach: ApproachTask
    seed: int
    witness_distance: float  # [m]
    late_proof: bool  # few joints between the links: worth a cheap proof


@dataclass(frozen=True)
class _NeverResult:
    approach: Approach
    searched: bool
    found: Found | None
    bound: float | None  # proven clearance [m]


def _examine(task: _NeverTask) -> _NeverResult:
    """Stage 6 for one pair never seen in collision, in a worker."""
    pair = task.approach.pair
    approach = closest_approach(task.approach)
    searched = approach.distance < task.witness_distance and bool(approach.closest)
    found = search_witness(WitnessTask(pair, approach.closest[:SEARCH_STARTS], task.seed)) if searched else None
    bound = _prove(_ProofTask(pair, LATE_PROOF_BUDGET))[0] if found is None and task.late_proof else None
    return _NeverResult(approach, searched, found, bound)


def _examine_bundle(tasks: tuple[_NeverTask, ...]) -> list[_NeverResult]:
    """:func:`_examine` for a few pairs at once (one message to and from the worker)."""
    return [_examine(task) for task in tasks]


def _bundle(tasks: list[_NeverTask]) -> list[tuple[_NeverTask, ...]]:
    """``tasks`` in order, one per bundle while a witness search may follow (its closest
    sample's score, a lower bound of the distance, is below the search distance), then
    ``NEVER_BUNDLE`` at a time: the per-message cost of the pool matters for the many pairs
    whose closest approach is a few distance queries."""
    out: list[tuple[_NeverTask, ...]] = []
    rest: list[_NeverTask] = []
    for task in tasks:
        scores = task.approach.scores
        if not rest and len(scores) and float(scores[0]) < task.witness_distance:
            out.append((task,))
        else:
            rest.append(task)
    out.extend(tuple(rest[i : i + NEVER_BUNDLE]) for i in range(0, len(rest), NEVER_BUNDLE))
    return out


def _expensive_pairs(state: SamplingState, pairs: np.ndarray) -> list[tuple[int, int]]:
    """``(pair, distance-query budget)`` of the ``pairs`` worth a distance proof before
    sampling, judged on a pilot (the first ``PILOT_SAMPLES`` samples): pairs whose covers overlap
    often enough that sampling them would cost ``PILOT_MIN_QUERIES`` collision queries or
    more, and pairs with few joints between them whose bounding spheres overlap in most
    samples (cheap to prove, costly in the broad phase). A pair in collision in one of its
    first ``PILOT_CHECKS`` overlapping pilot samples is left out: it cannot be proven."""
    if not len(pairs):
        return []
    n = state.samples.shape[0]
    kin = state.kin
    frames = state.transforms(state.samples[: min(PILOT_SAMPLES, n)])
    bounds = world_bounds(frames, state.spheres)
    gaps = bound_gaps(bounds, state.spheres, state.first[pairs], state.second[pairs])
    bound_rate = (gaps <= 0).mean(axis=0)
    overlap = scores(state, frames, pairs, bounds, gaps) <= 0
    out = []
    for column, p in enumerate(pairs.tolist()):
        expected = overlap[:, column].mean() * n
        budget = int(min(PILOT_MAX_BUDGET, expected // 2)) if expected >= PILOT_MIN_QUERIES else 0
        if not budget and bound_rate[column] >= PILOT_BOUND_RATE:
            names = state.links[state.first[p]], state.links[state.second[p]]
            joints = [kin.index(j) for j in kin.path_joints(*names)]
            if len(set(joints) - state.symmetric) <= LATE_PROOF_MAX_JOINTS:
                budget = PILOT_SMALL_BUDGET
        if not budget:
            continue
        a, b = int(state.first[p]), int(state.second[p])
        checks = np.nonzero(overlap[:, column])[0][:PILOT_CHECKS]
        if any(state.scene.pair_collide(state.links[a], frames[s, a], state.links[b], frames[s, b])[0] for s in checks):
            continue
        out.append((p, budget))
    return out


def _joints_up_to(frames: list[str], placing: list[Joint | None], top: str) -> list[str]:
    """Names of the joints from a link up to its ancestor ``top``, given the link's
    :func:`~geomcheck.selfcollision.paths.ancestors` ``frames`` and the joint placing each."""
    out = []
    for frame, joint in zip(frames, placing, strict=True):
        if frame == top:
            break
        if joint is not None:
            out.append(joint.name)
    return out


class _Run:
    """One computation of the matrix: the shared state, and each pair's result as the stages
    settle it (pair ids index ``names``, sorted link pairs)."""

    def __init__(self, kin: Kinematics, scene: CollisionScene, default_q: np.ndarray, settings: MatrixSettings) -> None:
        self.kin, self.scene, self.settings = kin, scene, settings
        self.q0 = np.asarray(default_q, dtype=float)
        reachable = set(kin.link_names)
        links = tuple(name for name in scene.links if name in reachable)
        rows = {name: i for i, name in enumerate(links)}
        excluded = excluded_pairs(kin.robot, links, settings.semantics)
        pairs = ((min(x, y), max(x, y)) for x, y in itertools.combinations(links, 2))
        self.names = sorted(pair for pair in pairs if pair not in excluded)
        n = settings.samples
        self.state = SamplingState(
            kin=kin,
            scene=scene,
            spheres=link_spheres(scene, links),
            links=links,
            kin_rows=np.array([kin.link_index(name) for name in links], dtype=int),
            first=np.array([rows[a] for a, _ in self.names], dtype=int),
            second=np.array([rows[b] for _, b in self.names], dtype=int),
            samples=draw_samples(kin, settings),
            free_limit=n - int(np.ceil(settings.always_fraction * n - 1e-9)),
            symmetric=symmetric_variables(kin, scene),
            driven=drivers(kin),
        )
        self.results: dict[int, PairResult] = {}
        self.frames0 = self.state.transforms(self.q0[None])
        self.certified_early = 0
        self.queries = 0
        self.searches = 0

    def settle(self, pair: int, cls: PairClass, **evidence: object) -> None:
        self.results[pair] = PairResult(links=self.names[pair], cls=cls, **evidence)  # type: ignore[arg-type]

    def open(self) -> np.ndarray:
        return np.array([p for p in range(len(self.names)) if p not in self.results], dtype=int)

    def path_configuration(self, pair: int, q: np.ndarray) -> dict[str, float]:
        """Values of the joints between the pair's links in configuration ``q`` (n_joints,)."""
        return {name: float(q[self.kin.index(name)]) for name in self.kin.path_joints(*self.names[pair])}

    def adjacent_and_default(self) -> None:
        """Stages 1 and 2."""
        adjacent = adjacent_pairs(self.kin.robot, self.state.links)
        for p, pair in enumerate(self.names):
            if pair in adjacent:
                self.settle(p, PairClass.ADJACENT)
        pairs = self.open()
        if not len(pairs):
            return
        t0, first, second = self.frames0[0], self.state.first, self.state.second
        for p, score in zip(pairs, scores(self.state, self.frames0, pairs)[0], strict=True):
            if score > 0:
                continue
            a, b = self.names[p]
            hit, depth = self.scene.pair_collide(a, t0[first[p]], b, t0[second[p]])
            if hit:
                witness = Witness(self.path_configuration(p, self.q0), depth, WitnessSource.DEFAULT)
                self.settle(int(p), PairClass.DEFAULT, min_distance=-depth, witness=witness)

    def certify_without_samples(self) -> None:
        """Stage 3: rigid pairs by their constant distance, the others by sphere reach."""
        kin, state = self.kin, self.state
        driven, ranges = drivers(kin), joint_ranges(kin)
        moving = {j for j, (v, _, _) in driven.items() if kin.index(v) not in state.symmetric}
        ranges = {j: r if j in moving else (0.0, 0.0) for j, r in ranges.items()}
        covers = [state.spheres.cover(i) for i in range(len(state.links))]
        reach = {name: ancestor_reach(kin, name, covers[i], ranges) for i, name in enumerate(state.links)}
        # per link, the frames above it and the joint placing each, once instead of per pair
        above = {name: ancestors(kin, name) for name in state.links}
        placing = {name: [kin.parent_joint(frame) for frame in up] for name, up in above.items()}
        t0 = self.frames0[0]
        for p in self.open():
            (a, b), ra, rb = self.names[p], int(state.first[p]), int(state.second[p])
            above_b = set(above[b])
            top = next(x for x in above[a] if x in above_b)
            if not any(j in moving for name in (a, b) for j in _joints_up_to(above[name], placing[name], top)):
                bound = self.scene.pair_distance(a, t0[ra], b, t0[rb])
            else:
                bound = reach_clearance(reach[a], covers[ra][1], reach[b], covers[rb][1], top)
            if bound > 0:
                self.settle(int(p), PairClass.NEVER, certified=True, clearance_bound=bound)
                self.certified_early += 1

    def prove_expensive(self, workers: Workers) -> None:
        """Stage 4."""
        proofs = [_ProofTask(p, budget) for p, budget in _expensive_pairs(self.state, self.open())]
        for task, (bound, queries) in zip(proofs, workers.map(_prove, proofs), strict=True):
            self.queries += queries
            if bound is not None:
                self.settle(task.pair, PairClass.NEVER, certified=True, clearance_bound=bound)
                self.certified_early += 1

    def sample(self, workers: Workers, progress: Callable[[int], None] | None) -> tuple[list[int], Tally]:
        """Stage 5; the pairs never seen in collision, and the tallies."""
        n, samples = self.settings.samples, self.state.samples
        candidates = self.open()
        tally = run_sampling(workers, self.state, candidates, progress)
        self.queries += tally.queries
        never: list[int] = []
        for p in candidates.tolist():
            tested, hits = int(tally.tested[p]), int(tally.collisions[p])
            if hits == 0:
                never.append(p)
                continue
            first_hit = samples[tally.first_hit[p]]
            witness = Witness(self.path_configuration(p, first_hit), float(tally.first_depth[p]), WitnessSource.SAMPLE)
            always = tested == n and hits >= self.settings.always_fraction * n - 1e-9
            cls = PairClass.ALWAYS if always else PairClass.ENABLED
            self.settle(
                p, cls, tested=tested, collisions=hits, min_distance=-float(tally.max_depth[p]), witness=witness
            )
        return never, tally

    def never_seen(self, workers: Workers, never: list[int], tally: Tally) -> None:
        """Stage 6: closest approach, witness search, late proofs, one task per pair."""
        tasks = [
            _NeverTask(
                approach,
                self.settings.seed,
                self.settings.witness_distance,
                len(self.kin.path_joints(*self.names[approach.pair])) <= LATE_PROOF_MAX_JOINTS,
            )
            for approach in approach_tasks(self.state, never, tally.top_samples, tally.top_scores)
        ]
        # closest first: their witness searches run longest and should not be left for last
        tasks.sort(key=lambda t: (float(t.approach.scores[0]) if len(t.approach.scores) else np.inf, t.approach.pair))
        results = [r for bundle in workers.map(_examine_bundle, _bundle(tasks)) for r in bundle]
        for task, result in zip(tasks, results, strict=True):
            p = task.approach.pair
            self.searches += result.searched
            closest = result.approach.distance
            evidence: dict[str, object] = {
                "tested": int(tally.tested[p]),
                "min_distance": closest if np.isfinite(closest) else None,
            }
            if result.found is not None:
                config = self.path_configuration(p, result.found.configuration)
                witness = Witness(config, result.found.depth, WitnessSource.SEARCH)
                self.settle(p, PairClass.ENABLED, witness=witness, **evidence)
            else:
                certified = result.bound is not None
                self.settle(p, PairClass.NEVER, certified=certified, clearance_bound=result.bound, **evidence)

    def matrix(self, seconds: float) -> CollisionMatrix:
        stats = MatrixStats(
            seconds=seconds,
            narrow_phase_calls=self.queries,
            certified_before_sampling=self.certified_early,
            witness_searches=self.searches,
        )
        return CollisionMatrix(
            samples=self.settings.samples,
            seed=self.settings.seed,
            backend=self.scene.backend.name,
            semantics=self.settings.semantics,
            always_fraction=self.settings.always_fraction,
            links=self.state.links,
            pairs=tuple(self.results[p] for p in range(len(self.names))),
            default_configuration={j.name: float(v) for j, v in zip(self.kin.joints, self.q0, strict=True)},
            stats=stats,
        )


def draw_samples(kin: Kinematics, settings: MatrixSettings) -> np.ndarray:
    """The matrix's random configurations (samples, n_joints): uniform within the limits,
    from a generator seeded with ``settings.seed``."""
    return kin.sample(settings.samples, np.random.default_rng(settings.seed))


def compute_matrix(
    kin: Kinematics,
    scene: CollisionScene,
    default_q: np.ndarray,
    settings: MatrixSettings,
    progress: Callable[[int], None] | None = None,
) -> CollisionMatrix:
    """The collision matrix of the scene links reachable in ``kin``'s tree, with the default
    configuration ``default_q`` (n_joints,) and the samples of :func:`draw_samples`.
    ``progress(n)`` is called as samples are done."""
    settings.validate()
    started = time.perf_counter()
    run = _Run(kin, scene, default_q, settings)
    run.adjacent_and_default()
    run.certify_without_samples()
    if settings.workers > 1:
        scene.build()  # before the workers fork
    with Workers(run.state, settings.workers) as workers:
        run.prove_expensive(workers)
        never, tally = run.sample(workers, progress)
        run.never_seen(workers, never, tally)
    return run.matrix(time.perf_counter() - started)
