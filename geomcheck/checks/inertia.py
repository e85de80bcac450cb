"""GC5xx checks: each link's mass and inertia, on their own and against the link's geometry.

Writes the ``inertia`` report section: one entry per link with an ``<inertial>``, in
document order (docs/report-schema.md).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.inertia_bodies import Body, MergedBody, rigid_bodies, usable_mass
from geomcheck.checks.inertia_com import misplaced_com, template_origins
from geomcheck.checks.inertia_counterparts import check_counterparts
from geomcheck.diagnostics import Diagnostic, Severity, SkippedCheck
from geomcheck.geometry.elements import at_nanometre
from geomcheck.geometry.hull_cache import stored_distance_outside, stored_hull, stored_solid_hull
from geomcheck.geometry.inertia import (
    AXIS_NAMES,
    GeometryBounds,
    Hull,
    MassProperties,
    exceedance,
    geometry_bounds,
    mass_properties,
)
from geomcheck.geometry.shapes import link_points
from geomcheck.load.meshes import MeshProblem, MeshStore
from geomcheck.model import Inertial, Joint, Link, Mesh, Robot, SourceLocation
from geomcheck.rules.inertia import (
    COM_MISPLACED,
    COM_OUTSIDE,
    COPIED_INERTIA,
    EXCEEDS_GEOMETRY,
    IMPLAUSIBLE_DENSITY,
    MISSING_INERTIAL,
    NON_POSITIVE_MASS,
    NOT_POSITIVE_DEFINITE,
    TRIANGLE_INEQUALITY,
)
from geomcheck.thresholds import AnalysisThresholds, InertiaThresholds

GEOMETRY_CHECK = "inertia-geometry"
GRAMS_PER_KG = 1000.0
ALIGNED_TOLERANCE = 1e-9  # a principal axis this close to a link axis is named after it
PLAUSIBLE_MIN_DENSITY_KG_M3 = 100.0  # lighter than foam-filled plastic parts: not a real average [kg/m^3]


REPORTED_DIGITS = 6  # significant digits of reported moments and axes: what they mean, not a BLAS kernel's last digits
DISTINCT_MOMENTS = 1e-6  # moments closer than this share of the largest have no axis of their own [ratio]
AXIS_DECIMALS = 6  # decimals of a principal axis's components (a unit vector): a microradian, not solver noise


def rounded(value: float | None) -> float | None:
    """``value`` to :data:`REPORTED_DIGITS` significant digits (the same JSON on every CPU and
    BLAS build), ``None`` for non-finite."""
    if value is None or not math.isfinite(value):
        return None
    return float(f"{value:.{REPORTED_DIGITS}g}") + 0.0  # + 0.0: no negative zero


def distinct_axes(moments: np.ndarray, axes: np.ndarray) -> list[list[float | None] | None]:
    """The principal axes of moments that differ from the other two (``None`` for an axis
    whose moment equals another's: any direction in their plane is principal, and which one a
    solver returns depends on the CPU). ``axes`` columns, signs already canonical."""
    scale = max(float(np.max(np.abs(moments))), 1e-300)
    out: list[list[float | None] | None] = []
    for k in range(3):
        others = [abs(float(moments[k] - moments[j])) for j in range(3) if j != k]
        axis = np.round(axes[:, k], AXIS_DECIMALS)  # 1e-16 where the axis is 0 is a solver's, not the body's
        out.append(rounded_list(axis) if min(others) > DISTINCT_MOMENTS * scale else None)
    return out


def rounded_list(values: Iterable[float]) -> list[float | None]:
    return [rounded(float(v)) for v in values]


def metres_list(values: Iterable[float]) -> list[float | None]:
    """Coordinates [m] to a nanometre, then to :data:`REPORTED_DIGITS` significant digits: a
    bounding box face at 0 stays 0, not -2.9e-15 on one CPU and -2.1e-15 on another."""
    return [rounded(at_nanometre(float(v))) for v in values]


def vector_text(v: Iterable[float]) -> str:
    return "(" + ", ".join(f"{float(x):.4g}" for x in v) + ")"


def tensor_values(inertial: Inertial) -> tuple[float, ...]:
    return (inertial.ixx, inertial.ixy, inertial.ixz, inertial.iyy, inertial.iyz, inertial.izz)


def unique_links(robot: Robot) -> Iterator[Link]:
    """Links in document order, the first of duplicated names only (duplicates are a GC1xx finding)."""
    seen: set[str] = set()
    for link in robot.links:
        if link.name not in seen:
            seen.add(link.name)
            yield link


def moving_joint(robot: Robot, link: Link) -> Joint | None:
    """The non-fixed joint that moves ``link``, if any."""
    joint = robot.parent_joint.get(link.name)
    return joint if joint is not None and joint.is_moving else None


def link_geometry(link: Link, meshes: MeshStore, analysis: AnalysisThresholds) -> np.ndarray | str:
    """Extreme points of every shape of ``link`` in the link frame (each mesh's hull vertices,
    each primitive's tessellation), shape (n, 3) [m], or why they cannot be used.

    One unavailable mesh makes the whole link unusable: the rest would understate its extent.
    """
    if not link.has_geometry:
        return "link has no visual or collision geometry"
    for shape in (*link.visuals, *link.collisions):
        if isinstance(shape.geometry, Mesh):
            mesh = meshes.get(shape.geometry)
            if isinstance(mesh, MeshProblem):
                return f"{shape.label} mesh unavailable: {mesh.message}"
    points = link_points(link, meshes, analysis=analysis)
    if len(points) == 0:
        return "link geometry has no vertices"
    if not np.isfinite(points).all():
        return "link geometry has non-finite vertices"
    return points


def percent(share: float) -> str:
    """``share`` as a percentage with two significant digits: ``0.33%``, ``0.00039%``."""
    return f"{share * 100:.2g}%"


# what the merged body must pass for a member's finding to be lowered: the same check
MERGED_TEST: dict[str, Callable[[MergedBody, InertiaThresholds], bool]] = {
    NOT_POSITIVE_DEFINITE.code: MergedBody.tensor_valid,
    TRIANGLE_INEQUALITY.code: MergedBody.tensor_valid,
    EXCEEDS_GEOMETRY.code: MergedBody.within_geometry,
    COPIED_INERTIA.code: MergedBody.within_geometry,
    COM_OUTSIDE.code: MergedBody.com_inside,
    COM_MISPLACED.code: MergedBody.com_inside,
    IMPLAUSIBLE_DENSITY.code: MergedBody.density_plausible,
}
# plausibility against the geometry: a light link's inexact mass properties barely move the
# robot. GC503/GC504 are not among them: MuJoCo and Drake refuse such a tensor whatever it weighs.
LIGHT_LOWERED = frozenset(
    {EXCEEDS_GEOMETRY.code, COPIED_INERTIA.code, COM_OUTSIDE.code, COM_MISPLACED.code, IMPLAUSIBLE_DENSITY.code}
)
# what compares the inertial with the link's geometry and means nothing against a frame's marker box
GEOMETRY_LOWERED = frozenset({COM_OUTSIDE.code, COM_MISPLACED.code, IMPLAUSIBLE_DENSITY.code})
ROUND_PRODUCTS = 1e-2  # products of inertia under this share of a round tensor's moments are negligible [ratio]
MIN_PLACEHOLDER_LINKS = 3  # this many links or more sharing one <inertial>, and no other: placeholders


def uniform_placeholder(robot: Robot) -> int:
    """How many links carry one identical ``<inertial>`` when every link that has one carries
    that same one and there are at least ``MIN_PLACEHOLDER_LINKS``, else 0: a real robot's
    parts never share mass, centre of mass and tensor; a macro's default values do."""
    written = [link.inertial for link in unique_links(robot) if link.inertial is not None]
    distinct = {(i.mass, i.origin.xyz, i.origin.rpy, *tensor_values(i)) for i in written}
    return len(written) if len(distinct) == 1 and len(written) >= MIN_PLACEHOLDER_LINKS else 0


def power_of_ten(value: float) -> bool:
    """Whether ``value`` is 10^k for an integer k (0.001, 1e-4, 0.1): a value typed for "unknown"."""
    if not (value > 0.0 and math.isfinite(value)):
        return False
    exponent = round(math.log10(value))
    return math.isclose(value, 10.0**exponent, rel_tol=1e-9)


def round_tensor(inertial: Inertial | None) -> bool:
    """Whether ``inertial`` pairs a computed mass (not a power of ten) with a round tensor: one power
    of ten on every axis, products negligible beside it (iCub's 0.01 kg m^2 on its light links, raised
    for stability, the CAD's products of 1e-7 kept)."""
    if inertial is None or power_of_ten(inertial.mass):
        return False
    moments = {inertial.ixx, inertial.iyy, inertial.izz}
    products = (inertial.ixy, inertial.ixz, inertial.iyz)
    # the products may keep the CAD's values, negligible beside the raised moments
    small = all(abs(v) <= ROUND_PRODUCTS * inertial.ixx for v in products)
    return len(moments) == 1 and power_of_ten(inertial.ixx) and small


def round_placeholder(inertial: Inertial | None) -> bool:
    """Whether ``inertial`` is a placeholder typed for "unknown": its mass and diagonal moments
    powers of ten and no products of inertia (a frame's 0.01 kg with 0.001 kg m^2 on each axis)."""
    if inertial is None:
        return False
    products = (inertial.ixy, inertial.ixz, inertial.iyz)
    moments = (inertial.ixx, inertial.iyy, inertial.izz)
    return all(v == 0.0 for v in products) and all(power_of_ten(v) for v in (inertial.mass, *moments))


class Weigher:
    """Adjusts a finding's severity by its consequence, saying why, without hiding wrong data.

    A link merged across fixed joints into a body that passes the same check (pinocchio,
    Gazebo's fixed-joint lumping and MuJoCo's URDF import simulate that body), or carrying less
    than ``minor_mass_share`` of the robot's mass, keeps its finding at warning at least: the
    description's own numbers are still wrong (the merged body carries the wrong member inside
    it, and KDL and RViz read the link itself), and its maintainer would change them; the
    message says what the consumers do. Only two reasons reach info, because no part's data is
    judged: every link carries the same placeholder ``<inertial>`` (the whole robot's dynamics
    are fictitious, not this link's), and a link whose geometry is itself a placeholder (no
    larger than ``placeholder_extent_m``: a frame's marker, not a part to compare with)."""

    def __init__(
        self,
        robot: Robot,
        th: InertiaThresholds,
        points_of: Callable[[str], np.ndarray | str],
        hulls: HullMemo,
    ) -> None:
        self.robot = robot
        self.th = th
        self.bodies = rigid_bodies(robot)
        self.total = sum(usable_mass(link) for link in unique_links(robot))
        self.placeholders = uniform_placeholder(robot)
        self._points_of = points_of
        self._hulls = hulls
        self._merged: dict[str, MergedBody] = {}

    def merged(self, body: Body) -> MergedBody:
        if body.top not in self._merged:
            self._merged[body.top] = MergedBody(body, self.robot, self._points_of, self._hulls.of)
        return self._merged[body.top]

    def share(self, link: str) -> float:
        mass = usable_mass(self.robot.link_map.get(link))
        return mass / self.total if self.total > 0.0 else 1.0

    def placeholder_geometry(self, link: str, marker: bool) -> float | None:
        """The largest extent [m] of ``link``'s geometry when it is a placeholder, else ``None``: no
        larger than ``placeholder_extent_m``, or, when ``marker``, drawn with primitives alone no larger
        than ``marker_extent_m`` (the 5 mm or 1 cm box a frame is drawn with, not a part's shape)."""
        points = self._points_of(link)
        if isinstance(points, str) or not len(points):
            return None
        extent = float(np.ptp(points, axis=0).max())
        shapes = (*self.robot.link_map[link].visuals, *self.robot.link_map[link].collisions)
        primitives = not any(isinstance(s.geometry, Mesh) for s in shapes)
        limit = self.th.marker_extent_m if primitives and marker else self.th.placeholder_extent_m
        return extent if extent <= limit else None

    def weigh(self, d: Diagnostic) -> Diagnostic:
        """``d`` with its severity adjusted (see the class), saying why."""
        test = MERGED_TEST.get(d.code)
        if test is None or d.link is None or d.link not in self.bodies:
            return d
        body = self.bodies[d.link]
        notes: list[str] = []  # consequences that lower an error to a warning, never further
        reasons: list[str] = []  # no part's data judged: down to info
        data: dict[str, Any] = {}
        link = self.robot.link_map[d.link]
        placeholder = d.code in LIGHT_LOWERED and round_placeholder(link.inertial)
        fixed_marker = link.name != body.top and (d.data.get("point_mass") or placeholder)
        if body.merged and fixed_marker and test(self.merged(body), self.th):
            # a point mass, or round values typed for "unknown", on a frame fixed to a body that passes:
            # consumers merge it away, and no part's own values are wrong
            what = "a point mass" if d.data.get("point_mass") else "placeholder values (powers of ten)"
            reasons.append(f"{what} on a frame fixed to body {body.top}, which passes this check once merged")
            data["body"] = body.top
        elif body.merged and test(self.merged(body), self.th):
            notes.append(
                f"fixed joints merge it with {body.others_text(d.link)} into body {body.top}, which passes this "
                "check as pinocchio, Gazebo and MuJoCo simulate it; the link's own values are still wrong and are "
                "part of that body"
            )
            mass = usable_mass(self.robot.link_map.get(d.link))
            data["body"] = body.top
            data["body_mass_share"] = rounded(mass / body.mass) if body.mass > 0.0 else None
        if d.code in LIGHT_LOWERED:
            share = self.share(d.link)
            if share < self.th.minor_mass_share:
                notes.append(f"the link carries {percent(share)} of the robot's {self.total:.4g} kg")
                data["mass_share"] = rounded(share)
                ratio = float((d.data.get("worst") or {}).get("ratio") or 0.0)
                if d.code == EXCEEDS_GEOMETRY.code and 0.0 < ratio <= self.th.marginal_ratio:
                    reasons.append(f"a light part's estimate {ratio:.2g} times the bound, a little off")
            if d.code == EXCEEDS_GEOMETRY.code and round_tensor(link.inertial):
                reasons.append(
                    "a round tensor (one power of ten on every axis) with the part's computed mass: set on purpose, "
                    "as authors do to steady small links in Gazebo"
                )
            if self.placeholders:
                reasons.append(f"all {self.placeholders} links with an <inertial> carry this same one: placeholders")
            extent = self.placeholder_geometry(d.link, marker=d.code in GEOMETRY_LOWERED)
            if extent is not None:
                reasons.append(f"the link's geometry is a {extent * 1000:.2g} mm placeholder, not a part")
            mass = usable_mass(link)
            if 0.0 < mass <= self.th.negligible_mass_kg:
                reasons.append(f"its {mass:.3g} kg makes it a massless frame's placeholder, not a part")
        order = [Severity.ERROR, Severity.WARNING, Severity.INFO]
        level = order.index(d.severity)
        if reasons:
            level = len(order) - 1
        elif notes:
            level = max(level, min(level + len(notes), order.index(Severity.WARNING)))
        severity = order[level]
        if not reasons and not notes:
            return d
        data.setdefault("mass_share", rounded(self.share(d.link)))
        data.setdefault("body", None)
        data.setdefault("body_mass_share", None)
        said = "; ".join([*reasons, *notes])
        if severity is d.severity:
            message = f"{d.message} (kept at {severity.value}: {said})"
        else:
            message = f"{d.message} ({d.severity.value} lowered to {severity.value}: {said})"
        return replace(d, severity=severity, message=message, data={**d.data, **data})


@dataclass
class LinkFindings:
    """What the checks of one link produced."""

    entry: dict[str, Any]
    diagnostics: list[Diagnostic] = field(default_factory=list)
    skipped: list[SkippedCheck] = field(default_factory=list)


def find_copies(robot: Robot, th: InertiaThresholds) -> dict[str, Link]:
    """Links whose written tensor equals another link's while the masses differ by
    ``copied_inertia_mass_ratio`` or more, mapped to that other link.

    Among the links sharing a tensor the reference is the heaviest, ties broken by name: the
    same whatever the order of the ``<link>`` elements (the tensor of the heavier part is
    usually the original; copied onto a lighter part it gives radii of gyration too large).
    """
    groups: dict[tuple[float, ...], list[Link]] = {}
    for link in unique_links(robot):
        inertial = link.inertial
        if inertial is None:
            continue
        values = tensor_values(inertial)
        if not all(math.isfinite(v) for v in values) or not any(values) or not math.isfinite(inertial.mass):
            continue
        groups.setdefault(values, []).append(link)
    out: dict[str, Link] = {}
    for members in groups.values():
        if len(members) < 2:
            continue
        reference = min(members, key=lambda m: (-m.inertial.mass if m.inertial else 0.0, m.name))
        assert reference.inertial is not None
        for link in members:
            assert link.inertial is not None
            masses = sorted((link.inertial.mass, reference.inertial.mass))
            if link is not reference and masses[0] > 0.0 and masses[1] / masses[0] >= th.copied_inertia_mass_ratio:
                out[link.name] = reference
    return out


def copied_diagnostic(link: Link, reference: Link, location: SourceLocation | None) -> Diagnostic:
    assert link.inertial is not None and reference.inertial is not None
    mass, ref_mass = link.inertial.mass, reference.inertial.mass
    ratio = max(mass, ref_mass) / min(mass, ref_mass)
    values = tensor_values(link.inertial)
    return COPIED_INERTIA.diagnose(
        COPIED_INERTIA.message(
            tensor=vector_text(values), reference=reference.name, ratio=ratio, mass=mass, reference_mass=ref_mass
        ),
        link=link.name,
        about="inertia",
        location=location,
        data={
            "copied_from": reference.name,
            "mass": rounded(mass),
            "reference_mass": rounded(ref_mass),
            "mass_ratio": rounded(ratio),
            "tensor": rounded_list(values),
        },
    )


def mass_diagnostics(
    link: Link, joint: Joint | None, body: Body, th: InertiaThresholds, loc: SourceLocation | None
) -> list[Diagnostic]:
    """GC502 for a negative or non-finite mass anywhere, or a non-positive one on a moving
    link whose body (the link and the links fixed below it) has no mass either."""
    assert link.inertial is not None
    mass = link.inertial.mass
    data: dict[str, Any] = {"mass": rounded(mass), "min_mass_kg": th.min_mass_kg}
    if not math.isfinite(mass):
        message = NON_POSITIVE_MASS.message("not_finite", mass=mass)
    elif mass < 0.0:
        message = NON_POSITIVE_MASS.message("negative", mass=mass)
    elif joint is not None and mass <= th.min_mass_kg and body.mass <= th.min_mass_kg:
        message = NON_POSITIVE_MASS.message("moving", mass=mass, joint_type=joint.type, joint=joint.name)
        if body.merged:
            message += NON_POSITIVE_MASS.message("body", links=body.others_text(link.name))
            data["body_links"] = body.others(link.name)
    elif mass == 0.0 and any(v != 0.0 for v in tensor_values(link.inertial)):
        # rotational inertia is mass times squared distance: none without mass; consumers that merge the
        # link add a tensor with no mass to its body
        largest = max(abs(v) for v in tensor_values(link.inertial))
        message = NON_POSITIVE_MASS.message("massless_tensor", largest=largest)
        return [
            NON_POSITIVE_MASS.diagnose(
                message, link=link.name, about="mass", location=loc, data=data, severity=Severity.WARNING
            )
        ]
    else:
        return []
    return [NON_POSITIVE_MASS.diagnose(message, link=link.name, about="mass", location=loc, data=data)]


def tensor_diagnostics(
    link: Link, props: MassProperties, moves: bool, th: InertiaThresholds, loc: SourceLocation | None
) -> tuple[list[Diagnostic], bool]:
    """GC503 and GC504 on the tensor alone; also whether the triangle inequality holds."""
    out = []
    moments = props.moments
    text = ", ".join(f"{m:.4g}" for m in moments)
    data = {"principal_moments": rounded_list(moments), "mass": rounded(props.mass)}
    if not props.positive_definite:
        semidefinite = props.positive_semidefinite
        severity = Severity.WARNING if semidefinite and not moves else None
        kind = NOT_POSITIVE_DEFINITE.message(
            "zero" if not np.any(moments) else "semidefinite" if semidefinite else "negative"
        )
        out.append(
            NOT_POSITIVE_DEFINITE.diagnose(
                NOT_POSITIVE_DEFINITE.message(kind=kind, moments=text),
                link=link.name,
                about="inertia",
                location=loc,
                data=data | {"point_mass": bool(not np.any(moments))},
                severity=severity,
            )
        )
    a, b, c = moments
    triangle_ok = props.triangle_excess <= th.relative_tolerance * props.scale
    if props.positive_semidefinite and not triangle_ok:
        out.append(
            TRIANGLE_INEQUALITY.diagnose(
                TRIANGLE_INEQUALITY.message(a=a, b=b, sum=a + b, c=c),
                link=link.name,
                about="inertia",
                location=loc,
                data={**data, "excess": rounded(props.triangle_excess)},
            )
        )
    return out, triangle_ok


def direction_label(bounds: GeometryBounds, k: int) -> str:
    """``link y axis``, ``principal axis 2 (the link y axis)`` or ``principal axis 3 (-0.24, 0.97, -0.03)``."""
    label = bounds.labels[k]
    if not label.startswith("principal"):
        return label
    direction = bounds.directions[:, k]
    aligned = np.flatnonzero(np.abs(np.abs(direction) - 1.0) < ALIGNED_TOLERANCE)
    if len(aligned) == 1:
        return f"{label} (the link {AXIS_NAMES[aligned[0]]} axis)"
    return f"{label} {vector_text(direction)}"


def geometry_diagnostic(
    link: Link, props: MassProperties, bounds: GeometryBounds, th: InertiaThresholds, loc: SourceLocation | None
) -> Diagnostic | None:
    """GC505: the worst moment (or, failing none, the worst spread) beyond what the geometry allows."""
    limit = 1.0 + th.relative_tolerance
    axis_ratio = exceedance(bounds.moments, bounds.moment_bound)
    plane_ratio = exceedance(bounds.spread, bounds.spread_bound)
    if max(axis_ratio.max(), plane_ratio.max()) <= limit:
        return None
    m = props.mass
    data: dict[str, Any] = {
        "mass": rounded(m),
        "directions": list(bounds.labels),
        "moments": rounded_list(bounds.moments),
        "moment_bound": rounded_list(bounds.moment_bound),
        "radius_of_gyration": rounded_list(np.sqrt(np.clip(bounds.moments, 0.0, None) / m)),
        "reach": rounded_list(bounds.axis_reach),
        "spread": rounded_list(np.sqrt(np.clip(bounds.spread, 0.0, None) / m)),
        "extent": rounded_list(bounds.plane_reach),
    }
    if axis_ratio.max() > limit:
        kind, ratios = "moment", axis_ratio
        k = int(np.argmax(axis_ratio))
        gyration = math.sqrt(bounds.moments[k] / m)
        message = EXCEEDS_GEOMETRY.message(
            "moment",
            link=link.name,
            gyration=gyration,
            direction=direction_label(bounds, k),
            moment=bounds.moments[k],
            mass=m,
            reach=bounds.axis_reach[k],
            bound=bounds.moment_bound[k],
        )
    else:
        kind, ratios = "spread", plane_ratio
        k = int(np.argmax(plane_ratio))
        spread = math.sqrt(bounds.spread[k] / m)
        message = EXCEEDS_GEOMETRY.message(
            "spread",
            link=link.name,
            spread=spread,
            direction=direction_label(bounds, k),
            second_moment=bounds.spread[k],
            mass=m,
            extent=bounds.plane_reach[k],
            bound=bounds.spread_bound[k],
        )
    data["worst"] = {"direction": bounds.labels[k], "bound": kind, "ratio": rounded(float(ratios[k]))}
    return EXCEEDS_GEOMETRY.diagnose(message, link=link.name, about="inertia", location=loc, data=data)


def com_diagnostic(
    link: Link, props: MassProperties, hull: Hull, distance: float, loc: SourceLocation | None
) -> Diagnostic:
    spans = ", ".join(f"{a} {lo:.3f}..{hi:.3f}" for a, lo, hi in zip("xyz", hull.lower, hull.upper, strict=True))
    return COM_OUTSIDE.diagnose(
        COM_OUTSIDE.message(com=vector_text(props.com), distance=distance, bounds=spans),
        link=link.name,
        about="com",
        location=loc,
        data={
            "com": rounded_list(props.com),
            "distance": rounded(distance),
            "bounds": [metres_list(hull.lower), metres_list(hull.upper)],
        },
    )


def density_diagnostic(
    link: Link, mass: float, volume: float, th: InertiaThresholds, loc: SourceLocation | None
) -> Diagnostic:
    density = mass / volume
    as_grams = mass / GRAMS_PER_KG
    # A mass written in grams reads as a number of a real part (>= 1) and gives a density of real material.
    if mass >= 1.0 and PLAUSIBLE_MIN_DENSITY_KG_M3 <= density / GRAMS_PER_KG <= th.max_density_kg_m3:
        hint = f"The mass looks like grams: {as_grams:.6g} kg would give {density / GRAMS_PER_KG:.4g} kg/m^3. "
    else:
        hint = "If the link's shapes are placeholders smaller than the part, give it its real geometry. "
    return IMPLAUSIBLE_DENSITY.diagnose(
        IMPLAUSIBLE_DENSITY.message(
            mass=mass,
            volume=volume,
            density=density,
            times=density / th.max_density_kg_m3,
            max_density=th.max_density_kg_m3,
        ),
        help=hint + IMPLAUSIBLE_DENSITY.fix,
        link=link.name,
        about="mass",
        location=loc,
        data={"mass": rounded(mass), "hull_volume": rounded(volume), "density": rounded(density)},
    )


class HullMemo:
    """Convex hulls by the exact bytes of their points: links drawn alike get one hull."""

    def __init__(self) -> None:
        self._hulls: dict[bytes, Hull] = {}

    def of(self, points: np.ndarray) -> Hull:
        """The convex hull of ``points`` (n, 3) [m], computed once per distinct point set
        (and kept in the active store, :mod:`geomcheck.geometry.hull_cache`)."""
        key = hashlib.sha256(np.ascontiguousarray(points, dtype=float).tobytes()).digest()
        if key not in self._hulls:
            self._hulls[key] = stored_hull(points)
        return self._hulls[key]


def check_geometry(
    link: Link,
    props: MassProperties,
    points: np.ndarray,
    triangle_ok: bool,
    th: InertiaThresholds,
    out: LinkFindings,
    hulls: HullMemo,
) -> None:
    """GC505, GC506, GC508 and the geometry fields of the section entry.

    GC505 is only reported for a tensor that some body could have (GC503 and GC504 pass):
    one that breaks them is impossible whatever the geometry, and is reported as such.
    """
    loc = (link.inertial.location if link.inertial else None) or link.location
    hull = hulls.of(points)
    distance = stored_distance_outside(hull, props.com)
    entry = out.entry
    entry["com_inside_bounds"] = distance <= th.com_margin_m
    entry["com_distance_outside"] = rounded(distance)
    entry["bounds"] = [metres_list(hull.lower), metres_list(hull.upper)]
    entry["hull_volume"] = rounded(hull.volume)
    entry["density"] = rounded(props.mass / hull.volume) if hull.volume > 0.0 else None
    if distance > th.com_margin_m:
        out.diagnostics.append(com_diagnostic(link, props, hull, distance, loc))
    elif (misplaced := misplaced_com(link, props, points, th, loc)) is not None:
        out.diagnostics.append(misplaced)
    if hull.volume > 0.0 and props.mass / hull.volume > th.max_density_kg_m3:
        out.diagnostics.append(density_diagnostic(link, props.mass, hull.volume, th, loc))
    if not props.positive_semidefinite:
        return
    bounds = geometry_bounds(props, points)
    entry["geometry_bound"] = rounded_list(bounds.moment_bound[:3])
    entry["reach"] = rounded_list(bounds.axis_reach[:3])
    entry["spread"] = rounded_list(np.sqrt(np.clip(bounds.spread[:3], 0.0, None) / props.mass))
    entry["extent"] = rounded_list(bounds.plane_reach[:3])
    entry["moments_xyz"] = rounded_list(bounds.moments[3:])
    entry["geometry_bound_xyz"] = rounded_list(bounds.moment_bound[3:])
    finding = geometry_diagnostic(link, props, bounds, th, loc)
    entry["within_geometry"] = finding is None
    if finding is not None and triangle_ok:
        implied = implied_inertia(link, props, points)
        if implied is not None:
            finding = replace(finding, data={**finding.data, "implied_inertia": implied})
        out.diagnostics.append(finding)


def implied_inertia(link: Link, props: MassProperties, points: np.ndarray) -> dict[str, float | None] | None:
    """The tensor [kg m^2] of the solid convex hull of ``points`` (n, 3) [m, link frame] with
    the stated mass, about the stated centre of mass, in the ``<inertial>``'s own axes (its
    origin's rpy): what GC505's fix writes. ``None`` when the points span no volume."""
    if link.inertial is None:
        return None
    solid = stored_solid_hull(points)
    if solid is None:
        return None
    offset = props.com - solid.center_mass
    about_com = solid.moment_inertia * (props.mass / solid.mass) + props.mass * (
        float(offset @ offset) * np.eye(3) - np.outer(offset, offset)
    )
    rotation = link.inertial.origin.rotation()
    tensor = rotation.T @ about_com @ rotation
    # six significant digits of the largest moment: the hull's round-off off the diagonal becomes 0
    quantum = 10.0 ** (math.floor(math.log10(float(np.abs(tensor).max()))) - 5)
    tensor = np.round(tensor / quantum) * quantum + 0.0
    return {
        key: rounded(float(tensor[i, j]))
        for key, (i, j) in zip(
            ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)), strict=True
        )
    }


