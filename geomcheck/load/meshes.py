"""Mesh files: resolve URDF filenames through the bundle, load each file once, apply scale.

A loaded mesh is numpy arrays (:attr:`LoadedMesh.vertices`, :attr:`LoadedMesh.faces`);
its trimesh object is built, and trimesh (with scipy) imported, only when some code asks
for :attr:`LoadedMesh.mesh`. Binary STL is read with numpy, COLLADA with lxml and numpy
(:mod:`geomcheck.load.collada`), Wavefront OBJ with numpy (:mod:`geomcheck.load.obj`), both
trimesh's arrays bit for bit, and every file's triangles come from the cache when a store is
active, so a warm run reads meshes without trimesh, and a cold run of a robot with STL,
COLLADA and OBJ meshes too.
"""

from __future__ import annotations

import dataclasses
import functools
import glob
import hashlib
import io
import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar
from urllib.parse import unquote

import numpy as np

from geomcheck.cache import cached_arrays
from geomcheck.errors import GeomcheckError
from geomcheck.load.bundle import Bundle
from geomcheck.load.collada import read_collada
from geomcheck.load.mesh_units import METRE, collada_unit
from geomcheck.load.msh import read_msh
from geomcheck.load.obj import read_obj
from geomcheck.load.regular import read_regular_file
from geomcheck.load.stl import read_binary_stl
from geomcheck.model import Mesh, Vec3
from geomcheck.thresholds import LoadLimits

if TYPE_CHECKING:  # trimesh (with scipy) is imported on first use: a CLI that fails early starts fast
    import trimesh

T = TypeVar("T")

MAX_INDEXED_FILES = 50_000  # files looked at per package when searching a missing mesh by name
# what parse_mesh makes of a file's bytes, in the mesh-load cache key: raise it whenever that changes
# (2: a COLLADA file's declared <unit meter> applied; 3: MuJoCo's .msh read)
MESH_READER_VERSION = 3

MESH_FORMATS = {
    ".stl": "stl",
    ".stlb": "stl",  # binary STL under the extension rosbuild-era packages generated (and ROS's loaders read)
    ".obj": "obj",
    ".dae": "dae",
    ".ply": "ply",
    ".glb": "glb",
    ".gltf": "gltf",
    ".off": "off",
}

# MuJoCo's own legacy binary format (geomcheck.load.msh): only MuJoCo reads it, so only an
# MJCF description's meshes may be written in it
MUJOCO_MESH_FORMATS = {".msh": "msh"}


def mesh_formats(description_format: str) -> Mapping[str, str]:
    """The mesh file extensions (and the format each names) that the tools of a description in
    ``description_format`` (``urdf``, ``mjcf``, ``sdf``, ...) read."""
    return {**MESH_FORMATS, **MUJOCO_MESH_FORMATS} if description_format == "mjcf" else MESH_FORMATS


ProblemKind = Literal["unresolved-package", "missing-file", "unreadable", "empty", "unsupported-format", "out-of-range"]


@dataclass(frozen=True)
class LoadedMesh:
    """A mesh in its own frame with the URDF ``scale`` applied: ``vertices`` (n, 3) [m],
    ``faces`` (m, 3) indices into them."""

    filename: str  # as written in the URDF
    path: str  # display path of the file
    vertices: np.ndarray = field(compare=False, repr=False)
    faces: np.ndarray = field(compare=False, repr=False)
    distinct: bool = False  # every vertex is used by a face and no two are equal (welded on reading)
    sha256: str = ""  # of the file's bytes: with the scale, what the mesh's analyses depend on
    unit: float = METRE  # metres per file unit the file declares (COLLADA <unit meter>), applied to the vertices
    # display path of the missing build product this mesh (its source) stands in for, when the
    # file named is one a package's build generates (see generated_source)
    stands_for: str | None = None

    @functools.cached_property
    def mesh(self) -> trimesh.Trimesh:
        """The same triangles as a trimesh object (built on first use; imports trimesh)."""
        import trimesh

        return trimesh.Trimesh(vertices=self.vertices, faces=self.faces, process=False)


