"""The continuous-joint sweep: exhaustive, not sampled.

For every continuous joint (see :mod:`geomcheck.selfcollision.sweep_plan` for what turns
with it) and every link pair whose relative pose the turn changes, the sweep decides over
the *whole* turn whether the pair ever comes within the contact tolerance, and finds its
smallest clearance. The turn is cut into cells (first a regular grid, ``grid_points`` per
turn); the pair's distance ``d`` is computed at each cell's centre. Within a cell of half
widths ``h`` (per swept dimension), no point moves further than ``speed . h`` (the speed
bound of the plan), so the distance anywhere in the cell is at least ``d - speed . h``:

* ``d <= contact tolerance``: contact found at the centre;
* ``d - speed . h`` above the tolerance and no more than ``clearance_resolution`` below the
  smallest clearance of interest (the margin, or the smallest clearance found when below
  it): the cell is proven clear;
* otherwise the cell is halved (along the dimension with the largest ``speed * h``) and
  both halves are evaluated, down to cells so small that ``speed . h`` is below half the
  tolerance (then the distance inside exceeds half the tolerance: no penetration).

Contact cells next to clear ones are also halved until the ends of the colliding angle
ranges are known to ``angle_resolution`` (once a pair is known to collide, cells narrower
than that are not halved further). A narrow contact between two grid points is
therefore always found: the bound of the cell that contains it cannot prove it clear.
A pair is ``proven`` unless its search ran out of its query budget. Far pairs whose bounds
(bounding spheres swept about the axis) keep them beyond the margin over the whole turn
are proven without any query. For pairs with meshes the convex hulls' distance, a lower
bound, is tried first; the exact mesh distance is computed where the hulls cannot settle
a cell. That exact query asks the links' shape pairs nearest hulls first and skips a pair
whose hulls are further than the distance already found, and, against a still link, asks
first only the triangles of its meshes that the moving link can come near over the whole
sweep (when one revolute joint turns the pair, the triangles of both links that keep within
the clearance margin of the other in radius and height about its axis:
:mod:`geomcheck.selfcollision.crop`): both give the very distance and shapes of the full
query (a caster wheel in a recess of a large base mesh costs a few hundred triangles
instead of tens of thousands). When one revolute joint turns the pair's moving link past a still one, a cell that
the halving would split is first offered to the *turn bound*
(:mod:`geomcheck.selfcollision.turn_bound`): from the two links' triangles boxed in
cylindrical coordinates about the axis, it proves without a query that the distance over
the whole cell is at least the clearance the search must resolve (so a flange that keeps
the same small clearance all round its housing is settled on the first grid instead of
being halved down to the clearance resolution). Such a pair's first grid is *screened*: only
``screen_points`` of its cells are asked first, and the turn bound is offered the others at the
clearance those found, so that a flange turning in its housing (every exact query between the
two meshes costing milliseconds) is settled by a few dozen queries instead of one per grid cell;
what the bound cannot prove is asked as before. When a caster's swivel turns a wheel that
spins on its axle past a still link (two swept angles), a cell is offered to the wheel's
*solid of revolution* (:mod:`geomcheck.selfcollision.revolution`): one query per swivel angle
bounds the distance at every spin, so a cell it cannot prove yet is halved along the swivel
(its halves take the bound as their value), never along the spin; the cells are asked
nearest bound first, and the spin is searched once, where the solid comes closest, so that
the clearance to resolve is about the bound's and the far cells are proven by it alone.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, replace

import numpy as np

from geomcheck.collision.scene import CollisionScene
from geomcheck.kinematics import Kinematics
from geomcheck.progress import Progress
from geomcheck.selfcollision.crop import Reach, reach, still_parts, turning_parts
from geomcheck.selfcollision.default_pose import has_mesh
from geomcheck.selfcollision.revolution import revolution_bound
from geomcheck.selfcollision.sweep_cache import cached_pairs, pair_key
from geomcheck.selfcollision.sweep_plan import PairPlan, SweepGroup, link_motion, plan_pairs, sweep_groups
from geomcheck.selfcollision.sweep_search import CLEAR, CONTACT, PENDING, SPLIT, UNRESOLVED, PairSearch
from geomcheck.selfcollision.turn_bound import turn_bound, turning_joint
from geomcheck.thresholds import SelfCollisionThresholds

CHART_POINTS = 360  # most samples per pair in the report's polar chart [count]
PROBE_POINTS = 32  # spin angles first asked where a wheel's solid of revolution comes closest [count]
PROBE_ROUNDS = 12  # golden-section steps then narrowing the spin around the closest of them [count]
GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0  # [ratio]


@dataclass(frozen=True)
class SweepSettings:
    grid_points: int  # first grid [cells per turn]
    screen_points: int  # of that grid, the cells asked before the turn bound is tried [cells per turn]
    contact_tolerance: float  # [m]
    clearance_margin: float  # [m]
    clearance_resolution: float  # [m]
    angle_resolution: float  # [rad]
    max_queries: int  # per pair [count]
    max_queries_total: int  # of all the sweeps of one check, weighted [count]
    mesh_query_weight: int  # what one query between meshes counts in that total [count]

    @classmethod
    def from_thresholds(cls, t: SelfCollisionThresholds) -> SweepSettings:
        return cls(
            grid_points=max(4, t.sweep_grid_points),
            screen_points=max(1, t.sweep_screen_points),
            contact_tolerance=t.contact_tolerance_m,
            clearance_margin=max(t.clearance_margin_m, t.contact_tolerance_m),
            clearance_resolution=t.sweep_clearance_resolution_m,
            angle_resolution=t.sweep_angle_resolution_rad,
            max_queries=t.sweep_max_queries,
            max_queries_total=t.sweep_max_queries_total,
            mesh_query_weight=t.sweep_mesh_query_weight,
        )


@dataclass(frozen=True)
class PairSweep:
    """What the sweep found for one pair. Angles are the swept joint's values [rad] in [-pi, pi)."""

    links: tuple[str, str]  # (moving link, other link)
    adjacent: bool  # MoveIt's Adjacent pair
    min_clearance: float  # smallest distance found [m]; minus the largest depth when in contact
    min_angle: float  # angle of it (of the deepest contact when in contact) [rad]
    max_clearance: float  # largest distance found at a sample [m] (a lower bound there for meshes)
    clearance_bound: float  # proven lower bound of the distance over the turn [m] (contact: <= tolerance)
    colliding_ranges: tuple[tuple[float, float], ...]  # [rad], within [-pi, pi]
    max_depth: float  # largest penetration depth seen [m]
    proven: bool  # every cell decided within the query budget
    queries: int  # distance queries made
    shapes: tuple[int, int]  # closest shapes: indices in the scene's shapes of each link
    chart_angles: tuple[float, ...]  # [rad]
    chart_clearance: tuple[float, ...]  # smallest distance per chart bin [m]
    deepest: tuple[float, ...] = ()  # values of the group's dimensions at the deepest contact [rad]

    @property
    def colliding(self) -> bool:
        return bool(self.colliding_ranges)

    @property
    def whole_turn(self) -> bool:
        """In contact over the whole turn (of the swept joint)."""
        return self.colliding_ranges == ((-np.pi, np.pi),)


