"""Fit of a link's collision elements against the link's visual geometry.

The visual geometry (every visual shape of the link, merged, in the link frame) is reduced
to its convex hull's vertices plus area-weighted surface samples drawn with a fixed seed.
Each point is assigned to the collision element it is deepest in (or nearest to): a link
approximated by several primitives (a capsule of a cylinder and two spheres, a finger of
four boxes) is judged as their union, and each element answers for the part of the mesh
nearest to it. With one element the part is the whole mesh.

Signed distances to primitives are exact; to a collision mesh they are taken to its convex
hull (exact inside, a lower bound outside). Lengths [m], volumes [m^3], points (n, 3).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from geomcheck.geometry.elements import CollisionElement, VisualCloud, mm, ratio, sig
from geomcheck.geometry.enclosing import minimal_ball
from geomcheck.geometry.frames import rotation_between, snap_rotation, to_frame
from geomcheck.geometry.meshfit import MeshComparison, compare_meshes
from geomcheck.geometry.primitives import (
    extent_coverage,
    extent_gaps,
    half_extents,
    signed_distance,
    volume,
    volume_samples,
)
from geomcheck.geometry.suggest import AXIS_FRAMES, Suggestion, capsule_along, hull_2d, suggest
from geomcheck.geometry.surface import ConvexRegion, principal_axes
from geomcheck.model import Box, Capsule, Cylinder, Sphere, rpy_from_matrix
from geomcheck.thresholds import FitThresholds

AXIS_SEPARATION_COS = np.cos(np.radians(20.0))  # axes closer than 20 degrees count as the same [1]
SETTLE_ROUNDS = 8  # refits of a suggestion on the part it would answer for, before it takes the whole mesh


@dataclass(frozen=True)
class AxisAlternative:
    """The same cylinder turned onto another ``axis`` (3,) of the link frame: its new
    ``rotation`` (3, 3), the ``turn`` (3, 3) from the current one, and how it fits."""

    axis: np.ndarray
    axis_name: str  # "x", "y", "z" (link axes) or "principal"
    rotation: np.ndarray
    turn: np.ndarray
    coverage: float
    protrusion_max: float  # [m]


@dataclass(frozen=True)
class ElementFit:
    """How one collision element fits the part of the visual geometry it answers for.

    ``gaps``: per side, primitive face minus mesh extreme [m] (positive = primitive
    overshoots); ``extent``: per axis (share spanned, primitive extent, mesh extent, mesh interval);
    ``coverage``: share of the part's surface samples inside the element or within the
    tolerance; ``protrusion_*``: how far the part sticks out [m] (max over hull vertices and
    samples, exact for one primitive since distance to a convex set peaks at hull
    vertices; p95 over the area-weighted samples); ``slack``: element volume over the part's
    hull volume; ``mesh_inside``: share of the whole visual surface inside the element;
    ``in_hull``: share of the element's volume inside the visual hull (only computed when
    ``mesh_inside`` is below the disjointness fraction, else ``None``); ``nearest``: signed
    distance from the element to the closest visual point [m]; ``shift``: link-frame move
    [m] that centres the element on its part, ``fits_when_moved`` whether it then covers.
    """

    element: CollisionElement
    part_points: int
    gaps: dict[str, float] | None
    extent: dict[str, tuple[float, float, float, float, float]] | None
    coverage: float | None
    protrusion_max: float | None
    protrusion_p95: float | None
    worst_point: np.ndarray | None
    hull_volume: float | None
    slack: float | None
    mesh_inside: float
    in_hull: float | None
    nearest: float
    shift: np.ndarray | None
    fits_when_moved: bool
    axis_alternative: AxisAlternative | None
    suggested: Suggestion | None
    comparison: MeshComparison | None
    # the suggestion, in place of the element, answers for more of the mesh than its part
    # (points nearer to it than to the other elements) and was refitted to enclose them too
    suggestion_grown: bool = False
    # for a link's only element that covers the mesh: the primitive of another kind fitted to the
    # whole visual with the least volume, if any (GC302's wrong kind of shape)
    better_kind: Suggestion | None = None
    # for a link's only element: the least volume [m^3] of an element of its own kind fitted to
    # the whole visual (a capsule's own volume, not its enclosing cylinder's): whether the part
    # is shaped for the element's kind, apart from how much larger than that fit the element is
    own_kind_volume: float | None = None

    @property
    def fitted_slack(self) -> float | None:
        """The slack an element of this kind fitted to the part would have: a lone capsule's
        own fitted volume over the hull's, else the suggestion's (a capsule's is its cylinder's)."""
        if self.own_kind_volume is not None and self.hull_volume:
            return self.own_kind_volume / self.hull_volume
        return None if self.suggested is None else self.suggested.slack

    def to_dict(self) -> dict[str, Any]:
        """The metrics as report data: lengths in mm where the key says so, else SI."""
        alt = self.axis_alternative
        out: dict[str, Any] = {
            "gaps_mm": None if self.gaps is None else {k: mm(v) for k, v in self.gaps.items()},
            "coverage": ratio(self.coverage),
            "protrusion_max_mm": mm(self.protrusion_max),
            "protrusion_p95_mm": mm(self.protrusion_p95),
            "slack": ratio(self.slack, 3),
            "primitive_volume": sig(self.element.volume),
            "hull_volume": sig(self.hull_volume),
            "mesh_inside": ratio(self.mesh_inside),
            "in_hull": ratio(self.in_hull),
            "part_points": self.part_points,
            "offset_mm": None if self.shift is None else [mm(v) for v in self.shift],
            "fits_when_moved": self.fits_when_moved,
            "axis_alternative": None
            if alt is None
            else {
                "axis": [ratio(v) for v in alt.axis],
                "axis_name": alt.axis_name,
                "rpy": [ratio(v, 6) for v in rpy_from_matrix(snap_rotation(alt.rotation))],
                "coverage": ratio(alt.coverage),
                "protrusion_max_mm": mm(alt.protrusion_max),
            },
            "suggested": None if self.suggested is None else self.suggested.to_dict(),
        }
        c = self.comparison
        if c is not None:
            out |= {
                "reverse_coverage": ratio(c.reverse_coverage),
                "overshoot_max_mm": mm(c.overshoot_max),
                "overshoot_p95_mm": mm(c.overshoot_p95),
                "surface_distance_max_mm": mm(c.surface_distance_max),
                "surface_distance_p95_mm": mm(c.surface_distance_p95),
            }
        return out

    def covers(self, thresholds: FitThresholds) -> bool:
        """Whether the part sticks out no more than the tolerance over enough of its surface."""
        if self.coverage is None or self.protrusion_max is None:
            return True
        return self.protrusion_max <= thresholds.protrusion_tolerance_m and self.coverage >= thresholds.min_coverage

    def disjoint(self, thresholds: FitThresholds) -> bool:
        """Whether the element holds almost none of the mesh and lies almost all outside it."""
        f = thresholds.offset_overlap_fraction
        if self.mesh_inside >= f:
            return False
        if self.in_hull is None:
            return self.nearest > thresholds.protrusion_tolerance_m
        return self.in_hull < f


@dataclass(frozen=True)
class LinkFit:
    """Every element's fit, the union's ``coverage`` and ``protrusion_*`` [m], and the share
    of the surface samples that borrowed (neighbour) elements answer for."""

    elements: tuple[ElementFit, ...]
    coverage: float
    protrusion_max: float
    protrusion_p95: float
    borrowed_share: float = 0.0


def percentile(values: np.ndarray, q: float) -> float:
    """``np.percentile(values, q)`` (linear interpolation) by partial sorting."""
    n = len(values)
    if n == 1:
        return float(values[0])
    rank = q / 100.0 * (n - 1)
    lo, hi = int(np.floor(rank)), int(np.ceil(rank))
    part = np.partition(values, (lo, hi))
    return float(part[lo] + (part[hi] - part[lo]) * (rank - lo))


def _protrusions(sd_all: np.ndarray, sd_samples: np.ndarray) -> tuple[float, float]:
    """Largest protrusion over all points and 95th percentile over the samples [m], >= 0."""
    top = float(max(0.0, sd_all.max())) if len(sd_all) else 0.0
    p95 = max(0.0, percentile(sd_samples, 95.0)) if len(sd_samples) else top
    return top, p95


def _recentre(element: CollisionElement, part: np.ndarray, tolerance: float) -> tuple[np.ndarray, bool]:
    """Link-frame shift centring the element on ``part`` (n, 3), and whether it then covers it."""
    prim = element.primitive
    if prim is None:
        if element.hull is None:
            return np.zeros(3), False
        shift = 0.5 * (part.min(axis=0) + part.max(axis=0))
        shift -= 0.5 * (element.hull.vertices.min(axis=0) + element.hull.vertices.max(axis=0))
        return shift, bool(element.hull.signed_distance(part - shift).max() <= tolerance)
    local = element.local(part)
    h = half_extents(prim)
    if isinstance(prim, Sphere):
        centre, radius = minimal_ball(local)
        return element.rotation @ centre, radius <= prim.radius + tolerance
    lo, hi = local.min(axis=0), local.max(axis=0)
    centre = 0.5 * (lo + hi)
    fits = bool(np.all(hi - lo <= 2.0 * h + 2.0 * tolerance))
    if isinstance(prim, Cylinder):
        centre_2d, radius = minimal_ball(hull_2d(local[:, :2]))
        centre[:2] = centre_2d
        fits = bool(hi[2] - lo[2] <= prim.length + 2.0 * tolerance and radius <= prim.radius + tolerance)
    return element.rotation @ centre, fits


def _axis_alternative(
    element: CollisionElement, part: np.ndarray, samples: np.ndarray, tolerance: float
) -> AxisAlternative | None:
    """The best of the cylinder turned onto the link axes and the part's principal axes."""
    prim = element.primitive
    if not isinstance(prim, Cylinder) or len(samples) < 3:
        return None
    current = element.rotation[:, 2]
    candidates = [(name, frame[:, 2]) for name, frame in AXIS_FRAMES]
    candidates += [("principal", a) for a in principal_axes(samples).T]
    best: AxisAlternative | None = None
    for name, axis in candidates:
        cos = float(axis @ current)
        if abs(cos) >= AXIS_SEPARATION_COS:
            continue
        target = axis if cos >= 0 else -axis
        turn = rotation_between(current, target)
        rotation = turn @ element.rotation
        sd_part = signed_distance(prim, to_frame(part, rotation, element.translation))
        sd_samples = signed_distance(prim, to_frame(samples, rotation, element.translation))
        coverage = float(np.mean(sd_samples <= tolerance))
        if best is None or coverage > best.coverage + 1e-9:
            best = AxisAlternative(target, name, rotation, turn, coverage, float(max(0.0, sd_part.max())))
    return best


