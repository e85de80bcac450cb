"""GC201-GC204 (GC207 for a file out of range): a mesh file that cannot be used as found, or that is
named in a form some tools refuse."""

from __future__ import annotations

from geomcheck.checks.meshes.stats import element_diagnostic
from geomcheck.diagnostics import Diagnostic
from geomcheck.load.meshes import MeshProblem
from geomcheck.model import Link, Mesh, Shape
from geomcheck.rules import meshes as rules


def case_fixed_filename(filename: str, suggestion: str) -> str:
    """``filename`` with its tail replaced by the existing path's letter case."""
    n = 0
    while n < min(len(filename), len(suggestion)) and filename[-1 - n].lower() == suggestion[-1 - n].lower():
        n += 1
    return filename[: len(filename) - n] + suggestion[len(suggestion) - n :]


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
