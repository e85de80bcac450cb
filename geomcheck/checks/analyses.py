"""The analyses one check run shares between its rule families: named, typed products, each
computed lazily, once, when a selected rule first needs it.

    model ──► kinematics ──► default_configuration ◄── srdf
      │            │                  │
      ▼            ▼                  ▼
    meshes ──► collision_scene ──► not_pairs ──► adjacency
      │            │                  │
      │            └──────────────────┴─────► matrix
      ├──► mesh_stats ──► fits
      └──────────────────────────────────────► (inertia, views read meshes)

``model`` is the loaded description (``ctx.robot``): always there, reading no mesh file.
``meshes`` is the run's :class:`geomcheck.load.MeshStore`: a file is read, and trimesh
imported, only when some product asks for one of its meshes. :data:`DEPENDENCIES` declares
the graph, :data:`FAMILY_NEEDS` what each rule family reads; a family never reads another's
findings, only these products. Nothing heavy is imported here: each product imports what it
needs when it is computed, so a run of the structure rules alone imports neither trimesh nor
a collision backend and reads no mesh.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np

    from geomcheck.collision import CollisionScene
    from geomcheck.geometry.elements import CollisionElement, VisualCloud
    from geomcheck.geometry.fit import LinkFit
    from geomcheck.geometry.orientation import Winding
    from geomcheck.geometry.surface import Solid
    from geomcheck.kinematics import Kinematics
    from geomcheck.load import LoadedDescription, MeshStore
    from geomcheck.load.meshes import MeshProblem
    from geomcheck.load.srdf import Srdf
    from geomcheck.model import Geometry, Mesh, Vec3
    from geomcheck.options import CheckOptions
    from geomcheck.selfcollision.matrix import CollisionMatrix

# product -> the products it is computed from
DEPENDENCIES: dict[str, tuple[str, ...]] = {
    "model": (),
    "meshes": ("model",),
    "mesh_stats": ("meshes",),
    "windings": ("meshes",),
    "fits": ("model", "mesh_stats", "meshes"),
    "kinematics": ("model",),
    "srdf": (),
    "default_configuration": ("kinematics", "srdf"),
    "collision_scene": ("model", "meshes"),
    "not_pairs": ("collision_scene",),
    "adjacency": ("collision_scene", "not_pairs"),
    "matrix": ("kinematics", "default_configuration", "collision_scene"),
}
# rule family -> the products it reads (see geomcheck.checks.FAMILY_MODULES)
FAMILY_NEEDS: dict[str, tuple[str, ...]] = {
    "structure": ("model",),
    "meshes": ("mesh_stats", "windings", "kinematics"),
    "fit": ("fits",),
    "inertia": ("meshes", "kinematics"),
    "selfcollision": ("kinematics", "collision_scene", "default_configuration", "adjacency", "srdf"),
    "motion": ("fits",),
    "matrix": ("matrix", "srdf", "adjacency"),
    "views": ("fits", "meshes"),
    "scene": ("kinematics", "default_configuration", "meshes"),
}


def closure(names: tuple[str, ...] | list[str] | set[str]) -> set[str]:
    """``names`` and every product they are computed from."""
    out: set[str] = set()
    todo = list(names)
    while todo:
        name = todo.pop()
        if name not in out:
            out.add(name)
            todo.extend(DEPENDENCIES[name])
    return out


def reads_meshes(families: tuple[str, ...] | list[str]) -> bool:
    """Whether running ``families`` may read mesh files."""
    return "meshes" in closure([need for family in families for need in FAMILY_NEEDS[family]])


MeshKey = tuple[str, "Vec3"]  # (filename as written, scale)


@dataclass(frozen=True)
class MeshStats:
    """A loaded mesh in its own frame, ``scale`` applied: ``extents`` (3,) [m], ``area``
    [m^2], convex ``hull_volume`` [m^3] (0 when flat), whether every vertex is ``finite``, and
    ``offset``: how far the centre of its bounding box lies from the file's origin [m]."""

    extents: tuple[float, float, float]
    area: float
    hull_volume: float
    finite: bool
    flat: bool
    offset: float = 0.0

    @property
    def size(self) -> float:
        """Largest extent [m]."""
        return max(self.extents)