def empty_entry(link: Link, inertial: Inertial) -> dict[str, Any]:
    """Section entry with every field present, geometry-dependent ones unknown (``None``)."""
    return {
        "link": link.name,
        "mass": rounded(inertial.mass),
        "com": rounded_list(inertial.origin.xyz),
        "principal_moments": None,
        "principal_axes": None,
        "geometry_bound": None,
        "radius_of_gyration": None,
        "reach": None,
        "positive_definite": None,
        "triangle_ok": None,
        "within_geometry": None,
        "com_inside_bounds": None,
        "spread": None,
        "extent": None,
        "moments_xyz": None,
        "geometry_bound_xyz": None,
        "com_distance_outside": None,
        "bounds": None,
        "hull_volume": None,
        "density": None,
        "copied_from": None,
    }


def check_link(
    link: Link,
    joint: Joint | None,
    body: Body,
    points_of: Callable[[str], np.ndarray | str],
    th: InertiaThresholds,
    hulls: HullMemo,
) -> LinkFindings:
    """Every GC5xx check of one link with an ``<inertial>`` but GC501 and GC507."""
    inertial = link.inertial
    assert inertial is not None
    loc = inertial.location or link.location
    out = LinkFindings(empty_entry(link, inertial))
    out.diagnostics.extend(mass_diagnostics(link, joint, body, th, loc))
    if not all(math.isfinite(v) for v in (*tensor_values(inertial), *inertial.origin.xyz, *inertial.origin.rpy)):
        out.entry["positive_definite"] = False
        out.diagnostics.append(
            NOT_POSITIVE_DEFINITE.diagnose(
                NOT_POSITIVE_DEFINITE.message("not_finite", tensor=vector_text(tensor_values(inertial))),
                link=link.name,
                about="inertia",
                location=loc,
                data={"tensor": [str(v) for v in tensor_values(inertial)]},
            )
        )
        return out
    props = mass_properties(inertial)
    entry = out.entry
    entry["principal_moments"] = rounded_list(props.moments)
    entry["principal_axes"] = distinct_axes(props.moments, props.axes)
    entry["positive_definite"] = props.positive_definite
    if not (props.mass > 0.0 and math.isfinite(props.mass)):
        # A massless link's tensor says nothing; GC502 reports the mass where it matters.
        return out
    tensor_findings, triangle_ok = tensor_diagnostics(link, props, joint is not None, th, loc)
    out.diagnostics.extend(tensor_findings)
    entry["triangle_ok"] = triangle_ok
    entry["radius_of_gyration"] = [rounded(math.sqrt(m / props.mass)) if m >= 0 else None for m in props.moments]
    points = points_of(link.name)
    if isinstance(points, str):
        out.skipped.append(SkippedCheck(GEOMETRY_CHECK, link.name, points))
        return out
    check_geometry(link, props, points, triangle_ok, th, out, hulls)
    return out


