"""GC202 and GC201 once per package: a package nobody knows, a package not built."""

from __future__ import annotations

from dataclasses import dataclass

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load.meshes import LoadedMesh, MeshProblem, MeshStore
from geomcheck.model import Link, Mesh, Shape
from geomcheck.rules import meshes as rules

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


def grouped_data(
    package: str, kind: str, links: list[str], references: list[dict[str, object]], **extra: object
) -> dict[str, object]:
    """The data of a finding about one package's references (GC202): what it concerns, how many."""
    return {
        "package": package,
        "kind": kind,
        "count": len(references),
        "links": links,
        **extra,
        "references": references,
    }


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
        data=grouped_data(
            package,
            "unresolved-package",
            names,
            [r.row(alternative=problems[id(r)].alternative) for r in references],
        ),
    )


def beside_package_diagnostic(
    store: MeshStore, package: str, references: list[Reference], known: str, advice: str
) -> Diagnostic:
    """GC202: an unknown package whose files sit in a folder of its name beside the root file,
    where PyBullet reads them (:meth:`geomcheck.load.meshes.MeshStore.folder_beside`): one
    finding per package; the meshes were read from there and every other check ran on them."""
    refs = _sorted(references)
    first = min(refs, key=lambda r: r.position)
    names, listed = _links_text(refs)
    folder = store.folder_beside(package)
    assert folder is not None
    shown = store.bundle.display(folder)
    n = len(refs)
    noun, verb = ("mesh reference", "was") if n == 1 else ("mesh references", "were")
    message = (
        f"package '{package}' is not known (known packages: {known}): its {n} {noun} on {len(names)} "
        f"link{'s' if len(names) != 1 else ''} ({listed}) {verb} read from the folder of that name beside the root "
        f"file ({shown}), as PyBullet reads package:// paths; ROS tools (RViz, Gazebo, MoveIt) cannot load them"
    )
    return rules.MESH_PACKAGE_UNRESOLVED.diagnose(
        message,
        help=(
            f"Make {shown} a package (a package.xml with <name>{package}</name>) and {advice}, or write the "
            "filenames relative to the root file (PyBullet and ROS read both)."
        ),
        about=f"package:{package}",
        location=first.shape.location,
        data=grouped_data(
            package, "package-beside-root", names, [r.row() for r in refs], folder=shown, accepted_by=["pybullet"]
        ),
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
