"""Certified-never pairs: conservative bounds prove that two links can never touch.

* **Sphere reach** (no collision query, :func:`ancestor_reach`, :func:`reach_clearance`):
  each link is covered by spheres fixed in its frame. Going up the tree, a revolute joint
  sweeps a sphere's centre along an arc (enclosed by the ball on the arc's chord, or the
  whole circle for a half turn or more), a prismatic joint along a segment. If these *reach
  balls* in the frame of the two links' common ancestor, grown by the sphere radii, stay
  apart, no configuration brings the links together.
* **Lipschitz distance** (:class:`PairCertifier`): on boxes of the variables on the pair's
  tree path (the other joints do not change the pair's relative pose), the exact distance
  at the box centre minus how far any point of either link can move within the box (a joint
  moving by at most ``a`` moves a point at distance ``r`` from its axis by at most
  ``2 r sin(a / 2)``, ``r`` bounded over the box by the reach balls) is a lower bound of
  the distance everywhere in the box. Boxes too coarse to conclude are halved (branch and
  bound, up to a budget of distance queries).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from geomcheck.kinematics import Kinematics
from geomcheck.selfcollision.paths import PRISMATIC, Chain, PairPath

Cover = tuple[np.ndarray, np.ndarray]  # centres (k, 3) in the link frame [m], radii (k,) [m]


def _rotate(points: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """``points`` (R, 3) rotated about the unit ``axis`` (3,) by ``angle`` (R,) [rad] (Rodrigues)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    x, y, z = axis
    skew_t = np.array([[0.0, z, -y], [-z, 0.0, x], [y, -x, 0.0]])  # points @ skew_t == axis x points
    dot = points @ axis
    return points * c + (points @ skew_t) * s + (dot[:, None] * axis) * (1.0 - c)


def _apply(transform: np.ndarray, points: np.ndarray) -> np.ndarray:
    return points @ transform[:3, :3].T + transform[:3, 3]


@dataclass(frozen=True)
class Reach:
    """Where points fixed in a chain's link frame can be over boxes of joint values (R rows).

    ``centre`` (R, 3) and ``radius`` (R,) [m]: a ball in the ancestor frame holding every
    position; ``growth`` (R, n_steps) [m]: each step's share of the radius; ``arms`` (R,
    n_steps) [m]: the largest distance of the point from each step's axis over the box.
    """

    centre: np.ndarray
    radius: np.ndarray
    growth: np.ndarray
    arms: np.ndarray


