"""A collision element refitted clear of the links it would otherwise hit.

A primitive fitted to a link's mesh encloses the mesh's convex hull, and a hull can reach
where the mesh does not: a base shell with the casters in wells under its deck has a box
that takes the wells, and the wheels turning in them. When the fitted primitive of a fix
brings self-collision findings (GC4xx) with other links, the link's own mesh is split into
boxes, each enclosing its piece of the mesh, that keep clear of those links over their
motion: their collision geometry at the default pose and over a full turn of every
continuous joint between them (the joints the sweep turns), sampled, plus the clearance
margin and the distance a point moves between two samples. Pieces are found by cutting the
mesh's points with planes of the box frame at the mesh's own vertex coordinates (where its
parts meet), each cut chosen to leave the fewest pieces that still reach the other links,
then the smallest total volume; a piece whose box is clear is kept. When the mesh itself
comes that close to the other links, or more than ``MAX_BOXES`` pieces would be needed, there
is no such fit and the fix is withdrawn. The boxes are in the link frame, or in the frame of
the fitted box when it is turned. Lengths [m].
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from geomcheck.checks import CheckContext
from geomcheck.diagnostics import Diagnostic
from geomcheck.fixes.derive import vector
from geomcheck.fixes.model import Applicability, ReplaceElement, SuggestedFix
from geomcheck.geometry.elements import CollisionElement
from geomcheck.geometry.neighbours import Neighbour, invariant
from geomcheck.geometry.primitives import least_signed_distance, volume_samples
from geomcheck.geometry.shapes import primitive_mesh
from geomcheck.geometry.surface import Surface
from geomcheck.load import LoadedDescription
from geomcheck.load.meshes import MeshStore, mesh_formats
from geomcheck.model import Pose, rpy_from_matrix
from geomcheck.options import CheckOptions

MAX_BOXES = 8  # a link's mesh is split into at most this many boxes [count]
MAX_CONFIGURATIONS = 360  # joint positions sampled for the other links' motion [count]
OTHER_SAMPLES = 400  # at least this many surface (and volume) samples per element of the other links [count]
MAX_OTHER_SAMPLES = 6000  # at most this many surface samples per element [count]
CUTS_PER_AXIS = 24  # candidate cutting planes per axis [count]
VOXELS = 250  # the other links' points are thinned to one per voxel of 1/250 of the mesh's extent [count]
OFF_VERTEX_COST = 1.05  # a cut between the mesh's vertex coordinates counts 5 % more volume [1]
MERGE_GAIN = 1.1  # two boxes are merged when the box enclosing both is at most 10 % larger [1]
MIN_PIECE_POINTS = 4  # a piece with fewer points is not cut further [count]
CONFIGURATIONS_PER_CHUNK = 16  # configurations of the other links' motion moved at once [count]
GROWN_SLACK = 1e-9  # a box is searched for points near it grown by its margin and this share more [1]


def _element_points(element: CollisionElement, rng: np.random.Generator, spacing: float) -> tuple[np.ndarray, float]:
    """Vertices and surface samples (about ``spacing`` [m] apart, fewer on a large element) of a
    collision element in its link's frame, and for a primitive samples of its volume too (n, 3);
    and the samples' spacing [m]."""
    if element.primitive is not None:
        surface = Surface.from_mesh(primitive_mesh(element.primitive), element.rotation, element.translation)
    elif element.solid is not None:
        surface = element.solid.surface
    else:
        return np.zeros((0, 3)), 0.0
    count = int(np.clip(surface.area / spacing**2, OTHER_SAMPLES, MAX_OTHER_SAMPLES))
    parts = [surface.vertices, surface.sample(count, rng)]
    if element.primitive is not None:
        inner = volume_samples(element.primitive, OTHER_SAMPLES, rng)
        parts.append(inner @ element.rotation.T + element.translation)
    return np.concatenate(parts), float(np.sqrt(surface.area / count))


def _spins_in_place(elements: list[CollisionElement], joint: str, axis: Iterable[float]) -> str | None:
    """``joint`` when every element of its child link is the same at every angle of it (a wheel's
    cylinder on its axle): turning it moves no collision geometry."""
    a = np.asarray(tuple(axis), dtype=float)
    if not np.linalg.norm(a) > 0.0:
        return None
    here = Neighbour("", joint, np.eye(3), np.zeros(3), a / np.linalg.norm(a), np.zeros(3))
    return joint if all(invariant(e, here) for e in elements) else None


