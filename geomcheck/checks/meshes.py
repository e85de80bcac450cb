"""GC2xx: every mesh a link refers to is found, readable, sound, and in metres.

Runs before the fit family and leaves, per mesh file and scale, statistics in
``ctx.analyses.mesh_stats`` (``MeshStats``); the geometry (:class:`Solid`: unique vertices,
bounded convex hull) is kept by the mesh store, computed once per file and scale. One
finding per problem file per referencing element: subject the link, ``about`` the element
(``visual[0]``, ``collision[1]``).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, replace
from pathlib import PurePosixPath
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.analyses import MeshStats
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.errors import GeomcheckError
from geomcheck.geometry.shapes import mesh_solid_in
from geomcheck.geometry.surface import Solid
from geomcheck.geometry.units import infer_unit_factor, median, plausible_factor
from geomcheck.load.meshes import LoadedMesh, MeshProblem, MeshStore
from geomcheck.model import Box, Cylinder, Joint, Link, Mesh, Robot, Shape, Sphere
from geomcheck.rules import Rule
from geomcheck.rules import meshes as rules
from geomcheck.thresholds import MeshThresholds

MIN_REFERENCE_LINKS = 3  # other links needed before the robot's typical size is a reference [count]
ZERO_AREA_M2 = 1e-12  # a surface smaller than this has no area [m^2]


def mesh_solid(ctx: CheckContext, mesh: Mesh) -> Solid | MeshProblem:
    """The mesh in its own frame (``scale`` applied) with its unique vertices and hull,
    computed once per file and scale; or why it is unavailable. Non-finite vertices are
    replaced by zeros here (GC207 reports them; the geometry is then unusable)."""
    return mesh_solid_in(ctx.meshes, mesh, ctx.thresholds.analysis)


def mesh_stats(ctx: CheckContext, mesh: Mesh) -> MeshStats | MeshProblem:
    """Statistics of ``mesh`` (computed once per file and scale), or why it is unavailable."""
    cache = ctx.analyses.mesh_stats
    key = (mesh.filename, mesh.scale)
    if key not in cache:
        solid = mesh_solid(ctx, mesh)
        if isinstance(solid, MeshProblem):
            cache[key] = solid
        else:
            loaded = ctx.meshes.get(mesh)
            assert not isinstance(loaded, MeshProblem)
            finite = bool(np.isfinite(loaded.vertices).all())
            unique = solid.vertices
            extents = np.ptp(unique, axis=0) if len(unique) and finite else np.zeros(3)
            cache[key] = MeshStats(
                extents=(float(extents[0]), float(extents[1]), float(extents[2])),
                area=solid.surface.area if finite else 0.0,
                hull_volume=solid.hull.volume if solid.hull is not None else 0.0,
                finite=finite,
                flat=solid.hull is None,
            )
    return cache[key]


def shapes(link: Link) -> Iterator[Shape]:
    yield from link.visuals
    yield from link.collisions


def shape_size(ctx: CheckContext, shape: Shape) -> float | None:
    """Largest extent [m] of a shape's geometry; ``None`` when a mesh is unavailable or unsound."""
    g = shape.geometry
    if isinstance(g, Box):
        return float(max(g.size))
    if isinstance(g, Cylinder):
        return float(max(2.0 * g.radius, g.length))
    if isinstance(g, Sphere):
        return 2.0 * float(g.radius)
    stats = mesh_stats(ctx, g)
    return stats.size if isinstance(stats, MeshStats) and stats.finite and stats.size > 0 else None


def case_fixed_filename(filename: str, suggestion: str) -> str:
    """``filename`` with its tail replaced by the existing path's letter case."""
    n = 0
    while n < min(len(filename), len(suggestion)) and filename[-1 - n].lower() == suggestion[-1 - n].lower():
        n += 1
    return filename[: len(filename) - n] + suggestion[len(suggestion) - n :]