@dataclass(frozen=True)
class MeshProblem:
    """Why a mesh could not be used. ``suggestion`` is a display path that exists and
    differs only by letter case, when there is one."""

    filename: str
    kind: ProblemKind
    message: str
    path: str | None = None
    suggestion: str | None = None
    alternative: str | None = None  # package:// URI of a file of the same name elsewhere in the bundle
    generated_from: str | None = None  # display path of the mesh a package build makes this missing file from


MeshResult = LoadedMesh | MeshProblem


def _case_insensitive_match(path: Path) -> Path | None:
    """An existing path that equals ``path`` but for letter case, or ``None``."""
    parts = path.parts
    current = Path(parts[0])
    for part in parts[1:]:
        if (current / part).exists():
            current = current / part
            continue
        if not current.is_dir():
            return None
        candidates = [c for c in current.iterdir() if c.name.lower() == part.lower()]
        if not candidates:
            return None
        current = sorted(candidates)[0]
    return current if current != path else None


def generated_source(path: Path) -> Path | None:
    """The mesh a package's build makes ``path`` from, when ``path`` is one of the convex
    decompositions that rosbuild-era packages generated at build time
    (``meshes/X/convex/NAME_convex.stlb`` from ``meshes/X/NAME.stl``, with the
    ``convex_decomposition`` and ``ivcon`` tools) and that source exists; else ``None``."""
    if path.parent.name != "convex" or not path.stem.endswith("_convex") or len(path.stem) == len("_convex"):
        return None
    stem = path.stem[: -len("_convex")]
    for candidate in sorted(path.parent.parent.glob(f"{glob.escape(stem)}.*")):
        if candidate.suffix.lower() == ".stl" and candidate.is_file():
            return candidate
    return None


def geometry_only(loaded: object) -> trimesh.Trimesh | None:
    """The triangles of what trimesh loaded as one mesh in the file's frame, without visuals.

    Scenes (DAE, multi-object OBJ) are flattened with their node transforms. Visuals
    (textures, materials) are dropped: the checks need geometry only, and copying textured
    visuals needs Pillow.
    """
    import trimesh

    if isinstance(loaded, trimesh.Trimesh):
        return trimesh.Trimesh(vertices=loaded.vertices, faces=loaded.faces, process=False)
    if not isinstance(loaded, trimesh.Scene):
        return None
    parts = []
    for node in loaded.graph.nodes_geometry:
        transform, name = loaded.graph[node]
        geometry = loaded.geometry.get(name)
        if isinstance(geometry, trimesh.Trimesh) and len(geometry.faces):
            vertices = trimesh.transformations.transform_points(geometry.vertices, transform)
            parts.append(trimesh.Trimesh(vertices=vertices, faces=geometry.faces, process=False))
    if not parts:
        return None
    if len(parts) == 1:
        return parts[0]
    merged = trimesh.util.concatenate(parts)
    return merged if isinstance(merged, trimesh.Trimesh) else None


def read_with_trimesh(data: bytes, fmt: str) -> tuple[np.ndarray, np.ndarray] | None:
    """The triangles trimesh reads from a mesh file's bytes, flattened by :func:`geometry_only`:
    vertices (n, 3) and faces (m, 3) as trimesh holds them, ``None`` when the file holds no
    geometry. Imports trimesh."""
    import trimesh

    loaded = geometry_only(
        trimesh.load(io.BytesIO(data), file_type=fmt, process=False, resolver=None, skip_materials=True)
    )
    return None if loaded is None else (loaded.vertices, loaded.faces)