@dataclass(frozen=True)
class JointSweep:
    """The sweep of one continuous joint."""

    group: SweepGroup
    moving_links: tuple[str, ...]
    pairs: tuple[PairSweep, ...]  # pairs searched (sorted by link names)
    far_pairs: int  # pairs proven beyond the margin by their bounds alone
    grid_points: int
    shared: bool = False  # the check's budget cut its pairs' own (SweepSettings.max_queries_total)

    @property
    def proven(self) -> bool:
        return all(p.proven for p in self.pairs)


def wrap(angle: np.ndarray | float) -> np.ndarray:
    """Angles mapped to [-pi, pi)."""
    return (np.asarray(angle, dtype=float) + np.pi) % (2 * np.pi) - np.pi


class _Sweeper:
    def __init__(
        self,
        kin: Kinematics,
        scene: CollisionScene,
        q0: np.ndarray,
        settings: SweepSettings,
        group: SweepGroup,
        plans: list[PairPlan],
    ) -> None:
        self.kin, self.scene, self.q0, self.settings, self.group = kin, scene, q0, settings, group
        self.dim_index = [kin.index(name) for name in group.dimensions]
        self.searches = [
            PairSearch(
                p,
                scene,
                settings.grid_points,
                len(group.dimensions),
                functools.partial(turn_bound, kin, scene, q0, group, p),
                functools.partial(revolution_bound, kin, scene, q0, group, p, settings.clearance_margin),
            )
            for p in plans
        ]
        self.links = sorted({link for p in plans for link in p.links}, key=kin.link_index)
        self.column = {link: i for i, link in enumerate(self.links)}
        # links that stay at the default pose are placed once
        still = kin.link_transforms(q0[None], self.links)[0]
        self.still = {
            link: scene.placements(link, still[i][None])[0]
            for i, link in enumerate(self.links)
            if any(p.links[1] == link and not p.both_move for p in plans)
        }
        self._crop_meshes(still)

    def _crop_meshes(self, still: np.ndarray) -> None:
        """Give each search whose second link stays still the part of that link's meshes its
        moving link can come near (:mod:`geomcheck.selfcollision.crop`)."""
        kin, scene = self.kin, self.scene
        frames, axes = kin.link_transforms(self.q0[None])[0], kin.tree_axes(self.q0)
        reaches: dict[str, Reach] = {}  # per moving link: it meets many still ones
        for s in self.searches:
            if s.plan.both_move or not s.has_mesh:
                continue
            turning = turning_joint(kin, self.group, s.plan)
            if turning is not None:  # one joint turns it: both links cut to what keeps near in (r, z)
                axis = tuple(v[0] for v in kin.axis(turning[0], self.q0[None]))
                placed = np.stack([frames[kin.link_index(s.a)], still[self.column[s.b]]])
                keep = self.settings.clearance_margin
                s.parts_a, s.parts = turning_parts(scene, s.plan.links, placed, (axis[0], axis[1]), keep)
                continue
            if s.a not in reaches:
                motion = link_motion(kin, scene, s.a, self.group.dimensions, frames, axes)
                reaches[s.a] = reach(*motion.sphere, self.settings.clearance_margin)
            s.parts = still_parts(scene, s.b, still[self.column[s.b]], reaches[s.a])

    def target(self, s: PairSearch) -> float:
        """The clearance the search must resolve: the margin, or the smallest one found below it."""
        return min(self.settings.clearance_margin, s.best)

    def run(self) -> None:
        for s in self.searches:
            self.screen(s)
        while True:
            batches = [(s, np.flatnonzero(s.state == PENDING)) for s in self.searches]
            batches = [(s, rows) for s, rows in batches if len(rows)]
            if not batches:
                return
            configs = np.repeat(self.q0[None], sum(len(rows) for _, rows in batches), axis=0)
            at = 0
            for s, rows in batches:
                configs[at : at + len(rows)][:, self.dim_index] = s.centre[rows]
                at += len(rows)
            frames = self.kin.link_transforms(configs, self.links)
            at = 0
            for s, rows in batches:
                self.evaluate(s, rows, frames[at : at + len(rows)])
                self.classify(s, rows, frames[at : at + len(rows), self.column[s.a]])
                at += len(rows)
                if len(self.group.dimensions) == 1:
                    self.refine_boundaries(s)
                s.split(np.flatnonzero(s.state == SPLIT))

    def screen(self, s: PairSearch) -> None:
        """Ask every ``grid_points / screen_points``-th cell of the first grid of a pair whose
        moving link one joint turns past a still mesh, then offer the other cells to the turn
        bound at the clearance those cells give: a flange that keeps the same small clearance
        all round its housing (every exact query between them costs milliseconds) is then
        settled by a few queries instead of one per grid cell. The cells the bound cannot prove
        are asked as before, so the clearance found is the same to the clearance resolution."""
        step = len(s.state) // self.settings.screen_points
        if step < 2 or not s.has_mesh or s.plan.both_move or s.plan.constant or len(self.group.dimensions) != 1:
            return
        rows = np.arange(0, len(s.state), step)
        configs = np.repeat(self.q0[None], len(rows), axis=0)
        configs[:, self.dim_index] = s.centre[rows]
        frames = self.kin.link_transforms(configs, self.links)
        self.evaluate(s, rows, frames)
        self.classify(s, rows, frames[:, self.column[s.a]])
        tol, eps = self.settings.contact_tolerance, self.settings.clearance_resolution
        if s.best <= tol:  # in contact: the colliding ranges' ends are searched on the whole grid
            return
        threshold = max(self.target(s) - eps, float(np.nextafter(tol, np.inf)))
        turn = s.turn_for(threshold)
        rest = np.flatnonzero(s.state == PENDING)
        if turn is None or not len(rest):
            return
        proven = rest[turn.clear(s.centre[rest, 0], s.half[rest, 0], threshold)]
        s.floor[proven], s.state[proven] = threshold, CLEAR

    def spin_bounds(self, s: PairSearch, rows: np.ndarray, frames_a: np.ndarray) -> np.ndarray | None:
        """The solid-of-revolution bound (n,) [m] at the cells' swivel centres, or ``None``
        for a pair without one; its queries are the search's."""
        spin = s.spin_bound()
        if spin is None:
            return None
        asked = spin.queries
        bound = spin.at(s.centre[rows, 0], frames_a)
        s.queries += spin.queries - asked
        return bound

    def evaluate(self, s: PairSearch, rows: np.ndarray, frames: np.ndarray) -> None:
        tol, eps = self.settings.contact_tolerance, self.settings.clearance_resolution
        ring = self.spin_bounds(s, rows, frames[:, self.column[s.a]])
        ring_lower = np.full(len(rows), -np.inf)
        if ring is not None:
            # the halves of a cell halved for the wheel's solid of revolution (along the swivel: a
            # query at their centre could not prove them over their spin) take its bound as their
            # value, a lower bound as the hulls' is; the other cells are asked nearest bound first,
            # so that the closest distances found early prove the far cells by the bound alone. A
            # cell at the bound's cap is asked all the same: the cap is no distance to chart
            assert s.spin is not None
            by_ring = s.ring[rows]
            s.value[rows[by_ring]] = ring[by_ring]
            ask = np.flatnonzero(~by_ring)[np.argsort(ring[~by_ring], kind="stable")]
            rows, frames, ring = rows[ask], frames[ask], ring[ask]
            ring_lower = np.where(ring < s.spin.cap, ring - s.spin.speed * s.half[rows, 0], -np.inf)
            if not s.probed and len(rows) and tol < ring[0] < s.spin.cap:
                s.probed = True
                self.probe(s, s.centre[rows[0]].copy())
        slack = s.slack(rows)
        scene = self.scene
        placed_a = scene.placements(s.a, frames[:, self.column[s.a]])
        if s.plan.both_move:
            placed_b = scene.placements(s.b, frames[:, self.column[s.b]])
        else:
            placed_b = [self.still[s.b]] * len(rows)
        for k, row in enumerate(rows):
            if ring_lower[k] > tol and ring_lower[k] >= self.target(s) - eps:
                assert ring is not None
                s.value[row], s.floor[row] = ring[k], ring_lower[k]
                continue
            pa, pb = placed_a[k], placed_b[k]
            bounds = None
            if s.has_mesh:
                s.queries += 1
                bounds = scene.placed_hull_distances(s.a, pa, s.b, pb)
                bound = float(bounds.min(initial=np.inf))
                lower = bound - slack[k]
                if lower > tol and lower >= self.target(s) - eps:
                    s.value[row] = bound
                    continue
            d = self.exact(s, pa, pb, bounds, s.centre[row])
            s.value[row], s.exact[row] = d, True
            if d <= tol:
                # primitives: the distance is signed; meshes: the convex hulls' depth
                s.depth[row] = max(0.0, -(bound if s.has_mesh else d))

    def exact(self, s: PairSearch, pa: list, pb: list, bounds: np.ndarray | None, at: np.ndarray) -> float:
        """The exact distance [m] of the pair placed ``pa``, ``pb`` (at the swept values ``at``),
        kept as the search's smallest when it is."""
        s.queries += 1
        d, shape_a, shape_b = self.scene.placed_closest(s.a, pa, s.b, pb, bounds, s.parts, s.parts_a)
        if d < s.best:
            s.best, s.best_shapes, s.best_angle = d, (shape_a, shape_b), float(at[0])
        return d

    def probe(self, s: PairSearch, at: np.ndarray) -> None:
        """Search the wheel's spin at the swept values ``at`` (where its solid of revolution comes
        closest): :data:`PROBE_POINTS` spin angles, then golden-section steps around the closest.
        The solid's bound is within a facet's bulge of the closest spin, so the smallest distance
        found there lowers the clearance the search must resolve to about the bound: the other
        cells are then proven by the bound with few halvings of the swivel. Each distance is
        kept as a cell of no width (a sample of the chart)."""
        assert s.spin is not None
        dim = self.group.dimensions.index(s.spin.spin)
        scene = self.scene
        found: dict[float, float] = {}

        def ask(spin: float) -> float:
            if spin not in found:
                config = at.copy()
                config[dim] = spin
                q = self.q0.copy()
                q[self.dim_index] = config
                frames = self.kin.link_transforms(q[None], [s.a, s.b])[0]
                pa = scene.placements(s.a, frames[0][None])[0]
                pb = scene.placements(s.b, frames[1][None])[0] if s.plan.both_move else self.still[s.b]
                s.queries += 1
                found[spin] = self.exact(s, pa, pb, scene.placed_hull_distances(s.a, pa, s.b, pb), config)
            return found[spin]

        step = 2 * np.pi / PROBE_POINTS
        start = float(at[dim]) - np.pi
        spins = [start + step * k for k in range(PROBE_POINTS)]
        best = min(spins, key=ask)
        lo, hi = best - step, best + step
        left, right = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
        for _ in range(PROBE_ROUNDS):
            if ask(left) <= ask(right):
                hi, right = right, left
                left = hi - GOLDEN * (hi - lo)
            else:
                lo, left = left, right
                right = lo + GOLDEN * (hi - lo)
        spins = sorted(found)
        m = len(spins)
        centre = np.repeat(at[None], m, axis=0)
        centre[:, dim] = spins
        everything = np.ones(len(s.state), dtype=bool)
        values = np.array([found[v] for v in spins])
        s.add(everything, centre, np.zeros((m, s.half.shape[1])), values, True, CLEAR, np.zeros(m, dtype=bool))

    def classify(self, s: PairSearch, rows: np.ndarray, frames_a: np.ndarray) -> None:
        tol, eps = self.settings.contact_tolerance, self.settings.clearance_resolution
        floor = min(eps, tol / 2)
        target = self.target(s)
        slack = s.slack(rows)
        lower = s.value[rows] - slack
        contact = s.exact[rows] & (s.value[rows] <= tol)
        settled = (lower > tol) & (lower >= target - eps)
        # the bound of the whole cell from the links' cylindrical boxes (no query): at least the
        # clearance the search must resolve, and more than the contact tolerance
        threshold = max(target - eps, float(np.nextafter(tol, np.inf)))
        if not (settled | contact).all() and (turn := s.turn_for(threshold)) is not None:
            proven = ~settled & ~contact & turn.clear(s.centre[rows, 0], s.half[rows, 0], threshold)
            s.floor[rows[proven]] = threshold
            settled |= proven
        open_ = ~settled & ~contact
        s.along_first = np.zeros(0, dtype=int)
        if open_.any() and (bound := self.spin_bounds(s, rows[open_], frames_a[open_])) is not None:
            # the wheel's solid of revolution: a bound over every spin, so a cell it cannot prove yet
            # is halved along the swivel when the bound at its centre is above the threshold
            assert s.spin is not None
            lower = bound - s.spin.speed * s.half[rows[open_], 0]
            proven = (lower > tol) & (lower >= threshold)
            s.floor[rows[open_][proven]] = lower[proven]
            settled[np.flatnonzero(open_)[proven]] = True
            s.along_first = rows[open_][~proven & (bound > threshold)]
        # no penetration inside: the distance at the centre (or the bound there) is above the tolerance
        tiny = (slack <= floor) & (s.exact[rows] | (s.value[rows] > tol))
        if s.best <= tol:
            # the pair is known to collide: what is left to find are the ends of the colliding
            # ranges, so a cell narrower than the angle resolution needs no more halving
            tiny |= s.half[rows, 0] <= self.settings.angle_resolution / 2
        state = np.where(contact, CONTACT, np.where(settled | tiny, CLEAR, SPLIT))
        if s.best <= tol and len(self.group.dimensions) > 1:
            # the ranges reported are along the swept joint: a cell whose angles of it lie in a range
            # already in contact, at some angle of the joints below, would not change them
            s.state[rows] = state
            state = np.where((state == SPLIT) & self.within_contact(s, rows), CLEAR, state)
        over = s.queries + 2 * int((state == SPLIT).sum()) > self.settings.max_queries * (2 if s.has_mesh else 1)
        if over:
            state = np.where(state == SPLIT, UNRESOLVED, state)
        s.state[rows] = state

    @staticmethod
    def within_contact(s: PairSearch, rows: np.ndarray) -> np.ndarray:
        """Whether each cell ``rows`` spans angles of the swept joint (its first dimension) that lie
        within the union of the contact cells' angles: bool (n,)."""
        ranges = contact_ranges(s)
        if not ranges:
            return np.zeros(len(rows), dtype=bool)
        lo = wrap(s.centre[rows, 0] - s.half[rows, 0])
        hi = lo + 2 * s.half[rows, 0]
        inside = np.zeros(len(rows), dtype=bool)
        for a, b in ranges:  # a cell across +-pi meets two ranges: it stays to be halved
            inside |= (lo >= a - 1e-12) & (hi <= b + 1e-12)
        return inside

    def refine_boundaries(self, s: PairSearch) -> None:
        """Halve contact cells next to non-contact cells until the range ends are resolved."""
        if not (s.state == CONTACT).any() or s.queries >= self.settings.max_queries:
            return
        order = np.argsort(s.centre[:, 0], kind="stable")
        contact = s.state[order] == CONTACT
        border = contact & ~(np.roll(contact, 1) & np.roll(contact, -1))
        wide = s.half[order, 0] > self.settings.angle_resolution / 2
        rows = order[border & wide]
        s.state[rows] = SPLIT

    # ------------------------------------------------------------------ results
    def result(self, s: PairSearch) -> PairSweep:
        contact = s.state == CONTACT
        primary = s.centre[:, 0]
        at: tuple[float, ...] = ()
        ranges = contact_ranges(s)
        clear = ~contact
        lower = np.maximum(s.value[clear] - s.slack(clear), s.floor[clear])
        bound = float(lower.min()) if clear.any() else -np.inf
        if s.turn is not None and s.turn.whole_turn > 0:  # a gap at every angle (0: boxes overlap, no proof)
            bound = max(bound, s.turn.whole_turn)
        if contact.any():
            deepest = int(np.flatnonzero(contact)[np.argmax(s.depth[contact])])
            max_depth = float(s.depth[deepest])
            min_clearance, min_angle = -max_depth, float(wrap(primary[deepest]))
            at = tuple(float(v) for v in s.centre[deepest])
            bound = min_clearance  # in contact: the distance is down to minus the depth
        elif np.isfinite(s.best):  # the smallest distance computed exactly (halved cells included)
            max_depth, min_clearance, min_angle = 0.0, s.best, float(wrap(s.best_angle))
        else:  # every cell settled by the convex hulls: their smallest distance, a lower bound
            best = int(np.argmin(s.value))
            max_depth, min_clearance, min_angle = 0.0, float(s.value[best]), float(wrap(primary[best]))
        if s.plan.constant:  # the same clearance all round: one value per chart bin
            bins = min(self.settings.grid_points, CHART_POINTS)
            angles, clearance = chart(-np.pi + 2 * np.pi * np.arange(bins) / bins, np.full(bins, s.value[0]), bins)
        else:
            angles, clearance = chart(primary, s.value, self.settings.grid_points)
        return PairSweep(
            links=s.plan.links,
            adjacent=s.plan.adjacent,
            min_clearance=min_clearance,
            min_angle=min_angle,
            max_clearance=float(asked.max()) if len(asked := s.value[np.isfinite(s.value)]) else np.inf,
            clearance_bound=bound,
            colliding_ranges=ranges,
            max_depth=max_depth,
            proven=not (s.state == UNRESOLVED).any(),
            queries=s.queries,
            shapes=s.best_shapes,
            chart_angles=angles,
            chart_clearance=clearance,
            deepest=at,
        )