@dataclass(frozen=True)
class Motion:
    """One other link's collision geometry as the continuous joints between it and the link
    turn: its ``points`` (n, 3, in its own frame) and their transforms into the link's frame,
    one per sampled configuration (b, 4, 4)."""

    points: np.ndarray
    relative: np.ndarray

    def moved(self, chunk: int = CONFIGURATIONS_PER_CHUNK) -> Iterator[np.ndarray]:
        """The points moved by ``chunk`` configurations at a time, (k * n, 3) each: never the
        whole (b, n, 3) motion at once (hundreds of megabytes for a base's casters)."""
        for first in range(0, len(self.relative), chunk):
            yield _placed(self.points, self.relative[first : first + chunk]).reshape(-1, 3)


def _placed(points: np.ndarray, relative: np.ndarray) -> np.ndarray:
    """``points`` (n, 3) under each rigid transform of ``relative`` (b, 4, 4): (b, n, 3)."""
    return points @ relative[:, :3, :3].transpose(0, 2, 1) + relative[:, None, :3, 3]


def keep_out(ctx: CheckContext, link: str, others: Iterable[str]) -> tuple[list[Motion], float]:
    """How ``others``' collision geometry moves in ``link``'s frame as the continuous joints
    between them turn (every other joint at the default pose), and how far [m] a place of
    that geometry may be from the nearest sampled point: half the move between two samples of
    the motion plus the spacing of the samples on the surface."""
    from geomcheck.checks.fit import link_elements

    kin = ctx.analyses.kinematics
    q0 = ctx.analyses.default_configuration.copy()
    rng = np.random.default_rng(ctx.thresholds.fit.seed)
    motions, step = [], 0.0
    for other in sorted(set(others)):
        elements = link_elements(ctx, ctx.robot.link_map[other])
        if isinstance(elements, str) or not elements:
            continue
        sampled = [_element_points(e, rng, ctx.thresholds.self_collision.clearance_margin_m) for e in elements]
        points = np.concatenate([p for p, _ in sampled])
        spacing = max(gap for _, gap in sampled)
        own = kin.parent_joint(other)
        spinning = _spins_in_place(elements, own.name, own.axis) if own is not None else None
        turning = [
            kin.index(name)
            for name in kin.path_joints(link, other)
            if kin.joints[kin.index(name)].type == "continuous" and name != spinning
        ]
        per = max(8, round(MAX_CONFIGURATIONS ** (1.0 / len(turning)))) if turning else 1
        grids = [np.linspace(-np.pi, np.pi, per, endpoint=False) for _ in turning]
        shape = [per] * len(turning)
        q = np.repeat(q0[None, :], int(np.prod(shape)) if turning else 1, axis=0)
        for k, values in enumerate(itertools.product(*grids)):
            q[k, turning] = values
        poses = kin.link_transforms(q, [link, other])  # (b, 2, 4, 4)
        relative = np.linalg.inv(poses[:, 0]) @ poses[:, 1]
        step = max(step, _largest_move(points, relative, shape) + spacing)
        motions.append(Motion(points, relative))
    return motions, step


def _largest_move(points: np.ndarray, relative: np.ndarray, shape: list[int]) -> float:
    """Half the sum over the turning joints of the farthest any of ``points`` (n, 3) moves
    between two neighbouring configurations of the grid ``shape`` (``relative`` (b, 4, 4) in
    its order); 0 without a turning joint. A point's move between two rigid placements is a
    convex function of the point, so its maximum over the points is at a corner of their hull:
    the corners alone give the same figure at a fraction of the cost."""
    if not shape:
        return 0.0
    corners = points[_hull_corners(points)]
    grid = _placed(corners, relative).reshape(*shape, len(corners), 3)
    gaps = [float(np.linalg.norm(grid - np.roll(grid, 1, axis=a), axis=-1).max()) for a in range(len(shape))]
    return 0.5 * sum(gaps)


