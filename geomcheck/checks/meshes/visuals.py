"""GC211: a visual drawing the coarse collision mesh while the visual mesh lies beside it."""

from __future__ import annotations

from pathlib import PurePosixPath

from geomcheck.checks import CheckContext
from geomcheck.checks.meshes.stats import element_diagnostic
from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import GeomcheckError
from geomcheck.load.meshes import MeshProblem
from geomcheck.model import Link, Mesh, Shape
from geomcheck.rules import meshes as rules

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
