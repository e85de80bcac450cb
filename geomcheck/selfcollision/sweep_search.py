"""The cells of one pair's search in a continuous-joint sweep (:mod:`geomcheck.selfcollision.sweep`):
each a box of swept angles (its centre and half widths, one column per swept dimension), the
distance found for it and how (exact, or a bound), and its state; cells are halved in place
of their parents as the search refines, and the bounds that prove whole cells without a query
(the turn bound, a wheel's solid of revolution) are built the first time a cell needs them."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from geomcheck.collision.scene import CollisionScene, ShapePart
from geomcheck.selfcollision.default_pose import has_mesh
from geomcheck.selfcollision.revolution import RevolutionBound
from geomcheck.selfcollision.sweep_plan import PairPlan
from geomcheck.selfcollision.turn_bound import TurnBound

PENDING, CONTACT, CLEAR, SPLIT, UNRESOLVED = range(5)  # a cell's state


class PairSearch:
    """The cells of one pair's search; arrays grow as cells are halved (parents are dropped)."""

    def __init__(
        self,
        plan: PairPlan,
        scene: CollisionScene,
        grid_points: int,
        n_dims: int,
        turn: Callable[[float], TurnBound | None] = lambda cap: None,
        spin: Callable[[], RevolutionBound | None] = lambda: None,
    ):
        self.plan = plan
        self._turn = turn
        self._turn_built = False
        self.turn: TurnBound | None = None
        self._spin = spin
        self._spin_built = False
        self.spin: RevolutionBound | None = None
        self.along_first = np.zeros(0, dtype=int)  # cells ``split`` halves along the first variable
        self.a, self.b = plan.links
        self.has_mesh = any(has_mesh(scene, link) for link in plan.links)
        self.parts: tuple[ShapePart | None, ...] | None = None  # the still link's meshes near the moving one
        self.parts_a: tuple[ShapePart | None, ...] | None = None  # the moving link's near the still one
        # a constant distance needs one query, for a cell spanning the whole turn
        n = 1 if plan.constant else grid_points
        step = 2 * np.pi / n
        self.centre = np.zeros((n, n_dims))
        self.centre[:, 0] = -np.pi + step * np.arange(n) + (np.pi if plan.constant else 0.0)
        self.half = np.full((n, n_dims), np.pi)
        self.half[:, 0] = step / 2
        self.value = np.full(n, np.inf)
        self.exact = np.zeros(n, dtype=bool)
        self.depth = np.zeros(n)
        self.floor = np.full(n, -np.inf)  # a lower bound of the distance over the cell proven by ``turn`` [m]
        self.ring = np.zeros(n, dtype=bool)  # evaluated by ``spin`` alone (see :mod:`geomcheck.selfcollision.sweep`)
        self.probed = False  # the spin searched once (see :mod:`geomcheck.selfcollision.sweep`)
        self.state = np.full(n, PENDING, dtype=np.int8)
        self.queries = 0
        self.best = np.inf  # smallest exact distance found [m]
        self.best_shapes = (0, 0)
        self.best_angle = 0.0  # primary angle of ``best`` [rad]

    def turn_for(self, threshold: float) -> TurnBound | None:
        """What proves whole cells clear without a query (one turning link only), built when a
        cell first needs it (most pairs are settled by their first grid) for distances up to
        ``threshold`` [m]: the threshold of a search only decreases as it finds closer cells."""
        if not self._turn_built:
            self.turn, self._turn_built = self._turn(threshold), True
        return self.turn

    def spin_bound(self) -> RevolutionBound | None:
        """What proves a cell clear over every spin of a wheel on a swivel (two angles, one link
        spinning past a still one), built when a cell first needs it."""
        if not self._spin_built:
            self.spin, self._spin_built = self._spin(), True
        return self.spin

    def slack(self, rows: np.ndarray | slice = slice(None)) -> np.ndarray:
        return (self.half[rows] * self.plan.speed).sum(axis=1)

    def split(self, rows: np.ndarray) -> None:
        """Replace the cells ``rows`` by their two halves (pending)."""
        ring = np.isin(rows, self.along_first)
        self.along_first = np.zeros(0, dtype=int)  # row numbers change with the split
        if len(rows) == 0:
            return
        dim = np.argmax(self.half[rows] * self.plan.speed, axis=1)
        dim[ring] = 0
        pick = np.arange(len(rows))
        half = self.half[rows].copy()
        half[pick, dim] /= 2
        lo, hi = self.centre[rows].copy(), self.centre[rows].copy()
        lo[pick, dim] -= half[pick, dim]
        hi[pick, dim] += half[pick, dim]
        keep = np.ones(len(self.state), dtype=bool)
        keep[rows] = False
        m = 2 * len(rows)
        halves = (np.concatenate([lo, hi]), np.concatenate([half, half]))
        self.add(keep, *halves, np.full(m, np.inf), False, PENDING, np.concatenate([ring, ring]))

    def add(
        self,
        keep: np.ndarray,
        centre: np.ndarray,
        half: np.ndarray,
        value: np.ndarray,
        exact: bool,
        state: int,
        ring: np.ndarray,
    ) -> None:
        """Keep the cells ``keep`` (bool, one per cell) and append new ones at ``centre`` (m, d)
        with ``half`` widths, ``value`` [m], all ``exact`` or not, in ``state`` and valued by the
        wheel's solid of revolution where ``ring`` (m,) says: no depth and no floor yet."""
        m = len(centre)
        self.centre = np.concatenate([self.centre[keep], centre])
        self.half = np.concatenate([self.half[keep], half])
        self.value = np.concatenate([self.value[keep], value])
        self.exact = np.concatenate([self.exact[keep], np.full(m, exact)])
        self.depth = np.concatenate([self.depth[keep], np.zeros(m)])
        self.floor = np.concatenate([self.floor[keep], np.full(m, -np.inf)])
        self.ring = np.concatenate([self.ring[keep], ring])
        self.state = np.concatenate([self.state[keep], np.full(m, state, dtype=np.int8)])
