"""GC207, GC208 and GC210: a mesh without a sound surface, flat, or wound inconsistently."""

from __future__ import annotations

from pathlib import PurePosixPath

from geomcheck.checks import CheckContext
from geomcheck.checks.analyses import MeshStats
from geomcheck.checks.meshes.stats import element_diagnostic
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load.meshes import LoadedMesh
from geomcheck.model import Link, Mesh, Shape
from geomcheck.rules import meshes as rules
from geomcheck.thresholds import MeshThresholds

ZERO_AREA_M2 = 1e-12  # a surface smaller than this has no area [m^2]


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