def element_diagnostic(
    rule: Rule, link: Link, shape: Shape, message: str, data: dict[str, Any], help: str | None = None
) -> Diagnostic:
    """A finding of ``rule`` about one element of ``link``, located at the element."""
    return rule.diagnose(message, help=help, link=link.name, about=shape.label, location=shape.location, data=data)


def problem_diagnostic(link: Link, shape: Shape, problem: MeshProblem) -> Diagnostic:
    data = {
        "filename": problem.filename,
        "path": problem.path,
        "kind": problem.kind,
        "suggestion": problem.suggestion,
        "alternative": problem.alternative,
        "generated_from": problem.generated_from,
    }
    message = f"{shape.label} of link '{link.name}': {problem.message}"
    rule = {
        "missing-file": rules.MESH_FILE_NOT_FOUND,
        "unresolved-package": rules.MESH_PACKAGE_UNRESOLVED,
        "empty": rules.MESH_EMPTY,
        "out-of-range": rules.MESH_DEGENERATE,
    }.get(problem.kind, rules.MESH_UNREADABLE)
    help_text = None
    if problem.kind == "missing-file" and problem.suggestion:
        fixed = case_fixed_filename(problem.filename, problem.suggestion)
        data["existing_filename"] = fixed  # what geomcheck fix writes
        help_text = f'The file exists with other letter case: use filename="{fixed}".'
    elif problem.generated_from:
        help_text = (
            f"The package's build generates this file from {problem.generated_from} (rosbuild-era packages ran "
            "convex_decomposition and ivcon at build time): build the package before checking it, or point the "
            "collision element at a mesh kept in the package."
        )
    elif problem.alternative:
        help_text = (
            f"A mesh of the same name exists at {problem.alternative}: if it is the same part, use "
            f'filename="{problem.alternative}"; otherwise add the missing file or package.'
        )
    return element_diagnostic(rule, link, shape, message, data, help_text)


MAX_LINKS_NAMED = 5  # links a grouped finding's message names [count]


@dataclass(frozen=True)
class Reference:
    """One element whose mesh a grouped finding is about."""

    link: Link
    shape: Shape
    position: int  # the element's place in document order: the finding is located at the first

    @property
    def filename(self) -> str:
        assert isinstance(self.shape.geometry, Mesh)
        return self.shape.geometry.filename

    def row(self, **extra: object) -> dict[str, object]:
        return {"link": self.link.name, "about": self.shape.label, "filename": self.filename, **extra}


def package_of(filename: str) -> str:
    """The package a ``package://`` filename names (``""`` for other filenames)."""
    name = filename.strip()
    if not name.startswith("package://"):
        return ""
    return name[len("package://") :].lstrip("/").partition("/")[0]


def _links_text(references: list[Reference]) -> tuple[list[str], str]:
    """The links of ``references`` sorted, and a few of them in words."""
    names = sorted({r.link.name for r in references})
    listed = ", ".join(names[:MAX_LINKS_NAMED])
    if len(names) > MAX_LINKS_NAMED:
        listed += f" and {len(names) - MAX_LINKS_NAMED} more"
    return names, listed


def _sorted(references: list[Reference]) -> list[Reference]:
    return sorted(references, key=lambda r: (r.link.name, r.shape.kind, r.shape.index))