def parse_mesh(data: bytes, fmt: str) -> dict[str, np.ndarray]:
    """The triangles of a mesh file's bytes as ``vertices`` (n, 3) [m, the file's declared
    unit applied], ``faces`` (m, 3), ``distinct`` (whether the vertices were welded: all used,
    none repeated) and ``unit`` (metres per file unit the file declares: a COLLADA
    ``<unit meter>``, applied as RViz and Gazebo apply it; 1 for formats without units, see
    :mod:`geomcheck.load.mesh_units`); no faces when the file holds no geometry. Binary STL is
    read with numpy, COLLADA and OBJ with lxml and numpy (:mod:`geomcheck.load.collada`,
    :mod:`geomcheck.load.obj`: the same arrays as trimesh's; a file they do not reproduce is
    left to trimesh), the other formats through trimesh (imported only then)."""
    arrays = read_binary_stl(data) if fmt == "stl" else None
    if arrays is not None:
        return {"vertices": arrays[0], "faces": arrays[1], "distinct": np.array(True), "unit": np.array(METRE)}
    # read before trimesh: pycollada keeps the unit as metadata and never applies it
    unit = collada_unit(data) if fmt == "dae" else METRE
    if fmt == "msh":  # MuJoCo's own format: no other reader knows it
        read = read_msh(data)
        if read is None:
            raise ValueError("not a well-formed .msh file (its size does not match its counts)")
    else:
        read = read_collada(data) if fmt == "dae" else read_obj(data) if fmt == "obj" else None
    if read is None:
        read = read_with_trimesh(data, fmt)
    if read is None:
        return {
            "vertices": np.zeros((0, 3)),
            "faces": np.zeros((0, 3), dtype=np.int64),
            "distinct": np.array(False),
            "unit": np.array(unit),
        }
    vertices, faces = np.asarray(read[0], dtype=float), np.asarray(read[1], dtype=np.int64)
    # what a lenient reader makes of a malformed file is refused here, not deep in the geometry
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise ValueError(f"vertices of {vertices.shape[-1] if vertices.ndim == 2 else vertices.ndim} coordinates")
    if faces.size and (faces.ndim != 2 or faces.shape[1] != 3 or faces.min() < 0 or faces.max() >= len(vertices)):
        raise ValueError("faces that are not triangles of its vertices")
    if unit != METRE:
        vertices = vertices * unit
    return {"vertices": vertices, "faces": faces, "distinct": np.array(False), "unit": np.array(unit)}


Triangles = tuple[np.ndarray, np.ndarray]  # vertices (n, 3) float64, faces (m, 3) int64


def triangles(vertices: np.ndarray, faces: np.ndarray) -> Triangles:
    """``vertices`` as float64 and ``faces`` as int64 C-contiguous arrays: what trimesh holds
    of them (``process=False``). Loaded meshes are shared: nobody writes into them."""
    return np.ascontiguousarray(vertices, dtype=np.float64), np.ascontiguousarray(faces, dtype=np.int64)


def finite_reach(vertices: np.ndarray) -> float:
    """The largest magnitude of the finite coordinates of ``vertices`` (0 when there are none);
    non-finite ones are GC207 findings of their own."""
    finite = vertices[np.isfinite(vertices)]
    return float(np.abs(finite).max()) if finite.size else 0.0


