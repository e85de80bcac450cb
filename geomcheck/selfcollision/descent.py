"""Newton descent of a link pair's distance over the joints between the two links.

To first order, the signed distance ``d`` of two convex shapes changes as the material points
that realise it move: ``d' = n . (v_b(p_b) - v_a(p_a))`` with ``p_a``, ``p_b`` the nearest
points, ``n`` the unit normal from a to b, and ``v`` a point's velocity as one joint moves
(``w x (p - o)`` about a revolute axis ``w`` through ``o``, ``w`` along a prismatic one). From
the distance and this gradient ``g`` over the path variables, the step
``-(d + overshoot) g / |g|^2`` is the shortest one that reaches a penetration of ``overshoot``
to first order (a Newton step on the root of ``d``). Joints at a limit that the step would push
past are held there, and each step is capped to a share of every joint's range, a share that
shrinks when a step does not bring the shapes closer. A few such steps reach contact where a
derivative-free search spends a hundred distance queries.

A descent first follows the convex hulls' distance (cheap, and negative inside, so it leads
into overlap); where the hulls overlap without the shapes touching (concave meshes), a
second descent follows the shapes' own distance from there.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from geomcheck.collision.scene import CollisionScene
from geomcheck.selfcollision.paths import REVOLUTE, PairPath

DESCENT_STEPS = 16  # Newton steps per descent, one distance query each [count]
STEP_SHARE = 0.25  # largest step of a joint, as a share of its range [fraction]
MIN_STEP_SHARE = 1e-4  # the descent stops when its step share shrinks below this [fraction]
DEGENERATE_M = 1e-9  # below this distance the normal is undefined: a contact [m]
MIN_SPAN = 1e-9  # a joint range below this counts as this wide when steps are capped [rad or m]
BACKTRACK = 0.25  # a rejected step is retried this much shorter when the parabola says nothing [fraction]
BACKTRACK_MIN, BACKTRACK_MAX = 0.05, 0.5  # bounds of the parabola's shortening [fraction]


class PairDistance:
    """Signed distance of one link pair and its gradient over the search ``variables``
    (configuration indices, (m,)); configurations are full (n_joints,) vectors."""

    def __init__(self, scene: CollisionScene, names: tuple[str, str], path: PairPath, variables: np.ndarray) -> None:
        self.scene, self.names, self.path = scene, names, path
        column = {int(v): i for i, v in enumerate(variables)}
        steps = (*path.first.steps, *path.second.steps)
        self.size = len(variables)
        self.axes = np.array([s.axis for s in steps], dtype=float).reshape(-1, 3)
        self.revolute = np.array([s.kind == REVOLUTE for s in steps], dtype=bool)
        self.on_first = np.arange(len(steps)) < len(path.first.steps)
        columns = np.array([column.get(s.variable, -1) for s in steps], dtype=int)
        self.moving = columns >= 0
        self.columns = columns[self.moving]
        # a step on the first link's chain moves p_a, which enters d with a minus sign
        sign = np.where(self.on_first, -1.0, 1.0)
        self.weights = sign * np.array([s.multiplier for s in steps], dtype=float)

    def measure(self, q: np.ndarray, hull: bool) -> tuple[float, np.ndarray | None, np.ndarray, np.ndarray]:
        """``(d [m], gradient (m,) [m/rad or m/m] or None where undefined, first link's
        transform, second link's)`` at ``q``: of the convex hulls when ``hull``, else of the shapes."""
        ta, joints_a = self.path.first.transform_and_joints(q)
        tb, joints_b = self.path.second.transform_and_joints(q)
        d, pa, pb = self.scene.pair_nearest(self.names[0], ta, self.names[1], tb, hull)
        if abs(d) < DEGENERATE_M or not len(self.axes):
            return d, None, ta, tb
        normal = (pb - pa) / d  # from a to b whether apart (d > 0) or overlapping (d < 0)
        frames = np.array(joints_a + joints_b)
        w = np.einsum("kij,kj->ki", frames[:, :3, :3], self.axes)
        lever = np.where(self.on_first[:, None], pa, pb) - frames[:, :3, 3]
        # w . (lever x n): the rate at which a rotation about w moves the point along n
        turn = lever[:, [1, 2, 0]] * normal[[2, 0, 1]] - lever[:, [2, 0, 1]] * normal[[1, 2, 0]]
        rate = np.where(self.revolute, np.einsum("ki,ki->k", w, turn), w @ normal) * self.weights
        return d, np.bincount(self.columns, rate[self.moving], minlength=self.size), ta, tb


def newton_step(
    d: float,
    gradient: np.ndarray,
    x: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    span: np.ndarray,
    share: float,
    overshoot: float,
) -> np.ndarray | None:
    """The next values (m,) of the path variables ``x`` (m,) towards ``d = -overshoot`` [m]:
    joints at a limit the step pushes past held, every joint's move capped at ``share`` of its
    range ``span`` (m,); ``None`` when no joint can move the pair closer."""
    held = ((x <= lower) & (gradient > 0)) | ((x >= upper) & (gradient < 0))
    g = np.where(held, 0.0, gradient)
    norm2 = float(g @ g)
    if norm2 <= 0.0:
        return None
    step = -(d + overshoot) / norm2 * g
    largest = float(np.max(np.abs(step) / span))
    if largest > share:
        step *= share / largest
    return np.minimum(np.maximum(x + step, lower), upper)


# measure(q, hull) -> (signed distance [m], gradient over the path variables or None)
Measure = Callable[[np.ndarray, bool], tuple[float, np.ndarray | None]]


def descend(
    measure: Measure,
    q: np.ndarray,
    variables: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    hull: bool,
    overshoot: float,
) -> np.ndarray | None:
    """Newton steps from configuration ``q`` (n_joints,) over ``variables`` (m,), kept within
    ``lower``/``upper`` (m,), towards a signed distance of ``-overshoot`` [m]. ``measure`` may
    end the descent by raising (a collision found). A step that does not bring the shapes
    closer is retried shorter, at the minimum of the parabola through the distance, its slope
    and the distance at the rejected step (the shapes have no contact as deep as the overshoot:
    the minimum is where they come closest). Returns the configuration where the distance
    reached contact if ``hull`` (for the shapes' own descent), else ``None``."""
    x = q[variables]
    span = np.maximum(upper - lower, MIN_SPAN)
    d, gradient = measure(q, hull)
    share = STEP_SHARE
    for _ in range(DESCENT_STEPS):
        if d < DEGENERATE_M:
            return q if hull else None
        if gradient is None:
            return None
        nxt = newton_step(d, gradient, x, lower, upper, span, share, overshoot)
        if nxt is None:
            return None
        trial = q.copy()
        trial[variables] = nxt
        d_trial, g_trial = measure(trial, hull)
        if d_trial < d:
            q, x, d, gradient = trial, nxt, d_trial, g_trial
            share = min(STEP_SHARE, 2.0 * share)
            continue
        slope = float(gradient @ (nxt - x))  # d's rate along the step, per whole step [m]
        curvature = d_trial - d - slope
        t = -slope / (2.0 * curvature) if curvature > 0.0 and slope < 0.0 else BACKTRACK
        share = float(np.clip(t, BACKTRACK_MIN, BACKTRACK_MAX)) * float(np.max(np.abs(nxt - x) / span))
        if share < MIN_STEP_SHARE:
            return None
    return q if hull and d < DEGENERATE_M else None