def unknown_package_diagnostic(
    package: str, found: list[tuple[Reference, MeshProblem]], known: str, advice: str
) -> Diagnostic:
    """GC202: one finding per unknown package, however many elements name it; it lists them
    (link, element, filename, and the file of the same name elsewhere in the bundle when there is one)."""
    problems = {id(r): p for r, p in found}
    references = _sorted([r for r, _ in found])
    first = min(references, key=lambda r: r.position)
    names, listed = _links_text(references)
    alternatives = {r.filename: problems[id(r)].alternative for r in references if problems[id(r)].alternative}
    n = len(references)
    noun = "mesh reference" if n == 1 else "mesh references"
    message = (
        f"package '{package}' is not known (known packages: {known}): {n} {noun} on "
        f"{len(names)} link{'s' if len(names) != 1 else ''} ({listed}) cannot be loaded"
    )
    help_text = f"{advice[0].upper()}{advice[1:]}, or correct the package name."
    if alternatives:
        example = alternatives[min(alternatives)]
        k = len(alternatives)
        verb = "exists" if k == 1 else "exist"
        message += f"; {k} of the files {verb} under the same name elsewhere, such as {example}"
        help_text = (
            f"{advice[0].upper()}{advice[1:]}; if another package replaced "
            f"'{package}', point the filenames at it (the finding's data lists the file of the same name found "
            "for each reference)."
        )
    return rules.MESH_PACKAGE_UNRESOLVED.diagnose(
        message,
        help=help_text,
        about=f"package:{package}",
        location=first.shape.location,
        data={
            "package": package,
            "kind": "unresolved-package",
            "count": n,
            "links": names,
            "references": [r.row(alternative=problems[id(r)].alternative) for r in references],
        },
    )


def unbuilt_diagnostic(package: str, references: list[tuple[Reference, LoadedMesh]]) -> Diagnostic:
    """GC201, as information: the build products of a package that is not built (one finding
    per package); each is analysed as the source mesh the build makes it from."""
    loaded = {id(r): m for r, m in references}
    refs = _sorted([r for r, _ in references])
    first = min(refs, key=lambda r: r.position)
    names, listed = _links_text(refs)
    files = sorted({str(loaded[id(r)].stands_for) for r in refs})
    where = f"package '{package}'" if package else "the description's folder"
    n = len(files)
    message = (
        f"{where} is not built: {n} convex decomposition{'s' if n != 1 else ''} (convex/NAME_convex.stlb) that "
        f"its rosbuild build generates from NAME.stl {'are' if n != 1 else 'is'} missing, used by {len(refs)} "
        f"element{'s' if len(refs) != 1 else ''} on {len(names)} link{'s' if len(names) != 1 else ''} ({listed}); "
        "geomcheck analyses each source mesh in its place"
    )
    return rules.MESH_FILE_NOT_FOUND.diagnose(
        message,
        help=(
            "Build the package before checking it (rosbuild-era packages ran convex_decomposition and ivcon at "
            "build time), or point the collision elements at meshes kept in the package."
        ),
        about=f"package:{package}" if package else "build-products",
        location=first.shape.location,
        data={
            "package": package,
            "kind": "build-product",
            "count": len(refs),
            "links": names,
            "files": files,
            "references": [r.row(generated_from=loaded[id(r)].path) for r in refs],
        },
        severity=Severity.INFO,
    )


def quirk_diagnostic(link: Link, shape: Shape, quirk: str) -> Diagnostic:
    """GC202: a filename pinocchio accepts and resource_retriever (RViz, Gazebo, MoveIt) refuses,
    loaded as pinocchio loads it so that every other check still runs."""
    assert isinstance(shape.geometry, Mesh)
    filename = shape.geometry.filename
    fixed = "package://" + filename.strip()[len("package://") :].lstrip("/")
    return rules.MESH_PACKAGE_UNRESOLVED.diagnose(
        f"{shape.label} of link '{link.name}': {quirk}",
        help=f'Write filename="{fixed}": every tool reads that form.',
        link=link.name,
        about=shape.label,
        location=shape.location,
        data={"filename": filename, "kind": "tool-dependent", "accepted_by": ["pinocchio"], "alternative": fixed},
    )


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
    verdict = infer_unit_factor(size, link_ref, robot_ref, th.unit_factor_tolerance, trusted, span)
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