@dataclass
class FitTables:
    """The fit family's products, filled link by link as it fits them (all in link frames):
    ``links`` each fitted link's :class:`LinkFit`; ``visuals`` a link's visual geometry as a
    cloud, the reason it is unavailable, or ``None`` without visuals; ``elements`` a link's
    collision elements or a reason; ``primitive_solids`` visual primitives tessellated once
    per geometry. The ``*_alike`` tables share results between links drawn alike."""

    links: dict[str, LinkFit] = field(default_factory=dict)
    links_alike: dict[tuple[Any, ...], LinkFit] = field(default_factory=dict)
    visuals: dict[str, VisualCloud | str | None] = field(default_factory=dict)
    visuals_alike: dict[tuple[Any, ...], VisualCloud | str | None] = field(default_factory=dict)
    elements: dict[str, list[CollisionElement] | str] = field(default_factory=dict)
    primitive_solids: dict[Geometry, Solid] = field(default_factory=dict)


class Analyses:
    """The products of one run (see the module's graph), computed on first use."""

    def __init__(self, loaded: LoadedDescription, meshes: MeshStore, options: CheckOptions) -> None:
        self.loaded = loaded
        self.meshes = meshes
        self.options = options
        self._scenes: dict[str, CollisionScene] = {}
        self._visual_scenes: dict[tuple[str, ...], CollisionScene] = {}

    # ------------------------------------------------------------------ meshes
    @cached_property
    def mesh_stats(self) -> dict[MeshKey, MeshStats | MeshProblem]:
        """Per mesh file and scale, its statistics or why it is unavailable; filled as the
        meshes family asks (:func:`geomcheck.checks.meshes.mesh_stats`)."""
        return {}

    @cached_property
    def windings(self) -> dict[tuple[str, Any], Winding]:
        """Per mesh file and scale, how its faces are wound; filled as the meshes family asks
        (:func:`geomcheck.checks.meshes.soundness.winding_diagnostic`)."""
        return {}

    @cached_property
    def fits(self) -> FitTables:
        """The fit family's tables (:class:`FitTables`), filled as it fits links; with a
        cache store active, the fits of links drawn alike are also read from and written to
        it (:class:`geomcheck.geometry.fit_cache.StoredFits`)."""
        from geomcheck.cache import active_store
        from geomcheck.cache.keys import canonical

        store = active_store()
        if store is None:
            return FitTables()
        try:
            settings = canonical(self.options.thresholds)
        except TypeError:  # thresholds no key can hold: fits kept in memory only
            return FitTables()
        from geomcheck.geometry.fit_cache import StoredFits

        return FitTables(links_alike=StoredFits(store, self.mesh_digest, settings))

    def mesh_digest(self, mesh: Mesh) -> str | None:
        """The sha256 of a ``<mesh>``'s file, ``None`` when it did not load."""
        from geomcheck.load.meshes import LoadedMesh

        loaded = self.meshes.get(mesh)
        return loaded.sha256 if isinstance(loaded, LoadedMesh) and loaded.sha256 else None

    # ------------------------------------------------------------------ self-collision
    @cached_property
    def kinematics(self) -> Kinematics:
        """Forward kinematics of the model."""
        from geomcheck.kinematics import Kinematics

        return Kinematics(self.loaded.robot)

    @cached_property
    def srdf(self) -> Srdf | None:
        """The SRDF given with ``--srdf``; without one, the pairs the description itself
        disables (MJCF ``<exclude>``) or ``None``. Raises
        :class:`geomcheck.errors.InputError` when it cannot be read."""
        from geomcheck.load.srdf import read_srdf

        path = self.options.srdf
        if path is None:
            return self.loaded.declared_collision_filter  # MJCF <exclude> pairs; None for URDF
        return read_srdf(
            path,
            self.loaded.bundle.display(path.absolute()),
            self.options.thresholds.limits,
            bundle=self.loaded.bundle,  # a .srdf.xacro expands with the description's packages and sandbox
            args=self.options.args,
        )

    @cached_property
    def default_configuration(self) -> np.ndarray:
        """The default pose (n_joints,): 0 or mid-range, then the SRDF ``group_state`` named by
        ``options.pose_name`` (its one-DOF joints that are variables of the robot), then
        ``options.pose``. :class:`geomcheck.errors.UsageError` for an unknown pose or joint
        name, or a pose name without ``--srdf``. Callers copy it before changing it."""
        from geomcheck.errors import UsageError

        options = self.options
        kin = self.kinematics
        values: dict[str, float] = {}
        if options.pose_name is not None:
            document = self.srdf
            if document is None:
                raise UsageError(f"--pose-name {options.pose_name!r} needs an SRDF: give it with --srdf FILE")
            variables = {j.name for j in kin.joints}
            named = document.group_state(options.pose_name).single_values()
            values.update({k: v for k, v in named.items() if k in variables})
        values.update(options.pose)
        return kin.default_configuration(values)

    def collision_scene(self, backend: str | None = None) -> CollisionScene:
        """The collision scene for ``backend`` (default: the one the options name)."""
        from geomcheck.collision import CollisionScene, get_backend

        name = backend or self.options.backend
        if name not in self._scenes:
            self._scenes[name] = CollisionScene(self.loaded.robot, self.meshes, get_backend(name))
        return self._scenes[name]

    def visual_scene(self, links: tuple[str, ...]) -> CollisionScene:
        """A scene of the visual geometry of ``links`` (the parts as drawn: a mesh's triangles),
        in place of their collision geometry, for the run's backend; built once per set of links,
        and only for the few a finding asks about (a robot's every visual mesh is not needed)."""
        from dataclasses import replace

        from geomcheck.collision import CollisionScene, get_backend

        key = tuple(sorted(links))
        if key not in self._visual_scenes:
            robot = self.loaded.robot
            drawn = tuple(replace(link, collisions=link.visuals if link.name in links else ()) for link in robot.links)
            self._visual_scenes[key] = CollisionScene(
                replace(robot, links=drawn), self.meshes, get_backend(self.options.backend)
            )
        return self._visual_scenes[key]

    @cached_property
    def not_pairs(self) -> set[tuple[str, str]]:
        """Link pairs (sorted tuples) that the run's semantics does not check: under
        ``pinocchio``, links that only fixed joints join."""
        from geomcheck.collision import excluded_pairs

        return excluded_pairs(self.loaded.robot, self.collision_scene().links, self.options.semantics)

    @cached_property
    def adjacency(self) -> set[tuple[str, str]]:
        """MoveIt's Adjacent pairs among the links with usable collision geometry (sorted
        tuples), less those that are no pair under the run's semantics."""
        from geomcheck.collision import adjacent_pairs

        return adjacent_pairs(self.loaded.robot, self.collision_scene().links) - self.not_pairs

    @cached_property
    def matrix(self) -> CollisionMatrix:
        """The collision matrix (from the result cache when it holds it: the collision scene
        is then not even built), with a progress bar when asked."""
        from geomcheck.progress import Progress
        from geomcheck.selfcollision.compute import MatrixSettings, compute_matrix
        from geomcheck.selfcollision.matrix_cache import cached_matrix, matrix_key

        options = self.options
        settings = MatrixSettings.from_options(options)
        kin, q0 = self.kinematics, self.default_configuration.copy()

        def compute() -> CollisionMatrix:
            scene = self.collision_scene()
            with Progress(settings.samples, "matrix", unit="sample") as bar:
                return compute_matrix(kin, scene, q0, settings, progress=bar.advance)

        content = matrix_key(self.loaded.robot, self.meshes, q0, settings, options.backend, options.thresholds.limits)
        return cached_matrix(content, compute)

    # ------------------------------------------------------------------ bookkeeping
    def computed(self) -> set[str]:
        """The products computed so far (``model`` always; ``meshes`` once a file was read)."""
        lazy = {name for name in DEPENDENCIES if isinstance(getattr(type(self), name, None), cached_property)}
        names = {"model"} | {name for name in lazy if name in self.__dict__}
        if self._scenes:
            names.add("collision_scene")
        if self.meshes.files_read:
            names.add("meshes")
        return names


__all__ = ["DEPENDENCIES", "FAMILY_NEEDS", "Analyses", "FitTables", "MeshKey", "MeshStats", "closure", "reads_meshes"]