def reach(ch: Chain, points: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> Reach:
    """The :class:`Reach` of ``points[i]`` (R, 3) while step ``j`` stays in ``[lower[i, j],
    upper[i, j]]`` (R, n_steps) ([rad] or [m])."""
    rows, n_steps = lower.shape
    centre = _apply(ch.fixed[-1], points)
    radius = np.zeros(rows)
    growth = np.zeros((rows, n_steps))
    arms = np.zeros((rows, n_steps))
    for i in range(n_steps - 1, -1, -1):
        step = ch.steps[i]
        lo, hi = lower[:, i], upper[:, i]
        along = np.outer(centre @ step.axis, step.axis)
        arm = np.linalg.norm(centre - along, axis=1)
        arms[:, i] = arm + radius
        if step.kind == PRISMATIC:
            centre = centre + np.outer(0.5 * (lo + hi), step.axis)
            grow = 0.5 * (hi - lo)
        else:
            span = hi - lo
            half_turn = span >= np.pi
            chord_mid = 0.5 * (_rotate(centre, step.axis, lo) + _rotate(centre, step.axis, hi))
            centre = np.where(half_turn[:, None], along, chord_mid)
            grow = np.where(half_turn, arm, arm * np.sin(0.5 * np.minimum(span, np.pi)))
        radius = radius + grow
        growth[:, i] = grow
        centre = _apply(ch.fixed[i], centre)
    return Reach(centre, radius, growth, arms)


class PairCertifier:
    """The Lipschitz-distance proof for one pair. ``lower``/``upper`` (n_joints,) are the configuration's
    limits; ``cover_a``/``cover_b`` the links' sphere covers (every point of a link's
    geometry lies in one of its spheres); variables in ``held`` cannot change the pair's
    distance (a wheel's spin) and are held at 0."""

    def __init__(
        self,
        path: PairPath,
        lower: np.ndarray,
        upper: np.ndarray,
        cover_a: Cover,
        cover_b: Cover,
        held: frozenset[int] = frozenset(),
    ) -> None:
        self.path = path
        self.variables = np.asarray(path.variables, dtype=int)
        keep = np.array([v not in held for v in path.variables], dtype=bool)
        self.lower = np.where(keep, lower[self.variables], 0.0)
        self.upper = np.where(keep, upper[self.variables], 0.0)
        self.cover_a, self.cover_b = cover_a, cover_b
        column = {v: i for i, v in enumerate(path.variables)}
        self._chains = (path.first, path.second)
        # per chain: each step's variable column, multiplier and offset
        self._maps = [
            (
                np.array([column[s.variable] for s in ch.steps], dtype=int),
                np.array([s.multiplier for s in ch.steps], dtype=float),
                np.array([s.offset for s in ch.steps], dtype=float),
            )
            for ch in self._chains
        ]

    def _step_boxes(self, side: int, lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each step's value range (R, n_steps) for variable boxes (R, n_vars)."""
        cols, mult, off = self._maps[side]
        a = lower[:, cols] * mult + off
        b = upper[:, cols] * mult + off
        return np.minimum(a, b), np.maximum(a, b)

    def _by_variable(self, side: int, per_step: np.ndarray) -> np.ndarray:
        """Sum a (R, n_steps) quantity over the steps of each variable: (R, n_vars)."""
        out = np.zeros((per_step.shape[0], len(self.variables)))
        np.add.at(out.T, self._maps[side][0], per_step.T)
        return out

    def _reach(self, side: int, cover: Cover, lower: np.ndarray, upper: np.ndarray) -> Reach:
        """Reach of every cover sphere centre for every box: rows are box-major (R * k)."""
        k = len(cover[1])
        lo, hi = self._step_boxes(side, np.repeat(lower, k, axis=0), np.repeat(upper, k, axis=0))
        points = np.tile(cover[0], (lower.shape[0], 1))
        return reach(self._chains[side], points, lo, hi)

    def _split(self, lower: np.ndarray, upper: np.ndarray, weight: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Halve every box along its variable of largest ``weight`` (R, n_vars)."""
        rows = np.arange(lower.shape[0])
        split = np.argmax(weight, axis=1)
        cut = 0.5 * (lower[rows, split] + upper[rows, split])
        upper_left, lower_right = upper.copy(), lower.copy()
        upper_left[rows, split] = cut
        lower_right[rows, split] = cut
        return np.concatenate([lower, lower_right]), np.concatenate([upper_left, upper])

    def _motion(self, lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """How far any point of either link can move from its place at the box centre:
        total (R,) [m] and per variable (R, n_vars)."""
        n = lower.shape[0]
        per_var = np.zeros((n, len(self.variables)))
        for side, cover in ((0, self.cover_a), (1, self.cover_b)):
            k = len(cover[1])
            r = self._reach(side, cover, lower, upper)
            arms = (r.arms + np.tile(cover[1], n)[:, None]).reshape(n, k, -1).max(axis=1)
            lo, hi = self._step_boxes(side, lower, upper)
            half = 0.5 * (hi - lo)
            kinds = np.array([s.kind for s in self._chains[side].steps], dtype=int)
            chord = 2.0 * arms * np.sin(0.5 * np.minimum(half, np.pi))
            move = np.where(kinds == PRISMATIC, half, chord)
            per_var += self._by_variable(side, move)
        return per_var.sum(axis=1), per_var

    def distance_bound(
        self, distance: Callable[[np.ndarray], np.ndarray], margin: float = 0.0, budget: int = 256
    ) -> tuple[float | None, int]:
        """Proven clearance [m] from exact distances and motion bounds, or ``None``; and the
        number of distance queries made. ``distance(values)`` gives the pair's distance [m]
        for path-variable values (R, n_vars), shape (R,). Stops early (``None``) when a box
        centre is itself within ``margin``: no finer box can help there."""
        lower, upper = self.lower[None, :], self.upper[None, :]
        queries, best = 0, np.inf
        while lower.shape[0]:
            queries += lower.shape[0]
            if queries > budget:
                return None, queries - lower.shape[0]
            d = distance(0.5 * (lower + upper))
            if (d <= margin).any():
                return None, queries
            total, per_var = self._motion(lower, upper)
            bound = d - total
            done = bound > margin
            if done.any():
                best = min(best, float(bound[done].min()))
            lower, upper = lower[~done], upper[~done]
            if lower.shape[0]:
                lower, upper = self._split(lower, upper, per_var[~done])
        return float(best), queries


def ancestor_reach(
    kin: Kinematics, link: str, cover: Cover, ranges: Mapping[str, tuple[float, float]]
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Reach of a link's cover spheres in the frame of each of its ancestors (and its own):
    ``{frame: (centres (k, 3) [m], growth (k,) [m])}``, every joint in ``ranges`` over its
    whole range; a sphere's positions lie within ``growth`` of its centre."""
    centres = np.asarray(cover[0], dtype=float)
    growth = np.zeros(len(centres))
    out = {link: (centres, growth)}
    frame = link
    while (joint := kin.parent_joint(frame)) is not None:
        axis = np.asarray(joint.axis, dtype=float)
        norm = float(np.linalg.norm(axis))
        if joint.name in ranges and norm > 0:
            axis = axis / norm
            lo, hi = ranges[joint.name]
            if joint.type == "prismatic":
                centres = centres + 0.5 * (lo + hi) * axis
                growth = growth + 0.5 * (hi - lo)
            else:
                along = np.outer(centres @ axis, axis)
                arm = np.linalg.norm(centres - along, axis=1)
                if hi - lo >= np.pi:
                    centres, growth = along, growth + arm
                else:
                    ends = [_rotate(centres, axis, np.full(len(centres), v)) for v in (lo, hi)]
                    centres, growth = 0.5 * (ends[0] + ends[1]), growth + arm * np.sin(0.5 * (hi - lo))
        centres = _apply(joint.origin.matrix(), centres)
        frame = joint.parent
        out[frame] = (centres, growth)
    return out


def reach_clearance(
    reach_a: Mapping[str, tuple[np.ndarray, np.ndarray]],
    radii_a: np.ndarray,
    reach_b: Mapping[str, tuple[np.ndarray, np.ndarray]],
    radii_b: np.ndarray,
    ancestor: str,
) -> float:
    """Lower bound [m] of two links' distance over all configurations, from their
    :func:`ancestor_reach` in the frame of their common ``ancestor``; <= 0 proves nothing."""
    ca, ga = reach_a[ancestor]
    cb, gb = reach_b[ancestor]
    dist = np.linalg.norm(ca[:, None, :] - cb[None, :, :], axis=-1)
    gap = dist - (ga + radii_a)[:, None] - (gb + radii_b)[None, :]
    return float(gap.min())