class MeshStore:
    """Resolves and loads meshes of one bundle; every file is read at most once."""

    def __init__(
        self, bundle: Bundle, limits: LoadLimits | None = None, formats: Mapping[str, str] = MESH_FORMATS
    ) -> None:
        self.bundle = bundle
        self.limits = limits or LoadLimits()
        self.formats = formats  # extension -> format: what the description's own tools read (mesh_formats)
        self._files: dict[Path, Triangles | MeshProblem] = {}
        self._scaled: dict[tuple[str, Vec3], MeshResult] = {}
        self._derived: dict[tuple[str, Vec3, str], Any] = {}
        self._distinct: set[Path] = set()  # files whose vertices were welded on reading
        self._digests: dict[Path, str] = {}  # sha256 of each file read
        self._units: dict[Path, float] = {}  # metres per file unit each file read declares
        self._reach: dict[Path, float] = {}  # largest finite coordinate magnitude of each file read [file units]
        self._reading: tuple[str, int] | None = None  # display path and bytes of the file being read
        self._largest: tuple[str, int, int] | None = None  # display path, triangles and bytes of the largest mesh
        self.files_read = 0
        self._by_name: dict[str, list[str]] | None = None
        self._beside_root: dict[str, list[str]] | None = None  # mesh files under the root file's folder

    def same_name_elsewhere(self, filename: str) -> str | None:
        """Where a missing mesh ``filename`` most likely lives now: a mesh file of the same file
        name (letter case aside) in a known package, as a ``package://`` URI, or, for a filename
        relative to the root file or absolute, under the root file's folder, relative to it (a
        package that moved its meshes from ``meshes/`` to ``assets/`` and kept the old references;
        ``/meshes/x.stl``, whose leading slash makes it a path from the machine's root). The first
        in sorted order when several match; a relative reference prefers a relative match."""
        if self._by_name is None:
            index: dict[str, list[str]] = {}
            for package, directory in sorted(self.bundle.packages.items()):
                self._index(directory, f"package://{package}/", index)
            self._by_name = index
        name = filename.strip()
        base = unquote(name.rsplit("/", 1)[-1]).lower()
        if "://" not in name:  # relative, or absolute where a leading slash was one too many
            if self._beside_root is None:
                root = self.bundle.root_file.parent
                self._beside_root = {}
                if self._accessible(root):
                    self._index(root, "", self._beside_root)
            beside = [path for path in self._beside_root.get(base, []) if path != name]
            if beside:
                return beside[0]
        matches = [uri for uri in self._by_name.get(base, []) if uri != name]
        return matches[0] if matches else None

    def _index(self, directory: Path, prefix: str, index: dict[str, list[str]]) -> None:
        """Add the mesh files under ``directory`` (at most ``MAX_INDEXED_FILES`` looked at) to
        ``index``, by lower-case file name, each as ``prefix`` and its path relative to ``directory``."""
        for count, path in enumerate(sorted(directory.rglob("*"))):
            if count >= MAX_INDEXED_FILES:
                break
            if path.suffix.lower() in self.formats and path.is_file():
                index.setdefault(path.name.lower(), []).append(prefix + path.relative_to(directory).as_posix())

    def _with_alternative(self, problem: MeshProblem) -> MeshProblem:
        if problem.kind not in ("missing-file", "unresolved-package") or problem.suggestion or problem.generated_from:
            return problem
        alternative = self.same_name_elsewhere(problem.filename)
        if alternative is None:
            return problem
        return dataclasses.replace(
            problem, alternative=alternative, message=f"{problem.message}; a file of that name exists at {alternative}"
        )

    def resolve(self, filename: str) -> Path | MeshProblem:
        """Absolute path of a URDF mesh ``filename`` (package://, file://, absolute, or relative to the root file)."""
        name = filename.strip()
        if name.startswith("package://"):
            rest = name[len("package://") :]
            if rest.startswith("/") and rest.lstrip("/"):
                # package:///name/...: ROS's resource_retriever reads an empty package name and fails;
                # pinocchio drops the slashes and resolves the package: geomcheck does as pinocchio
                rest = rest.lstrip("/")
            package, _, relative = rest.partition("/")
            # a package given or found by its manifest, else its folder beside the root file (where
            # PyBullet reads it: GC202), else a folder of its name under a search root or above
            given = self.bundle.packages.get(package)
            directory = given or self.folder_beside(package) or self.bundle.package_dir(package)
            if directory is None:
                known = ", ".join(self.bundle.packages) or "none"
                return MeshProblem(
                    filename, "unresolved-package", f"package '{package}' is not known (known packages: {known})"
                )
            path = directory / unquote(relative)
        elif name.startswith("file://"):
            path = Path(unquote(name[len("file://") :]))
        else:
            path = Path(name)
            if not path.is_absolute():
                path = self.bundle.root_file.parent / path
        return path

    def folder_beside(self, package: str) -> Path | None:
        """The folder named ``package`` beside the root file, where PyBullet reads an unknown
        package's files (it drops ``package://`` and reads the rest from the root file's
        folder: ``xarm/xarm_description/meshes`` for ``package://xarm_description/meshes``);
        ``None`` when the package is given or found by its manifest, has no such folder or the
        folder is outside the sandbox. It comes before a folder of the package's name anywhere
        under a search root (a package named ``meshes`` is the one beside the file, not the
        first ``meshes`` folder of the workspace). ROS tools do not read it: GC202 says so, and
        the meshes are checked."""
        if not package or package in (".", "..") or package in self.bundle.packages:
            return None
        folder = self.bundle.root_file.parent / package
        return folder if folder.is_dir() and self._accessible(folder) else None

    @staticmethod
    def accepted_quirk(filename: str) -> str | None:
        """Why ``filename`` is resolved although ROS tools would not resolve it, naming the tools
        that accept it, or ``None`` for a filename every tool reads alike."""
        name = filename.strip()
        if name.startswith("package:///") and name[len("package://") :].lstrip("/"):
            package = name[len("package://") :].lstrip("/").partition("/")[0]
            return (
                f"'{filename}' has three slashes after package:, which ROS's resource_retriever (RViz, Gazebo, "
                f"MoveIt) reads as the empty package name and rejects; pinocchio accepts it as package "
                f"'{package}', and geomcheck analyses it as pinocchio does"
            )
        return None

    def _accessible(self, path: Path) -> bool:
        """Whether ``path`` is inside the bundle's sandbox (always, when it is not confined)."""
        try:
            self.bundle.check_access(path)
        except GeomcheckError:
            return False
        return True

    def _missing(self, path: Path, filename: str, display: str) -> MeshProblem:
        """The problem of a mesh ``filename`` whose file ``path`` does not exist, with what stands for
        it where something does: the file in other letter case, or the source a build makes it of."""
        match = _case_insensitive_match(path)
        suggestion = self.bundle.display(match) if match else None
        if suggestion:
            message = f"mesh file not found: {display}; did you mean {suggestion}?"
            return MeshProblem(filename, "missing-file", message, display, suggestion)
        source = generated_source(path)
        if source is not None and self._accessible(source):
            origin = self.bundle.display(source)
            message = f"mesh file not found: {display}, a build product: the convex decomposition of {origin}"
            return MeshProblem(filename, "missing-file", message, display, generated_from=origin)
        if Path(filename.strip()).is_absolute():  # its display path would climb out of the project
            display = filename.strip()
            return MeshProblem(filename, "missing-file", f"mesh file not found: {display} (an absolute path)", display)
        return MeshProblem(filename, "missing-file", f"mesh file not found: {display}", display)

    def _read(self, path: Path, filename: str) -> Triangles | MeshProblem:
        requested = path  # what get() knows the file by, before links are resolved
        display = self.bundle.display(path)
        try:
            path = self.bundle.check_access(path)
        except GeomcheckError as err:
            return MeshProblem(filename, "unreadable", str(err), display)
        if not path.is_file():
            return self._missing(path, filename, display)
        fmt = self.formats.get(path.suffix.lower())
        if fmt is None:
            return MeshProblem(
                filename, "unsupported-format", f"unsupported mesh format '{path.suffix}': {display}", display
            )
        size = path.stat().st_size
        if size > self.limits.max_mesh_bytes:
            return MeshProblem(
                filename,
                "unreadable",
                f"mesh file of {size} bytes exceeds the limit of {self.limits.max_mesh_bytes}",
                display,
            )
        self.files_read += 1
        self._reading = (display, size)
        try:
            data = read_regular_file(path, display, self.limits.max_mesh_bytes, "max_mesh_bytes")
            digest = hashlib.sha256(data).hexdigest()
            key = {"sha256": digest, "format": fmt, "reader": MESH_READER_VERSION}
            arrays = cached_arrays("mesh-load", key, lambda: parse_mesh(data, fmt))
            loaded = triangles(arrays["vertices"], arrays["faces"])
            self._digests[requested] = digest
            self._units[requested] = float(arrays["unit"])
            if bool(arrays["distinct"]):
                self._distinct.add(requested)
        except MemoryError:
            # a resource limit, not a defect of the file: the run stops and says where
            raise MemoryError(f"while reading the mesh {display} ({size / 1e6:.1f} MB)") from None
        except Exception as err:  # trimesh raises many kinds on corrupt files
            self._reading = None
            first = self.bundle.scrub(str(err).splitlines()[0]) if str(err) else type(err).__name__
            return MeshProblem(filename, "unreadable", f"cannot read mesh {display}: {first}", display)
        self._reading = None
        vertices, faces = loaded
        if len(faces) == 0:
            return MeshProblem(filename, "empty", f"mesh {display} has no triangles", display)
        self._reach[requested] = finite_reach(vertices)
        if self._largest is None or len(faces) > self._largest[1]:
            self._largest = (display, len(faces), size)
        return loaded

    def memory_hint(self) -> str | None:
        """Which mesh a run out of memory was most likely busy with: the file being read, else
        the largest mesh loaded, with its size; ``None`` before any mesh was read."""
        if self._reading is not None:
            path, size = self._reading
            return f"while reading the mesh {path} ({size / 1e6:.1f} MB)"
        if self._largest is not None:
            path, triangles, size = self._largest
            return f"the largest mesh is {path}: {triangles:,} triangles, {size / 1e6:.1f} MB"
        return None

    def get(self, mesh: Mesh) -> MeshResult:
        """The mesh of a ``<mesh>`` element, scaled, or the problem that prevents it."""
        key = (mesh.filename, mesh.scale)
        if key in self._scaled:
            return self._scaled[key]
        resolved = self.resolve(mesh.filename)
        result: MeshResult
        if isinstance(resolved, MeshProblem):
            result = self._with_alternative(resolved)
        else:
            absolute = resolved.absolute()
            if absolute not in self._files:
                self._files[absolute] = self._read(absolute, mesh.filename)
            base = self._files[absolute]
            stands_for = None
            if isinstance(base, MeshProblem) and base.generated_from is not None:
                # a build product of a package that is not built: analysed as its source, which the
                # build turns into it (a convex decomposition covers the same part)
                source = generated_source(absolute)
                if source is not None:
                    source = source.absolute()
                    if source not in self._files:
                        self._files[source] = self._read(source, mesh.filename)
                    if not isinstance(self._files[source], MeshProblem):
                        stands_for, absolute, base = base.path, source, self._files[source]
            if isinstance(base, MeshProblem):
                result = self._with_alternative(dataclasses.replace(base, filename=mesh.filename))
            elif (reach := self._reach.get(absolute, 0.0) * max(abs(f) for f in mesh.scale)) > self.limits.max_length_m:
                # geometry built from such numbers is not finite (squares, products, hulls overflow)
                message = (
                    f"mesh {self.bundle.display(absolute)} has vertex coordinates of {reach:.3g} m (scale applied), "
                    f"beyond the {self.limits.max_length_m:g} m any robot geometry may reach"
                )
                result = MeshProblem(mesh.filename, "out-of-range", message, self.bundle.display(absolute))
            else:
                # meshes are shared read-only: an unscaled reference is the file's own arrays
                vertices, faces = base
                if mesh.scale != (1.0, 1.0, 1.0):
                    factors = np.asarray(mesh.scale, dtype=float)
                    # a mirroring scale turns the winding inside out: flip it back, as trimesh does
                    faces = faces[:, ::-1] if np.prod(factors) < 0 else faces
                    with np.errstate(invalid="ignore"):  # infinite coordinates times a zero scale: NaN, GC207
                        vertices, faces = triangles(vertices * factors, faces)
                # a scale keeps welded vertices distinct unless it flattens the mesh
                distinct = absolute in self._distinct and all(f != 0.0 for f in mesh.scale)
                digest = self._digests.get(absolute, "")
                display = self.bundle.display(absolute)
                unit = self._units.get(absolute, METRE)
                result = LoadedMesh(mesh.filename, display, vertices, faces, distinct, digest, unit, stands_for)
        self._scaled[key] = result
        return result

    def derived(self, mesh: Mesh, name: str, compute: Callable[[LoadedMesh], T]) -> T | MeshProblem:
        """What ``compute`` makes of the mesh of a ``<mesh>`` element (scale applied), computed
        once per file, scale and ``name`` however many elements refer to it; or the problem
        that prevents loading it."""
        loaded = self.get(mesh)
        if isinstance(loaded, MeshProblem):
            return loaded
        key = (mesh.filename, mesh.scale, name)
        if key not in self._derived:
            self._derived[key] = compute(loaded)
        value: T = self._derived[key]
        return value


logging.getLogger("trimesh").setLevel(logging.ERROR)
__all__ = ["LoadedMesh", "MeshProblem", "MeshResult", "MeshStore"]
