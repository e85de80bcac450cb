"""GC205, GC206 and GC209: a mesh in other units than the metre, or of a size no robot link has."""

from __future__ import annotations

import functools
from collections import Counter
from dataclasses import replace
from pathlib import PurePosixPath

import numpy as np

from geomcheck.checks import CheckContext
from geomcheck.checks.analyses import MeshStats
from geomcheck.checks.meshes.stats import element_diagnostic, shape_size, shapes
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.geometry.units import infer_unit_factor, median, plausible_factor
from geomcheck.model import Box, Cylinder, Joint, Link, Mesh, Robot, Shape, Sphere
from geomcheck.rules import meshes as rules
from geomcheck.thresholds import MeshThresholds

MIN_REFERENCE_LINKS = 3  # other links needed before the robot's typical size is a reference [count]


def _scale_text(scale: tuple[float, float, float], factor: float) -> str:
    return " ".join(f"{s * factor:.6g}" for s in scale)


def primitive_corners(shape: Shape) -> np.ndarray | None:
    """The 8 corners (8, 3) [m] in the link frame of the box enclosing a primitive element
    (``None`` for a mesh)."""
    g = shape.geometry
    if isinstance(g, Box):
        half = 0.5 * np.asarray(g.size, dtype=float)
    elif isinstance(g, Cylinder):
        half = np.array([g.radius, g.radius, 0.5 * g.length], dtype=float)
    elif isinstance(g, Sphere):
        half = np.full(3, float(g.radius))
    else:
        return None
    signs = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    transform = shape.origin.matrix()
    corners: np.ndarray = (signs * half) @ transform[:3, :3].T + transform[:3, 3]
    return corners


def link_span(link: Link, child_joints: tuple[Joint, ...]) -> float | None:
    """Largest extent [m] of what a link has in metres whatever its meshes' units: its
    primitives (visual and collision) and, when joints hang from it, its origin and their
    origins; ``None`` when it has neither."""
    points = [c for c in (primitive_corners(s) for s in shapes(link)) if c is not None]
    if child_joints:
        points.append(np.array([(0.0, 0.0, 0.0), *(j.origin.xyz for j in child_joints)], dtype=float))
    if not points:
        return None
    return float(np.ptp(np.concatenate(points), axis=0).max())


class UnitReferences:
    """Reference sizes [m] for the unit check: per link, the sizes of its shapes split into
    primitives and meshes (with their filenames), so a mesh is never its own reference, and
    the link's span (:func:`link_span`)."""

    def __init__(self, ctx: CheckContext, robot: Robot) -> None:
        self.analyses = ctx.analyses
        self.per_link: dict[str, list[tuple[float, str | None]]] = {}
        self.spans: dict[str, float | None] = {}
        for link in robot.links:
            sizes = []
            for shape in shapes(link):
                size = shape_size(ctx, shape)
                if size is not None:
                    name = shape.geometry.filename if isinstance(shape.geometry, Mesh) else None
                    sizes.append((size, name))
            self.per_link.setdefault(link.name, []).extend(sizes)
            self.spans[link.name] = link_span(link, robot.child_joints.get(link.name, ()))

    def link(self, link: Link, shape: Shape) -> tuple[float | None, bool]:
        """Median size of the link's other geometry (primitives when it has any) and whether
        it is made of primitives (trusted: typed in metres)."""
        assert isinstance(shape.geometry, Mesh)
        own = shape.geometry.filename
        others = [(s, f) for s, f in self.per_link.get(link.name, []) if f != own]
        primitives = [s for s, f in others if f is None]
        if primitives:
            return median(primitives), True
        return median([s for s, _ in others]), False

    def robot_extent(self, typical: float | None) -> float | None:
        """The robot's extent [m]: the diagonal of the box holding its link frames with every
        joint at zero (or its nearest limit), plus a ``typical`` link's size; ``None`` without
        that size."""
        return None if typical is None else self.origins_span + typical

    @functools.cached_property
    def origins_span(self) -> float:
        """The diagonal [m] of the box holding the link frames, every joint at zero or its nearest
        limit; the kinematics are read only when a mesh is judged against the robot's extent."""
        kin = self.analyses.kinematics
        q = np.clip(np.zeros(len(kin.joints)), kin.lower, kin.upper)
        origins = kin.link_transforms(q[None])[0][:, :3, 3]
        return float(np.linalg.norm(np.ptp(origins, axis=0))) if len(origins) else 0.0

    def robot(self, link: Link, filename: str) -> float | None:
        """Typical size of the other links: the median of their largest shape (meshes of
        ``filename`` left out), once enough links have one."""
        sizes = []
        for name, shapes_sizes in self.per_link.items():
            usable = [s for s, f in shapes_sizes if f != filename]
            if name != link.name and usable:
                sizes.append(max(usable))
        return median(sizes) if len(sizes) >= MIN_REFERENCE_LINKS else None