def missing_diagnostic(link: Link, joint: Joint, body: Body) -> Diagnostic:
    message = MISSING_INERTIAL.message(joint_type=joint.type, joint=joint.name)
    data: dict[str, Any] = {"joint": joint.name, "joint_type": joint.type}
    if body.merged:
        message += MISSING_INERTIAL.message("body", links=body.others_text(link.name))
        data["body_links"] = body.others(link.name)
    return MISSING_INERTIAL.diagnose(message, link=link.name, about="mass", location=link.location, data=data)


def kinematics_only_diagnostic(robot: Robot) -> Diagnostic | None:
    """One GC501 (info) for a description in which no link has an ``<inertial>``: written for
    planning and display (MoveIt, RViz), not for simulation, on purpose. ``None`` when some
    link has one, or nothing moves."""
    if any(link.inertial is not None for link in robot.links):
        return None
    moving = [link.name for link in unique_links(robot) if moving_joint(robot, link) is not None]
    if not moving:
        return None
    return MISSING_INERTIAL.diagnose(
        MISSING_INERTIAL.message("kinematics_only", count=len(moving)),
        help="Nothing to change for planning and display. To simulate the robot, give every moving link an "
        "<inertial> (mass, centre of mass and tensor from CAD, or the formulas of a box, cylinder or sphere "
        "enclosing the part).",
        about="mass",
        severity=Severity.INFO,
        data={"moving_links": len(moving)},
    )