def contact_ranges(s: PairSearch) -> tuple[tuple[float, float], ...]:
    """The angles of the swept joint (the cells' first dimension) that ``s``'s contact cells span, merged [rad]."""
    contact = s.state == CONTACT
    lo, hi = s.centre[contact, 0] - s.half[contact, 0], s.centre[contact, 0] + s.half[contact, 0]
    return merge_ranges(zip(lo, hi, strict=True))


def merge_ranges(intervals: Iterable[tuple[float, float]]) -> tuple[tuple[float, float], ...]:
    """Union of angle intervals [rad], wrapped into [-pi, pi]; a range through +-pi comes out as
    two ranges, ``[-pi, b]`` and ``[a, pi]``."""
    pieces: list[tuple[float, float]] = []
    for lo_raw, hi_raw in intervals:
        lo, hi = float(lo_raw), float(hi_raw)
        if hi - lo >= 2 * np.pi - 1e-12:
            return ((-np.pi, np.pi),)
        lo_w = float(wrap(lo))
        hi_w = lo_w + (hi - lo)
        if hi_w > np.pi:
            pieces += [(lo_w, np.pi), (-np.pi, hi_w - 2 * np.pi)]
        else:
            pieces.append((lo_w, hi_w))
    pieces.sort()
    merged: list[list[float]] = []
    for lo, hi in pieces:
        if merged and lo <= merged[-1][1] + 1e-9:
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    if len(merged) == 1 and merged[0][0] <= -np.pi + 1e-9 and merged[0][1] >= np.pi - 1e-9:
        return ((-np.pi, np.pi),)
    return tuple((lo, hi) for lo, hi in merged)


