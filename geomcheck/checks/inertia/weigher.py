"""The family's severity policy: a finding lowered by its consequence, saying why (:class:`Weigher`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from geomcheck.checks.inertia.bodies import Body, MergedBody, rigid_bodies, usable_mass
from geomcheck.checks.inertia.placeholders import round_placeholder, round_tensor, uniform_placeholder
from geomcheck.checks.inertia.points import HullMemo
from geomcheck.checks.inertia.values import percent, rounded, unique_links
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.model import Mesh, Robot
from geomcheck.rules.inertia import (
    COM_MISPLACED,
    COM_OUTSIDE,
    COPIED_INERTIA,
    EXCEEDS_GEOMETRY,
    IMPLAUSIBLE_DENSITY,
    NOT_POSITIVE_DEFINITE,
    TRIANGLE_INEQUALITY,
)
from geomcheck.thresholds import InertiaThresholds

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


@dataclass
class Lowering:
    """Why a finding's severity changes: ``reasons`` take it to info (no part's data judged),
    ``notes`` lower an error to a warning and never further; ``data`` records them in the finding."""

    reasons: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)


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
        why = Lowering()
        self._merged_body(d, d.link, test, why)
        if d.code in LIGHT_LOWERED:
            self._light_link(d, d.link, why)
        if not why.reasons and not why.notes:
            return d
        return self._lowered(d, d.link, why)

    def _merged_body(
        self, d: Diagnostic, name: str, test: Callable[[MergedBody, InertiaThresholds], bool], why: Lowering
    ) -> None:
        """The body ``name`` is merged into passes the check: a marker on a frame fixed to it goes to
        info, any other member down to a warning."""
        body = self.bodies[name]
        link = self.robot.link_map[name]
        placeholder = d.code in LIGHT_LOWERED and round_placeholder(link.inertial)
        fixed_marker = link.name != body.top and (d.data.get("point_mass") or placeholder)
        if not (body.merged and test(self.merged(body), self.th)):
            return
        why.data["body"] = body.top
        if fixed_marker:
            # a point mass, or round values typed for "unknown", on a frame fixed to a body that passes:
            # consumers merge it away, and no part's own values are wrong
            what = "a point mass" if d.data.get("point_mass") else "placeholder values (powers of ten)"
            why.reasons.append(f"{what} on a frame fixed to body {body.top}, which passes this check once merged")
            return
        why.notes.append(
            f"fixed joints merge it with {body.others_text(name)} into body {body.top}, which passes this "
            "check as pinocchio, Gazebo and MuJoCo simulate it; the link's own values are still wrong and are "
            "part of that body"
        )
        mass = usable_mass(link)
        why.data["body_mass_share"] = rounded(mass / body.mass) if body.mass > 0.0 else None

    def _light_link(self, d: Diagnostic, name: str, why: Lowering) -> None:
        """A light link's plausibility against its geometry: down to a warning for its small share of the
        robot's mass, to info when its values or its geometry are placeholders."""
        share = self.share(name)
        if share < self.th.minor_mass_share:
            why.notes.append(f"the link carries {percent(share)} of the robot's {self.total:.4g} kg")
            why.data["mass_share"] = rounded(share)
            ratio = float((d.data.get("worst") or {}).get("ratio") or 0.0)
            if d.code == EXCEEDS_GEOMETRY.code and 0.0 < ratio <= self.th.marginal_ratio:
                why.reasons.append(f"a light part's estimate {ratio:.2g} times the bound, a little off")
        link = self.robot.link_map[name]
        if d.code == EXCEEDS_GEOMETRY.code and round_tensor(link.inertial):
            why.reasons.append(
                "a round tensor (one power of ten on every axis) with the part's computed mass: set on purpose, "
                "as authors do to steady small links in Gazebo"
            )
        if self.placeholders:
            why.reasons.append(f"all {self.placeholders} links with an <inertial> carry this same one: placeholders")
        extent = self.placeholder_geometry(name, marker=d.code in GEOMETRY_LOWERED)
        if extent is not None:
            why.reasons.append(f"the link's geometry is a {extent * 1000:.2g} mm placeholder, not a part")
        mass = usable_mass(link)
        if 0.0 < mass <= self.th.negligible_mass_kg:
            why.reasons.append(f"its {mass:.3g} kg makes it a massless frame's placeholder, not a part")

    def _lowered(self, d: Diagnostic, name: str, why: Lowering) -> Diagnostic:
        """``d`` at the severity ``why`` gives it: info for a reason, one level per note down to a
        warning at most; its message and data saying why."""
        order = [Severity.ERROR, Severity.WARNING, Severity.INFO]
        level = order.index(d.severity)
        if why.reasons:
            level = len(order) - 1
        else:
            level = max(level, min(level + len(why.notes), order.index(Severity.WARNING)))
        severity = order[level]
        data = dict(why.data)
        data.setdefault("mass_share", rounded(self.share(name)))
        data.setdefault("body", None)
        data.setdefault("body_mass_share", None)
        said = "; ".join([*why.reasons, *why.notes])
        if severity is d.severity:
            message = f"{d.message} (kept at {severity.value}: {said})"
        else:
            message = f"{d.message} ({d.severity.value} lowered to {severity.value}: {said})"
        return replace(d, severity=severity, message=message, data={**d.data, **data})