def _hull_corners(points: np.ndarray) -> np.ndarray:
    """Indices of the corners of the convex hull of ``points`` (n, 3); all of them when the
    hull is flat or degenerate (qhull refuses it)."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        return np.asarray(ConvexHull(points).vertices)
    except (QhullError, ValueError):
        return np.arange(len(points))


@dataclass(frozen=True)
class Obstacles:
    """The other links' moving geometry as :func:`clear_fit` reads it: thinned to one point per
    ``voxel`` (centres, in the fitted frame) near the link, with the ``margin`` grown by the
    voxel's half-diagonal, and the least signed distance [m] of the fitted primitive to all of it
    (``None`` without one)."""

    keep: np.ndarray
    margin: float
    nearest: float | None


def obstacles(
    motions: list[Motion],
    near: tuple[np.ndarray, np.ndarray],
    rotation: np.ndarray,
    bounds: tuple[np.ndarray, np.ndarray],
    margin: float,
    fitted: tuple[Any, Pose] | None,
) -> Obstacles:
    """The points of ``motions`` within the box ``near`` (link frame), a chunk of configurations
    at a time: their least signed distance to the ``fitted`` primitive (shape, pose), and, turned
    into the fitted frame by ``rotation``, :func:`thinned` near the box ``bounds`` (that frame):
    what :func:`clear_boxes` does with them all at once, without holding them all."""
    nearest = np.inf

    def turned() -> Iterator[np.ndarray]:
        nonlocal nearest
        for motion in motions:
            for moved in motion.moved():
                moved = moved[_within(moved.T, near[0], near[1])]
                if not len(moved):
                    continue
                if fitted is not None:
                    shape, pose = fitted
                    local = (moved - np.asarray(pose.xyz)) @ pose.rotation()
                    nearest = least_signed_distance(shape, local, at_most=nearest)
                yield moved @ rotation

    keep, grown = thinned(turned(), bounds, margin)
    return Obstacles(keep, grown, None if nearest == np.inf else float(nearest))


def thinned(
    chunks: Iterable[np.ndarray], bounds: tuple[np.ndarray, np.ndarray], margin: float
) -> tuple[np.ndarray, float]:
    """The points of ``chunks`` (each (n, 3)) within ``margin`` of the box ``bounds``, thinned to
    one per voxel of a quarter of the margin (or of 1/``VOXELS`` of the box), and the margin
    grown by the voxel's half-diagonal (unchanged when none is near). A chunk at a time: the
    voxels of the union are the union of each chunk's."""
    lo, hi = bounds
    voxel = max(0.25 * margin, float((hi - lo).max()) / VOXELS)
    voxels = Voxels(lo - margin, hi + margin, voxel)
    for chunk in chunks:
        voxels.mark(chunk[_within(chunk.T, lo - margin, hi + margin)])
    centres = voxels.centres()
    if not len(centres):
        return np.zeros((0, 3)), margin
    return centres, margin + 0.5 * voxel * np.sqrt(3.0)