def _in_hull(element: CollisionElement, visual: VisualCloud, th: FitThresholds) -> float | None:
    if visual.hull is None:
        return None
    rng = np.random.default_rng(th.seed)
    if element.primitive is not None:
        probe = volume_samples(element.primitive, th.volume_samples, rng) @ element.rotation.T + element.translation
    elif element.solid is not None:
        probe = element.solid.surface.sample(th.volume_samples, rng)
    else:
        return None
    return float(np.mean(visual.hull.signed_distance(probe) <= 0.0))


SIGNED_DISTANCE_DECIMALS = 12  # [m] decimals: far below any length the rules judge, far above solver noise


def _part_of(sd_row: np.ndarray, before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """The points an element with signed distances ``sd_row`` (n,) answers for, the other
    elements' smallest distances being ``before`` and ``after`` it in order (ties go first)."""
    return (sd_row < before) & (sd_row <= after)


def settled_suggestion(
    suggestion: Suggestion,
    kind: type[Box] | type[Cylinder] | type[Sphere],
    visual: VisualCloud,
    taken: np.ndarray,
    before: np.ndarray,
    after: np.ndarray,
    own_rotation: np.ndarray,
    th: FitThresholds,
) -> Suggestion | None:
    """The suggestion that, put in place of its element, encloses the part of the mesh it then
    answers for: the part depends on the element (each point goes to the element it is
    deepest in), so a primitive fitted to the current element's part can take over points of
    its neighbours' (borrowed) elements that it does not enclose. It is refitted to the parts
    taken so far until it gains no point; failing that, fitted to the whole mesh (``taken``
    (n,) the current part's mask over ``visual.points``; ``before``/``after`` (n,) the other
    elements' smallest signed distances, see :func:`_part_of`)."""
    pts, n_vertices = visual.points, len(visual.vertices)
    taken = taken.copy()
    for _ in range(SETTLE_ROUNDS):
        sd = signed_distance(suggestion.primitive, (pts - suggestion.translation) @ suggestion.rotation)
        gained = _part_of(sd, before, after) & ~taken
        if not gained.any():
            return suggestion
        taken |= gained
        hull = visual.hull if taken.all() else ConvexRegion.of(pts[taken])
        found = suggest(
            kind, pts[taken], visual.samples[taken[n_vertices:]], hull, own_rotation, th.simple_fit_margin,
            th.protrusion_tolerance_m,
        )  # fmt: skip
        if found is None:
            return None
        suggestion = found
    return suggest(
        kind, pts, visual.samples, visual.hull, own_rotation, th.simple_fit_margin, th.protrusion_tolerance_m
    )


def _fit_element(
    element: CollisionElement,
    visual: VisualCloud,
    sd_row: np.ndarray,
    mask: np.ndarray,
    part_hull: ConvexRegion | None,
    th: FitThresholds,
    others: tuple[np.ndarray, np.ndarray] | None = None,
) -> ElementFit:
    tol = th.protrusion_tolerance_m
    pts = visual.points
    n_vertices = len(visual.vertices)
    part, sd_part = pts[mask], sd_row[mask]
    sample_mask = mask[n_vertices:]
    part_samples, sd_samples = visual.samples[sample_mask], sd_row[n_vertices:][sample_mask]
    mesh_inside = float(np.mean(sd_row[n_vertices:] <= tol)) if len(visual.samples) else 0.0
    nearest = float(sd_row.min()) if len(sd_row) else float("inf")
    # the overlap with the hull only decides disjointness, which needs little mesh inside first
    in_hull = _in_hull(element, visual, th) if mesh_inside < th.offset_overlap_fraction else None
    comparison = compare_meshes(visual, element, th) if element.primitive is None else None
    if len(part) == 0:
        return ElementFit(
            element, 0, None, None, None, None, None, None, None, None,
            mesh_inside, in_hull, nearest, None, False, None, None, comparison,
        )  # fmt: skip
    protrusion_max, protrusion_p95 = _protrusions(sd_part, sd_samples)
    coverage = float(np.mean(sd_samples <= tol)) if len(sd_samples) else float(np.mean(sd_part <= tol))
    worst = part[int(np.argmax(sd_part))]
    covered = protrusion_max <= tol and coverage >= th.min_coverage
    shape_fit = _shape_fit(element, visual, mask, part, part_samples, part_hull, th, others, covered, comparison)
    # extremes of a part are at its hull's vertices: enough for centring and enclosing
    shift, fits = _recentre(element, part if part_hull is None else part_hull.vertices, tol)
    hull_volume = _held_volume(pts, sd_row <= tol, mask, part_hull)
    slack = element.volume / hull_volume if hull_volume else None
    return ElementFit(
        element=element,
        part_points=len(part),
        gaps=shape_fit.gaps,
        extent=shape_fit.extent,
        coverage=coverage,
        protrusion_max=protrusion_max,
        protrusion_p95=protrusion_p95,
        worst_point=worst,
        hull_volume=hull_volume,
        slack=slack,
        mesh_inside=mesh_inside,
        in_hull=in_hull,
        nearest=nearest,
        shift=shift,
        fits_when_moved=fits,
        axis_alternative=shape_fit.alternative,
        suggested=shape_fit.suggestion,
        comparison=comparison,
        suggestion_grown=shape_fit.grown,
    )


def _held_volume(pts: np.ndarray, inside: np.ndarray, mask: np.ndarray, part_hull: ConvexRegion | None) -> float | None:
    """The volume [m^3] of the mesh an element answers for: the convex hull of its part (``mask``)
    and of the points it holds (``inside``) that a nearer element owns. A battery's box repeating
    its visual box, mostly inside the torso's collision box, holds the whole battery, not the slab
    left out of the torso's box that is its part: its size is judged against the battery."""
    if part_hull is None:
        return None
    held = inside & ~mask
    if not held.any():
        return part_hull.volume
    whole = ConvexRegion.of(pts[mask | held])
    return part_hull.volume if whole is None else max(part_hull.volume, whole.volume)


class _ShapeFit(NamedTuple):
    """What an element's fit adds to its coverage: its gaps and extent coverage (a primitive's), the
    primitive suggested for its part and whether it grew against the others, and the same kind on
    another axis."""

    gaps: dict[str, float] | None = None
    extent: dict[str, tuple[float, float, float, float, float]] | None = None
    suggestion: Suggestion | None = None
    grown: bool = False
    alternative: AxisAlternative | None = None


def _shape_fit(
    element: CollisionElement,
    visual: VisualCloud,
    mask: np.ndarray,
    part: np.ndarray,
    part_samples: np.ndarray,
    part_hull: ConvexRegion | None,
    th: FitThresholds,
    others: tuple[np.ndarray, np.ndarray] | None,
    covered: bool,
    comparison: MeshComparison | None,
) -> _ShapeFit:
    """The :class:`_ShapeFit` of ``element`` over its ``part`` (n, 3): a mesh element's gaps are its
    ``comparison``'s; a primitive's suggestion grows, when ``others`` are given, until it settles
    against them, and an element that does not cover its part (``covered``) is tried on another axis."""
    if element.primitive is None:
        return _ShapeFit(gaps=comparison.gaps if comparison is not None else None)
    tol = th.protrusion_tolerance_m
    local = element.local(part)
    gaps, extent = extent_gaps(element.primitive, local), extent_coverage(element.primitive, local)
    kind = type(element.primitive)
    suggestion = suggest(kind, part, part_samples, part_hull, element.rotation, th.simple_fit_margin, tol)
    grown = False
    if suggestion is not None and others is not None:
        first = suggestion
        suggestion = settled_suggestion(suggestion, kind, visual, mask, *others, element.rotation, th)
        grown = suggestion is not first
    alternative = None if covered else _axis_alternative(element, part, part_samples, tol)
    return _ShapeFit(gaps, extent, suggestion, grown, alternative)


OTHER_KINDS: tuple[type[Box] | type[Cylinder] | type[Sphere], ...] = (Box, Cylinder, Sphere)


def other_kind(element: CollisionElement, visual: VisualCloud, th: FitThresholds) -> Suggestion | None:
    """The primitive of another kind than ``element``'s fitted to the whole ``visual`` (covering
    ``min_coverage`` of it) with the least volume, if any."""
    best: Suggestion | None = None
    for kind in OTHER_KINDS:
        if isinstance(element.primitive, kind):  # a capsule is measured as a cylinder
            continue
        fitted = suggest(
            kind, visual.vertices, visual.samples, visual.hull, None, th.simple_fit_margin, th.protrusion_tolerance_m
        )
        if fitted is None or fitted.volume <= 0.0 or fitted.coverage < th.min_coverage:
            continue
        if best is None or fitted.volume < best.volume:
            best = fitted
    return best


def own_kind_volume(element: CollisionElement, fitted: Suggestion | None, visual: VisualCloud) -> float | None:
    """The volume [m^3] of an element of ``element``'s kind fitted to the whole ``visual``:
    ``fitted``'s (the element's suggestion), or for a capsule, whose suggestion is the cylinder
    enclosing it, the least capsule about that cylinder's axis."""
    if fitted is None:
        return None
    if not isinstance(element.primitive, Capsule):
        return fitted.volume
    enclose = visual.hull.vertices if visual.hull is not None else visual.vertices
    return volume(capsule_along(enclose, fitted.rotation, fitted.translation))


def fit_link(
    visual: VisualCloud,
    elements: Sequence[CollisionElement],
    th: FitThresholds,
    borrowed: Sequence[CollisionElement] = (),
) -> LinkFit:
    """Fit every collision element of a link against its ``visual`` geometry. ``borrowed``
    elements (a neighbour's, valid at every joint position) take their share of the mesh and
    count in the union but get no fit of their own."""
    pts = visual.points
    if not elements or len(pts) == 0:
        return LinkFit((), 0.0, 0.0, 0.0)
    everything = [*elements, *borrowed]
    # to a picometre: two elements as near to a point (a copied element, nested hulls) tie on
    # every CPU, and the first owns it, instead of whichever a BLAS kernel's last digit favours
    sd = np.round(np.stack([e.signed_distance(pts) for e in everything]), SIGNED_DISTANCE_DECIMALS)  # (k, n)
    owner = np.argmin(sd, axis=0)
    fits = []
    far = np.full(len(pts), np.inf)
    for i, element in enumerate(elements):
        mask = owner == i
        hull = visual.hull if mask.all() else ConvexRegion.of(pts[mask])
        before = sd[:i].min(axis=0) if i > 0 else far
        after = sd[i + 1 :].min(axis=0) if i + 1 < len(everything) else far
        fits.append(_fit_element(element, visual, sd[i], mask, hull, th, (before, after)))
    if len(fits) == 1 and elements[0].primitive is not None and fits[0].covers(th):
        fits[0] = replace(fits[0], better_kind=other_kind(elements[0], visual, th))
    if len(fits) == 1 and elements[0].primitive is not None:
        fits[0] = replace(fits[0], own_kind_volume=own_kind_volume(elements[0], fits[0].suggested, visual))
    union = sd.min(axis=0)
    n_vertices = len(visual.vertices)
    top, p95 = _protrusions(union, union[n_vertices:])
    samples_sd = union[n_vertices:]
    coverage = float(np.mean(samples_sd <= th.protrusion_tolerance_m)) if len(samples_sd) else 0.0
    # covered by a neighbour's element: nearest to it and within the tolerance (nearest alone would
    # count a chassis 0% inside any collision as "95% covered across a joint" by the wheels' hubs)
    lent = (owner[n_vertices:] >= len(elements)) & (samples_sd <= th.protrusion_tolerance_m)
    borrowed_share = float(np.mean(lent)) if len(samples_sd) else 0.0
    return LinkFit(tuple(fits), coverage, top, p95, borrowed_share)


__all__ = [  # CollisionElement, VisualCloud and the rounding helpers live in geometry.elements
    "AXIS_SEPARATION_COS",
    "AxisAlternative",
    "CollisionElement",
    "ElementFit",
    "LinkFit",
    "VisualCloud",
    "fit_link",
    "mm",
    "percentile",
    "ratio",
    "sig",
]
