"""One mesh element's checks, in order, and the family's ``run``."""

from __future__ import annotations

from dataclasses import dataclass, field

from threadpoolctl import threadpool_limits

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.meshes.files import problem_diagnostic, quirk_diagnostic
from geomcheck.checks.meshes.packages import (
    Reference,
    beside_package_diagnostic,
    package_of,
    unbuilt_diagnostic,
    unknown_package_diagnostic,
)
from geomcheck.checks.meshes.soundness import integrity_diagnostic, winding_diagnostic
from geomcheck.checks.meshes.stats import mesh_stats, shapes
from geomcheck.checks.meshes.units import (
    UnitReferences,
    declared_unit_diagnostic,
    declared_units_grouped,
    units_diagnostic,
)
from geomcheck.checks.meshes.visuals import coarse_visual_diagnostic
from geomcheck.diagnostics import Diagnostic
from geomcheck.load.meshes import LoadedMesh, MeshProblem, MeshStore
from geomcheck.model import Mesh
from geomcheck.rules import meshes as rules


@dataclass
class PackageGroups:
    """The elements of unknown packages and of packages not built, by package: one finding per package,
    however many elements it concerns."""

    unknown: dict[str, list[tuple[Reference, MeshProblem]]] = field(default_factory=dict)
    unbuilt: dict[str, list[tuple[Reference, LoadedMesh]]] = field(default_factory=dict)
    beside: dict[str, list[Reference]] = field(default_factory=dict)  # read from the root file's folder


def run(ctx: CheckContext) -> FamilyResult:
    with threadpool_limits(limits=1, user_api="blas"):
        return _run(ctx)


def _run(ctx: CheckContext) -> FamilyResult:
    result = FamilyResult()
    refs = UnitReferences(ctx, ctx.robot)
    groups = PackageGroups()
    position = 0
    for link in ctx.robot.links:
        for shape in shapes(link):
            if not isinstance(shape.geometry, Mesh):
                continue
            position += 1
            result.diagnostics += element_findings(ctx, Reference(link, shape, position), refs, groups)
    result.diagnostics = declared_units_grouped(result.diagnostics)
    known = ", ".join(ctx.meshes.bundle.packages) or "none"
    result.diagnostics += [
        unknown_package_diagnostic(p, found, known, ctx.meshes.bundle.package_advice(p))
        for p, found in sorted(groups.unknown.items())
    ]
    result.diagnostics += [unbuilt_diagnostic(p, found) for p, found in sorted(groups.unbuilt.items())]
    result.diagnostics += [
        beside_package_diagnostic(ctx.meshes, p, found, known, ctx.meshes.bundle.package_advice(p))
        for p, found in sorted(groups.beside.items())
    ]
    return result


def element_findings(
    ctx: CheckContext, ref: Reference, refs: UnitReferences, groups: PackageGroups
) -> list[Diagnostic]:
    """The findings of one mesh element, in order; an unknown package's or an unbuilt package's
    element is put in ``groups`` instead. A degenerate mesh is checked no further."""
    link, shape, mesh = ref.link, ref.shape, ref.shape.geometry
    assert isinstance(mesh, Mesh)
    out: list[Diagnostic] = []
    stats = mesh_stats(ctx, mesh)
    quirk = MeshStore.accepted_quirk(mesh.filename)
    if quirk is not None and not isinstance(stats, MeshProblem):
        out.append(quirk_diagnostic(link, shape, quirk))
    if isinstance(stats, MeshProblem):
        if stats.kind == "unresolved-package":
            groups.unknown.setdefault(package_of(mesh.filename), []).append((ref, stats))
        else:
            out.append(problem_diagnostic(link, shape, stats))
        return out
    package = package_of(mesh.filename)
    if package and ctx.meshes.folder_beside(package) is not None:
        groups.beside.setdefault(package, []).append(ref)
    loaded = ctx.meshes.get(mesh)
    if isinstance(loaded, LoadedMesh) and loaded.stands_for is not None:
        groups.unbuilt.setdefault(package_of(mesh.filename), []).append((ref, loaded))
    found = integrity_diagnostic(link, shape, stats)
    if found is not None:
        out.append(found)
        if found.code == rules.MESH_DEGENERATE.code:
            return out
    th = ctx.thresholds.meshes
    unit = loaded.unit if isinstance(loaded, LoadedMesh) else 1.0
    later = (
        winding_diagnostic(ctx, link, shape, th),
        coarse_visual_diagnostic(ctx, link, shape),
        units_diagnostic(link, shape, stats, refs, th, unit),
        declared_unit_diagnostic(link, shape, stats, unit),
    )
    out.extend(d for d in later if d is not None)
    return out