def declared_unit_text(unit: float) -> str:
    """What a size message says of a unit the mesh file declares (nothing for metres)."""
    return "" if unit == 1.0 else f'; its declared <unit meter="{unit:g}"> is applied, as RViz and Gazebo apply it'


def units_diagnostic(
    link: Link, shape: Shape, stats: MeshStats, refs: UnitReferences, th: MeshThresholds, unit: float = 1.0
) -> Diagnostic | None:
    """GC205/GC206 for one loaded mesh element, or ``None`` when its size is plausible. ``unit``:
    the metres per file unit the file declares, already applied (named in the message)."""
    mesh = shape.geometry
    assert isinstance(mesh, Mesh)
    size = stats.size
    link_ref, trusted = refs.link(link, shape)
    robot_ref = refs.robot(link, mesh.filename)
    span = refs.spans.get(link.name)
    extent = refs.robot_extent(robot_ref)
    verdict = infer_unit_factor(
        size, link_ref, robot_ref, th.unit_factor_tolerance, trusted, span, stats.offset, extent
    )
    absurd = size > th.max_link_extent_m or size < th.min_link_extent_m
    name = PurePosixPath(mesh.filename).name
    data = {
        "filename": mesh.filename,
        "scale": list(mesh.scale),
        "extents": [round(e, 6) for e in stats.extents],
        "size": round(size, 6),
        "link_reference": None if link_ref is None else round(link_ref, 6),
        "robot_reference": None if robot_ref is None else round(robot_ref, 6),
    }
    if verdict is not None:
        ratio = verdict.link_ratio if verdict.link_ratio is not None else verdict.robot_ratio
        assert ratio is not None
        what = "the link's other geometry" if verdict.reference == "link" else "a typical link of this robot"
        ref = link_ref if verdict.reference == "link" else robot_ref
        direction = "large" if verdict.factor > 1 else "small"
        times = verdict.factor if verdict.factor > 1 else 1.0 / verdict.factor
        new_scale = _scale_text(mesh.scale, verdict.scale_factor)
        message = (
            f"{shape.label} mesh {name} is {times:.4g}x too {direction} ({verdict.explanation}?): it spans "
            f"{size:.3g} m against {ref:.3g} m for {what} (ratio {ratio:.3g})"
        )
        if verdict.reference == "link" and robot_ref is not None and verdict.robot_ratio is not None:
            message += f" and {robot_ref:.3g} m for a typical link ({verdict.robot_ratio:.3g}x)"
        message += declared_unit_text(unit)
        data |= {"factor": round(verdict.factor, 6), "suggested_scale": new_scale, "reference": verdict.reference}
        set_scale = f'Set scale="{new_scale}" on the <mesh> element (it is now "{_scale_text(mesh.scale, 1.0)}").'
        return element_diagnostic(rules.MESH_SCALE_SUSPECT, link, shape, message, data, set_scale)
    if not absurd:
        return None
    limit = th.max_link_extent_m if size > th.max_link_extent_m else th.min_link_extent_m
    side = "larger" if size > limit else "smaller"
    message = f"{shape.label} mesh {name} spans {size:.3g} m, {side} than any robot link should ({limit:g} m)"
    message += declared_unit_text(unit)
    guess = plausible_factor(size, robot_ref)
    fix: str | None = None
    if guess is not None:
        new_scale = _scale_text(mesh.scale, 1.0 / guess[0])
        data |= {"factor": round(guess[0], 6), "suggested_scale": new_scale}
        fix = f'If the mesh is in other units ({guess[1]}), set scale="{new_scale}" on the <mesh> element.'
    return element_diagnostic(rules.MESH_SIZE_IMPLAUSIBLE, link, shape, message, data, fix)