def _within(columns: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Which of the points whose coordinates are ``columns`` (3, n: points (n, 3) transposed)
    lie in the box ``lo``-``hi`` (faces included), (n,) bool: compared an axis at a time,
    without (n, 3) temporaries."""
    inside = (columns[0] >= lo[0]) & (columns[0] <= hi[0])
    for axis in (1, 2):
        inside &= (columns[axis] >= lo[axis]) & (columns[axis] <= hi[axis])
    return inside


def _bounds(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return points.min(axis=0), points.max(axis=0)


def _clear(lo: np.ndarray, hi: np.ndarray, keep: np.ndarray, margin: float) -> bool:
    """Whether no point of ``keep`` (3, m: coordinates by axis, each contiguous) is within
    ``margin`` of the box ``lo``-``hi``. Only a point of the box grown by the margin along each
    axis can be, and one in the box itself is: distances are computed for the rest of the grown
    box alone (a base's casters leave hundreds of thousands of points around every box tried)."""
    # grown by a hair more than the margin: a point it leaves out is farther than the margin
    # along one axis however lo - margin rounds, so the answer is the one all points give
    grown = margin * (1.0 + GROWN_SLACK)
    near = keep[:, _within(keep, lo - grown, hi + grown)]
    if near.shape[1] == 0:
        return True
    if _within(near, lo, hi).any():  # at distance 0, exactly: lo - x <= 0 <= x - hi is never rounded past 0
        return False
    points = near.T
    outside = np.maximum(np.maximum(lo - points, points - hi), 0.0)
    return bool(np.einsum("ij,ij->i", outside, outside).min() > margin * margin)


class Voxels:
    """The cubes of edge ``voxel`` [m] on the grid through the origin that hold a point, among
    those meeting the box ``lo``-``hi``: one flag per cube, so that marking millions of points
    (a caster's motion, a chunk at a time) costs no sort. At most about (``VOXELS`` + 10)^3
    flags for :func:`thinned`'s boxes (a byte each)."""

    def __init__(self, lo: np.ndarray, hi: np.ndarray, voxel: float) -> None:
        self.voxel = voxel
        self.corner = np.floor(np.asarray(lo, dtype=float) / voxel)
        self.dims = (np.floor(np.asarray(hi, dtype=float) / voxel) - self.corner).astype(np.int64) + 1
        self.flags = np.zeros(int(np.prod(self.dims)), dtype=bool)

    def mark(self, points: np.ndarray) -> None:
        """Flag the cubes holding ``points`` (n, 3), each within the box."""
        # a column at a time: the (n, 3) temporaries of millions of points cost more than the rest
        index = [(np.floor(points[:, axis] / self.voxel) - self.corner[axis]).astype(np.int64) for axis in range(3)]
        keys = index[0] * self.dims[1]
        keys += index[1]
        keys *= self.dims[2]
        keys += index[2]
        self.flags[keys] = True

    def centres(self) -> np.ndarray:
        """The centres (k, 3) of the flagged cubes, in lexicographic order."""
        keys = np.flatnonzero(self.flags)
        across, up = self.dims[1], self.dims[2]
        rows = np.column_stack((keys // (across * up), (keys // up) % across, keys % up))
        return (rows.astype(float) + self.corner) * self.voxel + 0.5 * self.voxel


def _volume(lo: np.ndarray, hi: np.ndarray) -> float:
    return float(np.prod(hi - lo))


def clear_boxes(
    points: np.ndarray, keep: np.ndarray, margin: float, cuts: np.ndarray
) -> list[tuple[np.ndarray, np.ndarray]] | None:
    """Boxes (lower, upper corners) enclosing a partition of ``points`` (n, 3) and each more
    than ``margin`` from every point of ``keep`` (m, 3), cutting at the coordinates ``cuts``
    (k, 3) (module docstring); ``None`` when no partition into ``MAX_BOXES`` boxes is clear."""
    near, grown = thinned([keep], _bounds(points), margin)
    return partition(points, near, grown, cuts)


def partition(
    points: np.ndarray, keep: np.ndarray, margin: float, cuts: np.ndarray
) -> list[tuple[np.ndarray, np.ndarray]] | None:
    """:func:`clear_boxes` on ``keep`` already thinned near ``points`` (and ``margin`` grown)."""
    axis_cuts = [np.unique(cuts[:, axis]) for axis in range(3)]  # sorted once; each piece takes its range
    done: list[tuple[np.ndarray, np.ndarray]] = []
    columns = np.ascontiguousarray(keep.T)  # by axis, as _clear reads them
    pending = [(points, columns)]
    while pending:
        piece, near = pending.pop()
        lo, hi = _bounds(piece)
        # a point of keep farther than the margin from this piece's box along one axis is farther
        # from the box and from every box inside it: its halves are judged on the rest alone
        near = near[:, _within(near, lo - margin, hi + margin)]
        if _clear(lo, hi, near, margin):
            done.append((lo, hi))
            continue
        if len(done) + len(pending) + 2 > MAX_BOXES or len(piece) < MIN_PIECE_POINTS:
            return None
        best: tuple[int, float, np.ndarray] | None = None
        for axis in range(3):
            found = _best_cut(piece, axis, axis_cuts[axis], lo, hi, near, margin)
            if found is not None and (best is None or found[:2] < best[:2]):
                best = found
        if best is None:
            return None
        left = best[2]
        pending.extend(((piece[~left], near), (piece[left], near)))
    return _merged(done, columns, margin)


def _first_blocked(boxes_lo: np.ndarray, boxes_hi: np.ndarray, near: np.ndarray, margin: float) -> int:
    """Index of the first of nested boxes (k, 3 corners each, each inside the next) that is not
    clear of ``near`` (``k`` when all are): a box holding a box that is not clear is not clear
    either, in floating point too, so a binary search asks :func:`_clear` about log2(k) boxes."""
    low, high = 0, len(boxes_lo)
    while low < high:
        mid = (low + high) // 2
        if _clear(boxes_lo[mid], boxes_hi[mid], near, margin):
            low = mid + 1
        else:
            high = mid
    return low


def _best_cut(
    piece: np.ndarray, axis: int, inside: np.ndarray, lo: np.ndarray, hi: np.ndarray, near: np.ndarray, margin: float
) -> tuple[int, float, np.ndarray] | None:
    """The cut of ``piece`` (n, 3) across ``axis`` leaving the fewest halves that are not clear of
    ``near``, then the least volume: ``(halves not clear, volume [m^3], mask of the left half)``,
    ``None`` when no candidate plane splits it. The candidates are the cuts ``inside`` the
    piece's box (sorted), thinned to ``CUTS_PER_AXIS``, then as many planes evenly spaced
    (counted ``OFF_VERTEX_COST`` times), tried in that order; the first best wins.

    The halves' boxes come from running minima and maxima over the points sorted along the axis,
    and whether each is clear from a binary search over them: the left halves grow with the
    plane, the right halves shrink."""
    planes = inside[np.searchsorted(inside, lo[axis], side="right") : np.searchsorted(inside, hi[axis], side="left")]
    if len(planes) > CUTS_PER_AXIS:
        planes = np.quantile(planes, np.linspace(0.0, 1.0, CUTS_PER_AXIS))
    even = np.linspace(lo[axis], hi[axis], CUTS_PER_AXIS + 2)[1:-1]  # where a smooth mesh has none
    places = np.concatenate((planes, even))
    costs = np.concatenate((np.ones(len(planes)), np.full(len(even), OFF_VERTEX_COST)))
    coords = piece[:, axis]
    ordered = piece[np.argsort(coords, kind="stable")]
    counts = np.searchsorted(ordered[:, axis], places, side="right")  # points left of (at) each plane
    splits = (counts > 0) & (counts < len(piece))
    if not splits.any():
        return None
    places, costs, counts = places[splits], costs[splits], counts[splits]
    left_lo, left_hi = np.minimum.accumulate(ordered, axis=0), np.maximum.accumulate(ordered, axis=0)
    right_lo = np.minimum.accumulate(ordered[::-1], axis=0)[::-1]
    right_hi = np.maximum.accumulate(ordered[::-1], axis=0)[::-1]
    sizes = np.unique(counts)  # the distinct left halves, smallest first
    left_blocked = _first_blocked(left_lo[sizes - 1], left_hi[sizes - 1], near, margin)
    # the right halves, smallest first, are nested the same way
    right_clear = _first_blocked(right_lo[sizes[::-1]], right_hi[sizes[::-1]], near, margin)
    rank = np.searchsorted(sizes, counts)
    blocked = (rank >= left_blocked).astype(int) + (rank < len(sizes) - right_clear).astype(int)
    left_volume = np.prod(left_hi[counts - 1] - left_lo[counts - 1], axis=1)
    volume = costs * (left_volume + np.prod(right_hi[counts] - right_lo[counts], axis=1))
    choice = int(np.lexsort((np.arange(len(places)), volume, blocked))[0])
    return int(blocked[choice]), float(volume[choice]), coords <= places[choice]


def _merged(
    boxes: list[tuple[np.ndarray, np.ndarray]], keep: np.ndarray, margin: float
) -> list[tuple[np.ndarray, np.ndarray]]:
    """``boxes`` with any two merged whose enclosing box is clear of ``keep`` (3, m, as
    :func:`_clear` reads it) and hardly larger than both (two slices of one plate, cut apart on
    the way to a third part)."""
    boxes = list(boxes)
    while True:
        best: tuple[float, int, int] | None = None
        for i, j in itertools.combinations(range(len(boxes)), 2):
            lo, hi = np.minimum(boxes[i][0], boxes[j][0]), np.maximum(boxes[i][1], boxes[j][1])
            extra = _volume(lo, hi) / (_volume(*boxes[i]) + _volume(*boxes[j]))
            if extra <= MERGE_GAIN and (best is None or extra < best[0]) and _clear(lo, hi, keep, margin):
                best = (extra, i, j)
        if best is None:
            return boxes
        _, i, j = best
        merged = (np.minimum(boxes[i][0], boxes[j][0]), np.maximum(boxes[i][1], boxes[j][1]))
        boxes = [b for k, b in enumerate(boxes) if k not in (i, j)] + [merged]


def _collision_xml(
    boxes: list[tuple[np.ndarray, np.ndarray]], rotation: np.ndarray, why: str, indent: str = "  "
) -> str:
    rpy = vector(rpy_from_matrix(rotation))
    out = [f"<!-- {why} -->"]
    for lo, hi in sorted(boxes, key=lambda b: (round(float(b[0][2]), 6), round(float(b[0][0]), 6), float(b[0][1]))):
        centre = rotation @ (0.5 * (lo + hi))
        out.append(
            f'<collision>\n{indent}<origin xyz="{vector(centre)}" rpy="{rpy}"/>\n'
            f'{indent}<geometry><box size="{vector(hi - lo)}"/></geometry>\n</collision>'
        )
    return "\n".join(out)


def clear_fit(
    loaded: LoadedDescription, options: CheckOptions, finding: Diagnostic, others: Iterable[str]
) -> SuggestedFix | None:
    """Boxes replacing the collision element of ``finding`` (a fitted-primitive fix) that keep
    clear of the links ``others`` (module docstring), fitted in ``loaded``; ``None`` when
    there are none."""
    from geomcheck.checks.fit import link_visual
    from geomcheck.checks.views import primitive_from_dict
    from geomcheck.geometry.elements import VisualCloud

    link = finding.link
    if link is None or link not in loaded.robot.link_map:
        return None
    meshes = MeshStore(loaded.bundle, options.thresholds.limits, mesh_formats(loaded.format))
    ctx = CheckContext(loaded=loaded, meshes=meshes, options=options)
    th = ctx.thresholds.fit
    visual = link_visual(ctx, loaded.robot.link_map[link], th)
    if not isinstance(visual, VisualCloud):
        return None
    reach = 0.1 * float(np.ptp(visual.points, axis=0).max()) + ctx.thresholds.self_collision.clearance_margin_m
    near = (visual.points.min(axis=0) - reach, visual.points.max(axis=0) + reach)
    motions, step = keep_out(ctx, link, others)
    margin = ctx.thresholds.self_collision.clearance_margin_m + step
    suggested = finding.data.get("suggested") or {}
    r, p, y = ((suggested.get("origin") or {}).get("rpy") or [0.0, 0.0, 0.0])[:3]
    rotation = Pose(rpy=(float(r), float(p), float(y))).rotation()
    local = visual.points @ rotation
    fitted = primitive_from_dict(suggested)
    found = obstacles(motions, near, rotation, _bounds(local), margin, fitted)
    boxes = partition(local, found.keep, found.margin, visual.vertices @ rotation)
    if boxes is None:
        return None
    names = ", ".join(sorted(set(others)))
    why = (
        f"{len(boxes)} boxes fitted to the link's mesh, clear of {names}: {_against(suggested, found.nearest, margin)}"
    )
    return SuggestedFix(
        Applicability.UNSAFE,
        f"replace the {finding.data.get('element', 'element')} by {why}",
        "collision",
        (ReplaceElement((), _collision_xml(boxes, rotation, why.replace("--", "- -"))),),
    )


def _against(suggested: dict[str, object], nearest: float | None, margin: float) -> str:
    """Why the boxes replace the primitive the check suggests (its help): how deep the other
    links' geometry, as their joints turn, goes into it (``nearest``: their least signed
    distance to it [m]), or how close it comes."""
    kind = str(suggested.get("type", "primitive"))
    if nearest is None:
        return f"the fitted {kind} would collide with them"
    if nearest < 0.0:
        return f"the fitted {kind} would overlap them by up to {1000.0 * -nearest:.0f} mm"
    return f"the fitted {kind} would come within {1000.0 * nearest:.0f} mm of them (clearance {1000.0 * margin:.0f} mm)"
