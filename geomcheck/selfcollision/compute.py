"""Computing the collision matrix (MoveIt Setup Assistant semantics, with proofs and witnesses).

Stages, cheapest first, each removing pairs from the next:

1. **Adjacent**: parent and child with geometry, or joined only through links without.
2. **Default**: in collision at the default configuration.
3. **Certified never** without any sample: rigidly joined pairs apart at the default pose
   (their distance never changes), and pairs whose sphere covers, swept over the whole
   ranges of the joints between them, stay apart.
4. **Certified never** with distance queries, for the pairs a broad-phase pilot on the first
   samples shows would be expensive to sample (covers often overlapping): exact distance at
   the centre of a box of joint values minus how far the links can move within it.
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

from geomcheck.collision.scene import CollisionScene, adjacent_pairs
from geomcheck.errors import UsageError
from geomcheck.kinematics import Kinematics
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
from geomcheck.selfcollision.paths import ancestors, common_ancestor, drivers, joint_ranges, pair_path
from geomcheck.selfcollision.sampling import CHUNK_SAMPLES, SamplingState, run_sampling, scores
from geomcheck.selfcollision.spheres import link_spheres
from geomcheck.selfcollision.witness import (
    SEARCH_STARTS,
    Approach,
    Found,
    WitnessTask,
    approach_tasks,
    closest_approach,
    search_witness,
)
from geomcheck.selfcollision.workers import Workers, shared
from geomcheck.thresholds import SelfCollisionThresholds

PILOT_MIN_QUERIES = 100  # expected collision queries that make a pair worth a distance proof [count]
PILOT_MAX_BUDGET = 1000  # distance queries allowed for one such proof [count]
LATE_PROOF_BUDGET = 32  # distance queries to certify a never-seen pair after sampling [count]
LATE_PROOF_MAX_JOINTS = 2  # only pairs with at most this many joints between them get one [count]


@dataclass(frozen=True)
class MatrixSettings:
    """How the matrix is computed: ``samples`` configurations drawn with ``seed``; Always at
    ``always_fraction`` of the samples or more; witness search below ``witness_distance``
    [m]; ``workers`` processes."""

    samples: int = 10000
    seed: int = 0
    always_fraction: float = 0.95
    witness_distance: float = 0.05
    workers: int = 2

    @classmethod
    def from_options(cls, options: CheckOptions) -> MatrixSettings:
        sc: SelfCollisionThresholds = options.thresholds.self_collision
        settings = cls(
            samples=options.samples if options.samples is not None else sc.samples,
            seed=options.seed if options.seed is not None else sc.seed,
            always_fraction=sc.always_fraction,
            witness_distance=sc.witness_distance_m,
            workers=options.workers,
        )
        settings.validate()
        return settings

    def validate(self) -> None:
        if self.samples < 1:
            raise UsageError(f"matrix samples must be at least 1, got {self.samples}")
        if not 0.0 < self.always_fraction <= 1.0:
            raise UsageError(f"always_fraction must be in (0, 1], got {self.always_fraction}")


@dataclass(frozen=True)
class _ProofTask:
    pair: int
    budget: int


def _prove(task: _ProofTask) -> tuple[float | None, int]:
    """Distance proof (stage 4 and 6) for one pair, in a worker."""
    state: SamplingState = shared()
    a, b = int(state.first[task.pair]), int(state.second[task.pair])
    name_a, name_b = state.links[a], state.links[b]
    path = pair_path(state.kin, name_a, name_b)
    if path.rigid:
        return None, 0
    certifier = PairCertifier(path, state.kin.lower, state.kin.upper, state.spheres.cover(a), state.spheres.cover(b))
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


def _joints_up_to(kin: Kinematics, link: str, top: str) -> list[str]:
    """Names of the joints from ``link`` up to its ancestor ``top``."""
    out = []
    for frame in ancestors(kin, link):
        if frame == top:
            break
        joint = kin.parent_joint(frame)
        if joint is not None:
            out.append(joint.name)
    return out


def _path_configuration(kin: Kinematics, a: str, b: str, q: np.ndarray) -> dict[str, float]:
    return {name: float(q[kin.index(name)]) for name in kin.path_joints(a, b)}


class _Builder:
    """Collects each pair's class and evidence as the stages settle them."""

    def __init__(self, names: list[tuple[str, str]]) -> None:
        self.names = names
        self.results: dict[int, PairResult] = {}

    def settle(self, pair: int, cls: PairClass, **evidence: object) -> None:
        self.results[pair] = PairResult(links=self.names[pair], cls=cls, **evidence)  # type: ignore[arg-type]

    def open(self) -> list[int]:
        return [p for p in range(len(self.names)) if p not in self.results]


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
    robot = kin.robot
    reachable = set(kin.link_names)
    links = tuple(name for name in scene.links if name in reachable)
    rows = {name: i for i, name in enumerate(links)}
    names = sorted((min(x, y), max(x, y)) for x, y in itertools.combinations(links, 2))
    first = np.array([rows[a] for a, _ in names], dtype=int)
    second = np.array([rows[b] for _, b in names], dtype=int)
    spheres = link_spheres(scene, links)
    samples = draw_samples(kin, settings)
    n = settings.samples
    free_limit = n - int(np.ceil(settings.always_fraction * n - 1e-9))
    state = SamplingState(
        kin=kin,
        scene=scene,
        spheres=spheres,
        links=links,
        kin_rows=np.array([kin.link_index(name) for name in links], dtype=int),
        first=first,
        second=second,
        samples=samples,
        free_limit=free_limit,
    )
    build = _Builder(names)
    q0 = np.asarray(default_q, dtype=float)

    # 1. Adjacent
    adjacent = adjacent_pairs(robot, links)
    for p, pair in enumerate(names):
        if pair in adjacent:
            build.settle(p, PairClass.ADJACENT)

    # 2. Default
    t0_batch = state.transforms(q0[None])
    t0 = t0_batch[0]
    open_pairs = np.array(build.open(), dtype=int)
    default_scores = scores(state, t0_batch, open_pairs)[0] if len(open_pairs) else np.zeros(0)
    for p, score in zip(open_pairs, default_scores, strict=True):
        if score > 0:
            continue
        a, b = names[p]
        hit, depth = scene.pair_collide(a, t0[first[p]], b, t0[second[p]])
        if hit:
            witness = Witness(_path_configuration(kin, a, b, q0), depth, WitnessSource.DEFAULT)
            build.settle(int(p), PairClass.DEFAULT, min_distance=-depth, witness=witness)

    # 3. Certified without samples: rigid pairs, and sphere reach over the whole ranges
    driven = drivers(kin)
    ranges = joint_ranges(kin)
    reach = {name: ancestor_reach(kin, name, spheres.cover(i), ranges) for i, name in enumerate(links)}
    certified_early = 0
    for p in build.open():
        a, b = names[p]
        top = common_ancestor(kin, a, b)
        if not any(j in driven for name in (a, b) for j in _joints_up_to(kin, name, top)):
            d = scene.pair_distance(a, t0[first[p]], b, t0[second[p]])
            if d > 0:
                build.settle(p, PairClass.NEVER, certified=True, clearance_bound=d)
                certified_early += 1
            continue
        bound = reach_clearance(reach[a], spheres.cover(first[p])[1], reach[b], spheres.cover(second[p])[1], top)
        if bound > 0:
            build.settle(p, PairClass.NEVER, certified=True, clearance_bound=bound)
            certified_early += 1

    with Workers(state, settings.workers) as workers:
        # 4. Distance proofs for pairs that would be expensive to sample
        open_pairs = np.array(build.open(), dtype=int)
        proofs: list[_ProofTask] = []
        if len(open_pairs):
            pilot = samples[: min(CHUNK_SAMPLES, n)]
            rate = (scores(state, state.transforms(pilot), open_pairs) <= 0).mean(axis=0)
            expected = rate * n
            for p, calls in zip(open_pairs, expected, strict=True):
                if calls >= PILOT_MIN_QUERIES:
                    proofs.append(_ProofTask(int(p), int(min(PILOT_MAX_BUDGET, calls // 2))))
        proof_queries = 0
        for task, (proved, queries) in zip(proofs, workers.map(_prove, proofs), strict=True):
            proof_queries += queries
            if proved is not None:
                build.settle(task.pair, PairClass.NEVER, certified=True, clearance_bound=proved)
                certified_early += 1

        # 5. Sampling
        candidates = np.array(build.open(), dtype=int)
        tally = run_sampling(workers, state, candidates, progress)
        never: list[int] = []
        for p in candidates:
            tested, hits = int(tally.tested[p]), int(tally.collisions[p])
            if hits == 0:
                never.append(int(p))
                continue
            a, b = names[p]
            hit_q = samples[tally.first_hit[p]]
            witness = Witness(_path_configuration(kin, a, b, hit_q), float(tally.first_depth[p]), WitnessSource.SAMPLE)
            always = tested == n and hits >= settings.always_fraction * n - 1e-9
            build.settle(
                int(p),
                PairClass.ALWAYS if always else PairClass.ENABLED,
                tested=tested,
                collisions=hits,
                min_distance=-float(tally.max_depth[p]),
                witness=witness,
            )

        # 6. Closest approach, witness search, late proofs
        tasks = approach_tasks(state, never, tally.top_samples, tally.top_scores)
        approaches: dict[int, Approach] = dict(zip(never, workers.map(closest_approach, tasks), strict=True))
        near = [p for p in never if approaches[p].distance < settings.witness_distance and approaches[p].closest]
        searches = [WitnessTask(p, approaches[p].closest[:SEARCH_STARTS], settings.seed) for p in near]
        found: dict[int, Found | None] = dict(zip(near, workers.map(search_witness, searches), strict=True))
        late = [
            _ProofTask(p, LATE_PROOF_BUDGET)
            for p in never
            if found.get(p) is None and len(kin.path_joints(*names[p])) <= LATE_PROOF_MAX_JOINTS
        ]
        proven = dict(zip([t.pair for t in late], workers.map(_prove, late), strict=True))
    for p in never:
        a, b = names[p]
        searched = found.get(p)
        evidence: dict[str, object] = {
            "tested": int(tally.tested[p]),
            "collisions": 0,
            "min_distance": approaches[p].distance if np.isfinite(approaches[p].distance) else None,
        }
        if searched is not None:
            config = _path_configuration(kin, a, b, searched.configuration)
            witness = Witness(config, searched.depth, WitnessSource.SEARCH)
            build.settle(p, PairClass.ENABLED, witness=witness, **evidence)
            continue
        late_bound, _ = proven.get(p, (None, 0))
        build.settle(p, PairClass.NEVER, certified=late_bound is not None, clearance_bound=late_bound, **evidence)

    pairs = tuple(build.results[p] for p in range(len(names)))
    stats = MatrixStats(
        seconds=time.perf_counter() - started,
        narrow_phase_calls=tally.queries + proof_queries,
        certified_before_sampling=certified_early,
        witness_searches=len(near),
    )
    return CollisionMatrix(
        samples=n,
        seed=settings.seed,
        backend=scene.backend.name,
        always_fraction=settings.always_fraction,
        links=links,
        pairs=pairs,
        default_configuration={j.name: float(v) for j, v in zip(kin.joints, q0, strict=True)},
        stats=stats,
    )