def integrity_diagnostic(link: Link, shape: Shape, stats: MeshStats) -> Diagnostic | None:
    """GC207/GC208 for one loaded mesh element."""
    mesh = shape.geometry
    assert isinstance(mesh, Mesh)
    name = PurePosixPath(mesh.filename).name
    data = {"filename": mesh.filename, "area": stats.area, "hull_volume": stats.hull_volume, "finite": stats.finite}
    if not stats.finite:
        message = f"{shape.label} mesh {name} has non-finite (NaN or infinite) vertex coordinates"
        return element_diagnostic(rules.MESH_DEGENERATE, link, shape, message, data)
    if stats.area <= ZERO_AREA_M2:
        message = f"{shape.label} mesh {name} has no surface: its triangles have zero total area"
        return element_diagnostic(rules.MESH_DEGENERATE, link, shape, message, data)
    if stats.flat:
        e = stats.extents
        message = f"{shape.label} mesh {name} is flat: it spans {e[0]:.3g} x {e[1]:.3g} x {e[2]:.3g} m, no volume"
        if shape.kind == "visual":
            # a flat label, screen or decal is drawn as intended and never collides
            return rules.MESH_FLAT.diagnose(
                message + " (a visual: drawn as intended, it never collides)",
                link=link.name,
                about=shape.label,
                location=shape.location,
                data=data,
                severity=Severity.INFO,
            )
        return element_diagnostic(rules.MESH_FLAT, link, shape, message, data)
    return None


def winding_diagnostic(ctx: CheckContext, link: Link, shape: Shape, th: MeshThresholds) -> Diagnostic | None:
    """GC210 for a mesh whose faces disagree with their neighbours' winding, or that is inside out
    (each file and scale examined once)."""
    mesh = shape.geometry
    loaded = ctx.meshes.get(mesh) if isinstance(mesh, Mesh) else None
    if not isinstance(loaded, LoadedMesh) or len(loaded.faces) > th.winding_max_faces:
        return None
    cache = ctx.analyses.windings
    key = (loaded.filename, mesh.scale if isinstance(mesh, Mesh) else None)
    if key not in cache:
        from geomcheck.geometry.orientation import winding

        cache[key] = winding(loaded.vertices, loaded.faces)
    found = cache[key]
    name = PurePosixPath(loaded.filename).name
    if found.inconsistent_share >= th.inconsistent_winding_share:
        message = rules.MESH_WINDING.message(
            "mixed", label=shape.label, name=name, inconsistent=found.inconsistent, shared=found.shared,
            share=found.inconsistent_share,
        )  # fmt: skip
    elif found.inside_out:
        message = rules.MESH_WINDING.message("inside_out", label=shape.label, name=name, volume=found.volume)
    else:
        return None
    data = {
        "filename": loaded.filename,
        "shared_edges": found.shared,
        "inconsistent_edges": found.inconsistent,
        "inconsistent_share": round(found.inconsistent_share, 4),
        "closed": found.closed,
        "signed_volume": float(f"{found.volume:.6g}"),
    }
    return element_diagnostic(rules.MESH_WINDING, link, shape, message, data)


COLLISION_FOLDERS = ("collision", "collisions")
VISUAL_FOLDERS = ("visual", "visuals")
MESH_SUFFIXES = (".dae", ".stl", ".obj", ".DAE", ".STL", ".OBJ")


def visual_beside(ctx: CheckContext, mesh: Mesh) -> str | None:
    """The visual mesh of the same name in the ``visual`` folder beside the ``collision`` folder
    that ``mesh``'s file lies in, written as the URDF would name it, if one exists in the bundle."""
    written = mesh.filename.strip().split("/")
    for i in range(len(written) - 2, -1, -1):
        if written[i].lower() not in COLLISION_FOLDERS:
            continue
        stem = PurePosixPath(written[-1]).stem
        for folder in VISUAL_FOLDERS:
            for suffix in MESH_SUFFIXES:
                name = "/".join([*written[:i], folder, *written[i + 1 : -1], stem + suffix])
                path = ctx.meshes.resolve(name)
                if isinstance(path, MeshProblem):
                    return None
                try:  # announced to the whole-check cache as every look of a loader is
                    if ctx.meshes.bundle.check_access(path).is_file():
                        return name
                except GeomcheckError:
                    continue
        return None
    return None