class LinkPoints:
    """Each link's geometry points (:func:`link_geometry`), read once by whichever check needs them first."""

    def __init__(self, robot: Robot, meshes: MeshStore, analysis: AnalysisThresholds) -> None:
        self._robot = robot
        self._meshes = meshes
        self._analysis = analysis
        self._points: dict[str, np.ndarray | str] = {}

    def __call__(self, name: str) -> np.ndarray | str:
        if name not in self._points:
            self._points[name] = link_geometry(self._robot.link_map[name], self._meshes, self._analysis)
        return self._points[name]


def run(ctx: CheckContext) -> FamilyResult:
    robot = ctx.robot
    th = ctx.thresholds.inertia
    result = FamilyResult()
    copies = find_copies(robot, th)
    hulls = HullMemo()
    points_of = LinkPoints(robot, ctx.meshes, ctx.thresholds.analysis)
    weigher = Weigher(robot, th, points_of, hulls)
    entries = []
    kinematics_only = kinematics_only_diagnostic(robot)
    if kinematics_only is not None:
        result.diagnostics.append(kinematics_only)
    for link in unique_links(robot):
        joint = moving_joint(robot, link)
        body = weigher.bodies[link.name]
        if link.inertial is None:
            # pinocchio and Gazebo give a moving link the mass of the links fixed below it
            moving = joint is not None and not link.synthetic  # a frame between joints of one MJCF body
            if moving and joint is not None and kinematics_only is None and body.mass <= th.min_mass_kg:
                result.diagnostics.append(missing_diagnostic(link, joint, body))
            continue
        findings = check_link(link, joint, body, points_of, th, hulls)
        reference = copies.get(link.name)
        if reference is not None:
            findings.entry["copied_from"] = reference.name
            loc = link.inertial.location or link.location
            findings.diagnostics.append(copied_diagnostic(link, reference, loc))
        entries.append(findings.entry)
        result.diagnostics.extend(weigher.weigh(d) for d in findings.diagnostics)
        result.skipped.extend(findings.skipped)
    result.sections["inertia"] = entries
    result.diagnostics = template_origins(result.diagnostics, th.com_template_links)
    result.diagnostics.extend(check_counterparts(robot, ctx.analyses.kinematics, points_of, th))
    return result