def declared_unit_diagnostic(link: Link, shape: Shape, stats: MeshStats, unit: float) -> Diagnostic | None:
    """GC209 for a mesh whose file declares a unit other than the metre (``None`` otherwise):
    an error for a collision element, information for a visual one."""
    mesh = shape.geometry
    assert isinstance(mesh, Mesh)
    if unit == 1.0:
        return None
    name = PurePosixPath(mesh.filename).name
    unapplied = stats.size / unit
    new_scale = _scale_text(mesh.scale, unit)
    message = (
        f'{shape.label} mesh {name} declares <unit meter="{unit:g}">: RViz and Gazebo apply it ({stats.size:.3g} m '
        f"across), MoveIt and pinocchio do not ({unapplied:.3g} m across)"
    )
    data = {
        "filename": mesh.filename,
        "unit": unit,
        "scale": list(mesh.scale),
        "size": round(stats.size, 6),
        "size_unapplied": round(unapplied, 6),
        "suggested_scale": new_scale,
    }
    help_text = (
        f'Declare <unit meter="1"/> in {name} and set scale="{new_scale}" on the <mesh> element: every tool '
        "applies the URDF scale."
    )
    severity = Severity.INFO if shape.kind == "visual" else None
    if severity is not None:
        message += " (a visual: only viewers of pinocchio's visual model draw it otherwise)"
    return rules.MESH_UNIT_TOOL_DEPENDENT.diagnose(
        message,
        help=help_text,
        link=link.name,
        about=shape.label,
        location=shape.location,
        data=data,
        severity=severity,
    )


LISTED_MESHES = 5  # other meshes named in a grouped GC209 message; its data lists them all


def declared_units_grouped(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """``diagnostics`` with the GC209 findings of one link's meshes of one kind (visual or
    collision) declaring one unit reported once, as the first, naming the other files: a part
    exported as 18 COLLADA files in millimetres is one finding, as repeats of a macro are."""
    groups: dict[tuple[str | None, str, float], list[int]] = {}
    for index, d in enumerate(diagnostics):
        if d.code == rules.MESH_UNIT_TOOL_DEPENDENT.code:
            kind = d.about.split("[", 1)[0]
            groups.setdefault((d.link, kind, float(d.data["unit"])), []).append(index)
    dropped: set[int] = set()
    out = list(diagnostics)
    for members in groups.values():
        if len(members) < 2:
            continue
        first, others = diagnostics[members[0]], [diagnostics[i] for i in members[1:]]
        # each file once, with how often the link uses it (one spacer file drawn four times)
        used = Counter(PurePosixPath(str(d.data["filename"])).name for d in others)
        names = [f"{name} x{count}" if count > 1 else name for name, count in used.items()]
        listed = ", ".join(names[:LISTED_MESHES]) + (
            f" and {len(names) - LISTED_MESHES} more files" if len(names) > LISTED_MESHES else ""
        )
        out[members[0]] = replace(
            first,
            message=f"{first.message} (also {len(others)} more {first.about.split('[', 1)[0]} meshes: {listed})",
            data={**first.data, "meshes": [str(d.data["filename"]) for d in others]},
        )
        dropped.update(members[1:])
    return [d for i, d in enumerate(out) if i not in dropped]
