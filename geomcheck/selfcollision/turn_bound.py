"""A lower bound of a link pair's distance over angle intervals of one turning joint, without
distance queries: the sweep's certificate that a whole cell is clear.

When one revolute joint turns a link ``A`` past a link ``B`` that stays still, every point of
both keeps its *cylindrical* coordinates about the joint's axis: its radius ``r`` and axial
height ``z``; only ``A``'s azimuth ``phi`` shifts, by the turn. For two points at radii
``r1, r2``, heights ``z1, z2`` and azimuths at least ``delta`` apart (``delta`` in [0, pi])::

    |p - q|^2 = (r1 - r2)^2 + 2 r1 r2 (1 - cos dphi) + (z1 - z2)^2
             >= gap_r^2 + gap_z^2 + 4 a1 a2 sin^2(delta / 2)

where ``gap_r``, ``gap_z`` are the gaps between the two points' radius and height intervals
and ``a1``, ``a2`` the smallest radii. Each triangle of a mesh (each primitive, through its
support) is boxed in ``(r, z, phi)``: exact radius interval (the smallest radius is the
distance from the axis to the triangle), height interval, and azimuth interval (the whole
circle when the triangle surrounds or touches the axis). A triangle pair then keeps its
distance at or above a threshold ``T`` unless the turn brings its azimuth intervals within
``delta*`` of each other, with ``delta*`` solving the inequality above: one *forbidden arc*
of turn angles per triangle pair. A cell of the sweep whose turn interval meets no forbidden
arc is proven at least ``T`` from contact everywhere, with no query. Triangle pairs whose
``(r, z)`` boxes are ``T`` or more apart never forbid anything and are dropped once.

Near a joint the two links' facing surfaces are mostly surfaces of revolution (a flange in a
housing), so the bound is tight there, and a pair whose distance is the same small value at
every angle is proven without refining the turn to the clearance resolution.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from geomcheck.collision.scene import CollisionScene
from geomcheck.kinematics import Kinematics
from geomcheck.model import Joint
from geomcheck.selfcollision.sweep_plan import PairPlan, SweepGroup

ON_AXIS_M = 1e-12  # a triangle this close to the axis surrounds it: any azimuth [m]
ARC_PAD_RAD = 1e-9  # forbidden arcs are widened by this against rounding [rad]
CHUNK = 256  # triangles of the moving link compared at once [count]
REFINE_ROUNDS = 3  # times the triangles of close pairs are cut into four [count]
MAX_REFINED_PAIRS = 2_000_000  # no cutting that could leave more triangle pairs than this [count]
TWO_PI = 2 * np.pi


def _basis(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors completing ``direction`` to a right-handed frame (e1, e2, direction)."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(direction[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(direction, helper)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(direction, e1)


def _segment_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances from the origin to the 2D segments ``a``-``b`` (n, 2)."""
    d = b - a
    length = (d * d).sum(axis=1)
    t = np.clip(-(a * d).sum(axis=1) / np.where(length > 0, length, 1.0), 0.0, 1.0)
    closest = a + t[:, None] * d
    return np.hypot(closest[:, 0], closest[:, 1])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def triangle_boxes(triangles: np.ndarray, point: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Cylindrical boxes (n, 6) ``[r_min, r_max, z_min, z_max, phi_start, phi_width]`` of world
    triangles (n, 3, 3) about the axis through ``point`` along the unit ``direction``; azimuths
    [rad] from the right-handed basis of :func:`_basis`, width ``2 pi`` for the whole circle."""
    e1, e2 = _basis(direction)
    rel = triangles - point
    z = rel @ direction
    flat = np.stack([rel @ e1, rel @ e2], axis=-1)  # (n, 3, 2): the triangle seen along the axis
    p0, p1, p2 = flat[:, 0], flat[:, 1], flat[:, 2]
    edge = np.minimum(np.minimum(_segment_distance(p0, p1), _segment_distance(p1, p2)), _segment_distance(p2, p0))
    s0, s1, s2 = _cross(p1 - p0, -p0), _cross(p2 - p1, -p1), _cross(p0 - p2, -p2)
    around = ((s0 >= 0) & (s1 >= 0) & (s2 >= 0)) | ((s0 <= 0) & (s1 <= 0) & (s2 <= 0))
    r_min = np.where(around, 0.0, edge)
    r_max = np.hypot(flat[..., 0], flat[..., 1]).max(axis=1)
    # a triangle off the axis subtends less than half a turn: its azimuths span its corners'
    phi = np.arctan2(flat[..., 1], flat[..., 0])
    rel_phi = (phi - phi[:, :1] + np.pi) % TWO_PI - np.pi
    start = phi[:, 0] + rel_phi.min(axis=1)
    width = rel_phi.max(axis=1) - rel_phi.min(axis=1)
    full = r_min <= ON_AXIS_M
    width = np.where(full, TWO_PI, width)
    return np.stack([r_min, r_max, z.min(axis=1), z.max(axis=1), start % TWO_PI, width], axis=1)


def support_box(points: np.ndarray, pad: float, point: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """The cylindrical box (1, 6) of a convex solid given by support ``points`` (n, 3) and ``pad``:
    its radius may reach the axis and its azimuths are the whole circle."""
    rel = points - point
    z = rel @ direction
    r = np.linalg.norm(rel - z[:, None] * direction, axis=1)
    return np.array([[0.0, float(r.max()) + pad, float(z.min()) - pad, float(z.max()) + pad, 0.0, TWO_PI]])


def link_triangles(scene: CollisionScene, link: str, frame: np.ndarray) -> np.ndarray | None:
    """World triangles (n, 3, 3) of ``link``'s meshes placed at ``frame`` (4, 4); ``None`` when a
    shape is a primitive (its box cannot be refined, see :func:`link_boxes`)."""
    out = []
    for shape in scene.scene_shapes(link):
        if shape.mesh is None:
            return None
        world = frame @ shape.pose
        out.append(shape.mesh.vertices[shape.mesh.faces] @ world[:3, :3].T + world[:3, 3])
    return np.concatenate(out) if out else np.zeros((0, 3, 3))


def shape_boxes(
    scene: CollisionScene, link: str, frame: np.ndarray, point: np.ndarray, direction: np.ndarray
) -> list[np.ndarray]:
    """Per shape of ``link`` placed at ``frame`` (4, 4), in :meth:`CollisionScene.scene_shapes`
    order: the cylindrical boxes of its triangles (m, 6), or its one box (1, 6) for a primitive."""
    out = []
    for shape in scene.scene_shapes(link):
        if shape.mesh is None:
            points = shape.points @ frame[:3, :3].T + frame[:3, 3]  # support points are in the link frame
            out.append(support_box(points, shape.pad, point, direction))
            continue
        world = frame @ shape.pose
        triangles = shape.mesh.vertices[shape.mesh.faces] @ world[:3, :3].T + world[:3, 3]
        out.append(triangle_boxes(triangles, point, direction))
    return out


def link_boxes(
    scene: CollisionScene, link: str, frame: np.ndarray, point: np.ndarray, direction: np.ndarray
) -> np.ndarray:
    """Cylindrical boxes of every triangle (or primitive) of ``link`` placed at ``frame`` (4, 4)."""
    out = shape_boxes(scene, link, frame, point, direction)
    return np.concatenate(out) if out else np.zeros((0, 6))


def subdivided(triangles: np.ndarray) -> np.ndarray:
    """Each triangle (n, 3, 3) cut into four at its edges' midpoints: (4 n, 3, 3), children of
    triangle ``k`` at ``4 k .. 4 k + 3``."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
    children = [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return np.stack([np.stack(t, axis=1) for t in children], axis=1).reshape(-1, 3, 3)


def _gaps(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(r, z) gaps [m] between every box of ``a`` (n, 6) and of ``b`` (m, 6): (n, m)."""
    gr = np.maximum(0.0, np.maximum(b[None, :, 0] - a[:, None, 1], a[:, None, 0] - b[None, :, 1]))
    gz = np.maximum(0.0, np.maximum(b[None, :, 2] - a[:, None, 3], a[:, None, 2] - b[None, :, 3]))
    return np.hypot(gr, gz)


@dataclass(frozen=True)
class TurnBound:
    """Triangle pairs of a moving link ``A`` and a still link ``B`` whose ``(r, z)`` boxes are
    closer than ``cap`` [m]: what can forbid a turn interval for any threshold up to ``cap``.
    Turn angles are ``multiplier * (value - value at the default pose)`` of the swept variable."""

    cap: float  # [m]
    multiplier: float  # the joint's turn per unit of the swept variable
    origin: float  # the swept variable's default value [rad]
    rz: np.ndarray  # (k,) (r, z) gap [m]
    radii: np.ndarray  # (k,) product of the two smallest radii [m^2]
    start: np.ndarray  # (k,) turn at which the azimuth intervals start to overlap [rad]
    width: np.ndarray  # (k,) turns over which they overlap [rad] (>= 2 pi: every turn)
    _arcs: dict[float, tuple[np.ndarray, np.ndarray]] = field(
        default_factory=dict, init=False, compare=False, repr=False
    )

    @property
    def whole_turn(self) -> float:
        """A lower bound [m] of the distance at every turn: the smallest ``(r, z)`` gap (``cap``
        when no pair is closer)."""
        return float(min(self.cap, self.rz.min())) if len(self.rz) else self.cap

    def forbidden(self, threshold: float) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`merged_arcs`, kept per threshold (a search asks again each round)."""
        found = self._arcs.get(threshold)
        if found is None:
            found = self._arcs[threshold] = self.merged_arcs(threshold)
        return found

    def merged_arcs(self, threshold: float) -> tuple[np.ndarray, np.ndarray]:
        """Merged turn arcs ``(starts, ends)`` [rad] where some triangle pair may be closer than
        ``threshold`` (<= ``cap``), sorted, covering turns in [0, 2 pi) with copies a turn below."""
        close = self.rz < threshold
        if not close.any():
            return np.zeros(0), np.zeros(0)
        rz, radii, start, width = self.rz[close], self.radii[close], self.start[close], self.width[close]
        with np.errstate(divide="ignore", invalid="ignore"):
            need = (threshold**2 - rz**2) / (4 * radii)
        reach = np.where(need < 1.0, 2 * np.arcsin(np.sqrt(np.clip(need, 0.0, 1.0))), np.pi) + ARC_PAD_RAD
        lo, span = start - reach, width + 2 * reach
        if (span >= TWO_PI).any():
            return np.array([-TWO_PI]), np.array([2 * TWO_PI])
        lo = lo % TWO_PI
        lo, hi = np.concatenate([lo - TWO_PI, lo]), np.concatenate([lo - TWO_PI + span, lo + span])
        order = np.argsort(lo, kind="stable")
        lo, hi = lo[order], np.maximum.accumulate(hi[order])
        first = np.ones(len(lo), dtype=bool)
        first[1:] = lo[1:] > hi[:-1]
        group = np.cumsum(first) - 1
        ends = np.full(int(group[-1]) + 1, -np.inf)
        np.maximum.at(ends, group, hi)
        return lo[first], ends

    def clear(self, centre: np.ndarray, half: np.ndarray, threshold: float) -> np.ndarray:
        """Whether the distance is at least ``threshold`` [m] over each cell of the swept variable
        (``centre``, ``half`` width (n,) [rad]): bool (n,)."""
        if threshold > self.cap:
            return np.zeros(len(centre), dtype=bool)
        starts, ends = self.forbidden(threshold)
        if not len(starts):
            return np.ones(len(centre), dtype=bool)
        turn = (self.multiplier * (centre - self.origin)) % TWO_PI
        reach = abs(self.multiplier) * half
        lo, hi = turn - reach, turn + reach
        # the first forbidden arc ending at or after the cell's start must start after its end
        at = np.searchsorted(ends, lo, side="left")
        inside = at < len(ends)
        meets = np.zeros(len(centre), dtype=bool)
        meets[inside] = starts[at[inside]] <= hi[inside]
        # a cell reaching past a full turn also meets what lies a turn below
        wraps = hi >= TWO_PI
        if wraps.any():
            again = np.searchsorted(ends, lo[wraps] - TWO_PI, side="left")
            ok = again < len(ends)
            hit = np.zeros(int(wraps.sum()), dtype=bool)
            hit[ok] = starts[again[ok]] <= hi[wraps][ok] - TWO_PI
            meets[wraps] |= hit
        return ~meets & (reach < np.pi)


def close_pairs(a: np.ndarray, b: np.ndarray, cap: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Index pairs ``(i, j, gap)`` of the boxes ``a`` (n, 6) and ``b`` (m, 6) closer than ``cap`` in ``(r, z)``."""
    rows, cols, gaps = [], [], []
    order = np.argsort(a[:, 2], kind="stable")
    for at in range(0, len(order), CHUNK):
        chunk = a[order[at : at + CHUNK]]
        near = (
            (b[:, 2] < chunk[:, 3].max() + cap)
            & (b[:, 3] > chunk[:, 2].min() - cap)
            & (b[:, 0] < chunk[:, 1].max() + cap)
            & (b[:, 1] > chunk[:, 0].min() - cap)
        )
        index = np.flatnonzero(near)
        if not len(index):
            continue
        gap = _gaps(chunk, b[index])
        i, j = np.nonzero(gap < cap)
        rows.append(order[at + i])
        cols.append(index[j])
        gaps.append(gap[i, j])
    if not rows:
        return np.zeros(0, dtype=int), np.zeros(0, dtype=int), np.zeros(0)
    return np.concatenate(rows), np.concatenate(cols), np.concatenate(gaps)


def _pairs_bound(
    a: np.ndarray,
    b: np.ndarray,
    i: np.ndarray,
    j: np.ndarray,
    rz: np.ndarray,
    cap: float,
    multiplier: float,
    origin: float,
) -> TurnBound:
    # A's azimuths shifted by the turn meet B's from B's start minus A's end
    start = b[j, 4] - (a[i, 4] + a[i, 5])
    width = a[i, 5] + b[j, 5]
    return TurnBound(cap, multiplier, origin, rz, a[i, 0] * b[j, 0], start, width)


def pair_bound(a: np.ndarray, b: np.ndarray, cap: float, multiplier: float, origin: float) -> TurnBound:
    """The :class:`TurnBound` of the cylindrical boxes ``a`` (moving, (n, 6)) and ``b`` (still,
    (m, 6)) of :func:`triangle_boxes`, keeping the box pairs closer than ``cap`` in ``(r, z)``."""
    i, j, rz = close_pairs(a, b, cap)
    return _pairs_bound(a, b, i, j, rz, cap, multiplier, origin)


def refined_bound(
    moving: np.ndarray,
    still: np.ndarray,
    point: np.ndarray,
    direction: np.ndarray,
    cap: float,
    multiplier: float,
    origin: float,
) -> TurnBound:
    """:func:`pair_bound` of two triangle sets (n, 3, 3) and (m, 3, 3), the triangles of the
    pairs closer than ``cap`` cut into four (their boxes are tighter: a large slanted triangle's
    box is much larger than its image) for up to :data:`REFINE_ROUNDS` rounds, while the pairs
    left are not too many. Each round keeps only the pairs of pieces still closer than ``cap``."""
    a, b = triangle_boxes(moving, point, direction), triangle_boxes(still, point, direction)
    i, j, rz = close_pairs(a, b, cap)
    for _ in range(REFINE_ROUNDS):
        if not len(i) or 16 * len(i) > MAX_REFINED_PAIRS:
            break
        used_a, i = np.unique(i, return_inverse=True)
        used_b, j = np.unique(j, return_inverse=True)
        moving, still = subdivided(moving[used_a]), subdivided(still[used_b])
        a, b = triangle_boxes(moving, point, direction), triangle_boxes(still, point, direction)
        quarter = np.arange(4)
        i = (4 * i[:, None, None] + quarter[None, :, None]).repeat(4, axis=2).ravel()
        j = (4 * j[:, None, None] + quarter[None, None, :]).repeat(4, axis=1).ravel()
        pa, pb = a[i], b[j]
        gr = np.maximum(0.0, np.maximum(pb[:, 0] - pa[:, 1], pa[:, 0] - pb[:, 1]))
        gz = np.maximum(0.0, np.maximum(pb[:, 2] - pa[:, 3], pa[:, 2] - pb[:, 3]))
        rz = np.hypot(gr, gz)
        keep = rz < cap
        i, j, rz = i[keep], j[keep], rz[keep]
    return _pairs_bound(a, b, i, j, rz, cap, multiplier, origin)


def turning_joint(kin: Kinematics, group: SweepGroup, plan: PairPlan) -> tuple[Joint, str, float] | None:
    """The one revolute joint that turns ``plan``'s first link past its still second link in
    ``group``'s sweep, with its variable and multiplier, when there is one: the second link
    still, and the first one moved by one revolute joint of the group's first variable and by
    none of its other variables (a caster's housing in the sweep of the caster and its wheel:
    the wheel's angle does not move it); else ``None``."""
    if plan.both_move or plan.constant:
        return None
    drivers = [(j, kin.driver(j)) for j in kin.root_path(plan.links[0])]
    driven = [(j, d) for j, d in drivers if d is not None and d[0] in group.dimensions]
    if len(driven) != 1 or driven[0][1][0] != group.dimensions[0]:
        return None
    joint, (variable, multiplier) = driven[0]
    return (joint, variable, float(multiplier)) if joint.type in ("revolute", "continuous") else None


def turn_bound(
    kin: Kinematics, scene: CollisionScene, q0: np.ndarray, group: SweepGroup, plan: PairPlan, cap: float
) -> TurnBound | None:
    """The bound of ``plan``'s pair in ``group``'s sweep over its first variable, when one joint
    turns the pair (:func:`turning_joint`)."""
    turning = turning_joint(kin, group, plan)
    if turning is None:
        return None
    joint, variable, multiplier = turning
    moving, still = plan.links
    point, direction = (v[0] for v in kin.axis(joint, q0[None]))
    frames = kin.link_transforms(q0[None], [moving, still])[0]
    origin = float(q0[kin.index(variable)])
    mesh_a, mesh_b = link_triangles(scene, moving, frames[0]), link_triangles(scene, still, frames[1])
    if mesh_a is not None and mesh_b is not None:
        return refined_bound(mesh_a, mesh_b, point, direction, cap, float(multiplier), origin)
    a = link_boxes(scene, moving, frames[0], point, direction)
    b = link_boxes(scene, still, frames[1], point, direction)
    return pair_bound(a, b, cap, float(multiplier), origin)