def coarse_visual_diagnostic(ctx: CheckContext, link: Link, shape: Shape) -> Diagnostic | None:
    """GC211 for a visual drawing a collision folder's mesh when the visual mesh lies beside it."""
    mesh = shape.geometry
    if shape.kind != "visual" or not isinstance(mesh, Mesh):
        return None
    found = visual_beside(ctx, mesh)
    if found is None:
        return None
    message = rules.VISUAL_DRAWS_COLLISION_MESH.message(
        label=shape.label, name=PurePosixPath(mesh.filename).name, visual=found
    )
    return element_diagnostic(
        rules.VISUAL_DRAWS_COLLISION_MESH, link, shape, message, {"filename": mesh.filename, "visual_mesh": found}
    )


def run(ctx: CheckContext) -> FamilyResult:
    with threadpool_limits(limits=1, user_api="blas"):
        return _run(ctx)


def _run(ctx: CheckContext) -> FamilyResult:
    result = FamilyResult()
    th = ctx.thresholds.meshes
    refs = UnitReferences(ctx, ctx.robot)
    # one finding per unknown package and per package not built, however many elements they concern
    unknown: dict[str, list[tuple[Reference, MeshProblem]]] = {}
    unbuilt: dict[str, list[tuple[Reference, LoadedMesh]]] = {}
    position = 0
    for link in ctx.robot.links:
        for shape in shapes(link):
            if not isinstance(shape.geometry, Mesh):
                continue
            position += 1
            stats = mesh_stats(ctx, shape.geometry)
            quirk = MeshStore.accepted_quirk(shape.geometry.filename)
            if quirk is not None and not isinstance(stats, MeshProblem):
                result.diagnostics.append(quirk_diagnostic(link, shape, quirk))
            if isinstance(stats, MeshProblem) and stats.kind == "unresolved-package":
                package = package_of(shape.geometry.filename)
                unknown.setdefault(package, []).append((Reference(link, shape, position), stats))
                continue
            if isinstance(stats, MeshProblem):
                result.diagnostics.append(problem_diagnostic(link, shape, stats))
                continue
            loaded = ctx.meshes.get(shape.geometry)
            if isinstance(loaded, LoadedMesh) and loaded.stands_for is not None:
                package = package_of(shape.geometry.filename)
                unbuilt.setdefault(package, []).append((Reference(link, shape, position), loaded))
            found = integrity_diagnostic(link, shape, stats)
            if found is not None and found.code == rules.MESH_DEGENERATE.code:
                result.diagnostics.append(found)
                continue
            if found is not None:
                result.diagnostics.append(found)
            wound = winding_diagnostic(ctx, link, shape, th)
            if wound is not None:
                result.diagnostics.append(wound)
            coarse = coarse_visual_diagnostic(ctx, link, shape)
            if coarse is not None:
                result.diagnostics.append(coarse)
            unit = loaded.unit if isinstance(loaded, LoadedMesh) else 1.0
            units = units_diagnostic(link, shape, stats, refs, th, unit)
            if units is not None:
                result.diagnostics.append(units)
            declared = declared_unit_diagnostic(link, shape, stats, unit)
            if declared is not None:
                result.diagnostics.append(declared)
    result.diagnostics = declared_units_grouped(result.diagnostics)
    known = ", ".join(ctx.meshes.bundle.packages) or "none"
    result.diagnostics += [
        unknown_package_diagnostic(p, found, known, ctx.meshes.bundle.package_advice(p))
        for p, found in sorted(unknown.items())
    ]
    result.diagnostics += [unbuilt_diagnostic(p, found) for p, found in sorted(unbuilt.items())]
    return result