def chart(primary: np.ndarray, values: np.ndarray, grid_points: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The smallest value per chart bin (at most :data:`CHART_POINTS` over the turn), bins in angle order."""
    bins = min(grid_points, CHART_POINTS)
    width = 2 * np.pi / bins
    index = np.rint((wrap(primary) + np.pi) / width).astype(int) % bins
    lowest = np.full(bins, np.inf)
    np.minimum.at(lowest, index, values)
    keep = np.isfinite(lowest)
    angles = -np.pi + width * np.arange(bins)
    return tuple(float(a) for a in angles[keep]), tuple(float(v) for v in lowest[keep])


def sweep_joint(
    kin: Kinematics,
    scene: CollisionScene,
    q0: np.ndarray,
    adjacent: Iterable[tuple[str, str]],
    settings: SweepSettings,
    group: SweepGroup,
    budget: int | None = None,
) -> JointSweep:
    """Sweep one group (see the module docstring). ``budget``: the distance queries left to
    the check's sweeps, shared out evenly among this group's pairs when it is less than each
    pair's own budget (their searches then stop sooner, unproven: a bounded check)."""
    moving, plans = plan_pairs(kin, scene, group, q0, adjacent)
    near = [p for p in plans if p.far_bound <= settings.clearance_margin]
    own = settings.max_queries
    if budget is not None and near:
        weight = max(weight_of(scene, settings, p.links) for p in near)
        settings = replace(settings, max_queries=max(0, min(own, budget // (len(near) * weight))))

    def search(indices: list[int]) -> dict[int, PairSweep]:
        sweeper = _Sweeper(kin, scene, q0, settings, group, [near[i] for i in indices])
        sweeper.run()
        return {i: sweeper.result(s) for i, s in zip(indices, sweeper.searches, strict=True)}

    keys = [pair_key(kin, scene, q0, settings, group, plan) for plan in near]
    found = cached_pairs(keys, search, PairSweep)
    pairs = sorted(found, key=lambda p: tuple(sorted(p.links)))
    shared = settings.max_queries < own
    return JointSweep(group, moving, tuple(pairs), len(plans) - len(near), settings.grid_points, shared)


def weight_of(scene: CollisionScene, settings: SweepSettings, links: Iterable[str]) -> int:
    """What one query of the pair ``links`` counts in the check's budget of sweep queries."""
    return settings.mesh_query_weight if any(has_mesh(scene, link) for link in links) else 1


def sweep_continuous_joints(
    kin: Kinematics,
    scene: CollisionScene,
    q0: np.ndarray,
    adjacent: Iterable[tuple[str, str]],
    settings: SweepSettings,
    progress: Progress | None = None,
    groups: Sequence[SweepGroup] | None = None,
) -> Iterator[tuple[SweepGroup, JointSweep | None]]:
    """Sweep every continuous joint of the tree (``groups``: :func:`sweep_groups`'s), in document
    order, within the check's budget of queries (``settings.max_queries_total``): each group
    gets what the ones before it left, and once it is spent the rest are not swept (``None``)."""
    adjacent = set(adjacent)
    left = settings.max_queries_total
    for group in sweep_groups(kin, scene, q0) if groups is None else groups:
        swept = None
        if left > 0:
            swept = sweep_joint(kin, scene, q0, adjacent, settings, group, budget=left)
            left = max(0, left - sum(p.queries * weight_of(scene, settings, p.links) for p in swept.pairs))
        if progress is not None:
            progress.advance(note=group.joint.name)
        yield group, swept
