"""The collision objects of a robot: every usable ``<collision>`` shape of every link, built once.

Besides the engine objects, each link keeps a conservative *support* of its geometry in the
link frame: points plus a pad such that every point of the geometry lies within ``pad`` of
the points' convex hull. The maximum of any 1-Lipschitz convex function over the geometry
(distance from a point, from a line) is then at most its maximum over the points plus the
pad; bounding spheres and the sweep's speed bounds are computed from it with numpy.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from geomcheck.collision.base import SEPARATION_MARGIN, CollisionBackend, MeshArrays
from geomcheck.collision.support_cache import stored_support_points
from geomcheck.geometry.cover import hull_cover
from geomcheck.load.meshes import MeshProblem, MeshStore
from geomcheck.model import Box, Cylinder, Geometry, Mesh, Robot, Shape, Sphere

RIM_POINTS = 32  # points per cylinder rim circle in the support [count]

# The faces of the hull of a primitive's support points (:func:`_support`), as polygons of
# point indices: a box's corners are numbered 4 x + 2 y + z (0 for the negative side, 1 for the
# positive), a cylinder's rim points bottom circle first. Every support point is a vertex.
_BOX_FACES = ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5))
_RIM = range(RIM_POINTS)
_CYLINDER_FACES = (
    tuple(_RIM),
    tuple(i + RIM_POINTS for i in _RIM),
    *((i, (i + 1) % RIM_POINTS, (i + 1) % RIM_POINTS + RIM_POINTS, i + RIM_POINTS) for i in _RIM),
)
_SUPPORT_FACES: dict[type, tuple[tuple[int, ...], ...]] = {Box: _BOX_FACES, Cylinder: _CYLINDER_FACES}


@dataclass(frozen=True, eq=False)
class SceneShape:
    """One usable collision shape: its element, engine object and link-from-shape pose (4, 4)."""

    link: str
    shape: Shape
    obj: Any
    pose: np.ndarray
    points: np.ndarray  # (n, 3) support points in the link frame [m]
    pad: float  # [m]
    content: str = ""  # what the engine object is made of: a mesh file's sha256 and scale, or the primitive
    mesh: MeshArrays | None = None  # the triangles in the shape frame (``None`` for a primitive)
    at_origin: bool = field(init=False)  # the pose is the identity: placing the shape is free

    def __post_init__(self) -> None:
        object.__setattr__(self, "at_origin", bool(np.array_equal(self.pose, np.eye(4))))

    def world(self, frame: np.ndarray) -> np.ndarray:
        """World-from-shape (4, 4) for the world-from-link ``frame`` (4, 4)."""
        return frame if self.at_origin else frame @ self.pose

    @functools.cached_property
    def cover(self) -> tuple[tuple[np.ndarray, float], ...]:
        """Balls ``(centre (3,) in the link frame [m], radius [m])`` that together contain the
        whole shape; computed on first use and kept, like the engine object."""
        balls = hull_cover(np.asarray(self.points, dtype=float), _SUPPORT_FACES.get(type(self.shape.geometry)))
        return tuple((c, r + self.pad) for c, r in balls)


@dataclass(frozen=True)
class ShapePart:
    """Some of a mesh shape's triangles as an engine object (``obj``, in the shape's frame), for
    a query whose other object never comes near the rest: a distance to the part below
    ``exact_below`` [m] is the distance to the whole shape (the rest is at least that far)."""

    obj: Any
    exact_below: float  # [m]


@dataclass(frozen=True)
class UnusableShape:
    """A ``<collision>`` element left out of the scene, and why."""

    link: str
    shape: Shape
    reason: str


def _finite_positive(*values: float) -> bool:
    return all(np.isfinite(v) and v > 0 for v in values)


def _support(geometry: Box | Cylinder | Sphere | MeshArrays) -> tuple[np.ndarray, float]:
    """Support points (n, 3) and pad [m] of a geometry in its own frame."""
    if isinstance(geometry, Box):
        corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
        return corners * (np.asarray(geometry.size, dtype=float) / 2), 0.0
    if isinstance(geometry, Cylinder):
        t = np.linspace(0.0, 2 * np.pi, RIM_POINTS, endpoint=False)
        ring = np.stack([geometry.radius * np.cos(t), geometry.radius * np.sin(t), np.zeros_like(t)], axis=1)
        lift = np.array([0.0, 0.0, geometry.length / 2])
        points = np.concatenate([ring - lift, ring + lift])
        # the rim between two samples bulges at most one sagitta out of their chord
        return points, geometry.radius * float(1.0 - np.cos(np.pi / RIM_POINTS))
    if isinstance(geometry, Sphere):
        return np.zeros((1, 3)), float(geometry.radius)
    return stored_support_points(geometry), 0.0


class CollisionScene:
    """Collision objects of every link's ``<collision>`` elements, built once.

    ``links`` are the links with at least one usable collision shape, in document order;
    ``unusable`` lists the elements left out (mesh not loaded, non-positive size).
    """

    def __init__(self, robot: Robot, meshes: MeshStore, backend: CollisionBackend) -> None:
        self.robot = robot
        self.backend = backend
        self.unusable: list[UnusableShape] = []
        built: dict[Geometry, tuple[Any, np.ndarray, float, str, MeshArrays | None]] = {}
        by_link: dict[str, tuple[SceneShape, ...]] = {}
        for link in robot.links:
            if link.name in by_link:
                continue  # a duplicate link name: the first one wins, as in Robot.link_map
            usable = []
            for shape in link.collisions:
                entry = built.get(shape.geometry)
                if entry is None:
                    made = self._make(shape, meshes)
                    if isinstance(made, str):
                        self.unusable.append(UnusableShape(link.name, shape, made))
                        continue
                    entry = built[shape.geometry] = made
                obj, points, pad, content, arrays = entry
                pose = shape.origin.matrix()
                placed = points @ pose[:3, :3].T + pose[:3, 3]
                usable.append(SceneShape(link.name, shape, obj, pose, placed, pad, content, arrays))
            if usable:
                by_link[link.name] = tuple(usable)
        self._shapes = by_link
        self.links: tuple[str, ...] = tuple(by_link)
        self._spheres = {name: self._sphere(name) for name in self.links}

    def _make(self, shape: Shape, meshes: MeshStore) -> tuple[Any, np.ndarray, float, str, MeshArrays | None] | str:
        g = shape.geometry
        geometry: Box | Cylinder | Sphere | MeshArrays
        content = repr(g)
        if isinstance(g, Mesh):
            loaded = meshes.get(g)
            if isinstance(loaded, MeshProblem):
                return f"mesh not loaded: {loaded.message}"
            geometry = MeshArrays(loaded.vertices, loaded.faces)
            # unknown bytes (no digest): no content, so nothing keyed by it is cached
            content = f"mesh {loaded.sha256} scale {g.scale!r} for {loaded.stands_for}" if loaded.sha256 else ""
            if len(geometry.faces) == 0 or not np.all(np.isfinite(geometry.vertices)):
                return "mesh has no usable triangles"
        elif isinstance(g, Box):
            if not _finite_positive(*g.size):
                return f"box size {g.size} is not positive"
            geometry = g
        elif isinstance(g, Cylinder):
            if not _finite_positive(g.radius, g.length):
                return f"cylinder radius {g.radius} / length {g.length} is not positive"
            geometry = g
        else:
            if not _finite_positive(g.radius):
                return f"sphere radius {g.radius} is not positive"
            geometry = g
        points, pad = _support(geometry)
        arrays = geometry if isinstance(geometry, MeshArrays) else None
        return self.backend.make(geometry), points, pad, content, arrays

    def _sphere(self, link: str) -> tuple[np.ndarray, float]:
        shapes = self.scene_shapes(link)
        lo = np.min([s.points.min(axis=0) - s.pad for s in shapes], axis=0)
        hi = np.max([s.points.max(axis=0) + s.pad for s in shapes], axis=0)
        centre = (lo + hi) / 2
        return centre, float(max(np.linalg.norm(s.points - centre, axis=1).max() + s.pad for s in shapes))

    def build(self) -> None:
        """Build now what the engine objects build on first use (a mesh's BVH): forked workers
        then share it instead of each building its own."""
        for shapes in self._shapes.values():
            for s in shapes:
                build = getattr(s.obj, "build", None)
                if build is not None:
                    build()

    # ------------------------------------------------------------------ queries
    def scene_shapes(self, link: str) -> tuple[SceneShape, ...]:
        """The usable shapes of ``link`` (empty when it has none)."""
        return self._shapes.get(link, ())

    def shapes(self, link: str) -> list[tuple[Any, np.ndarray]]:
        """(engine object, link-from-shape (4, 4)) of every usable shape of ``link``."""
        return [(s.obj, s.pose) for s in self.scene_shapes(link)]

    def support(self, link: str) -> tuple[np.ndarray, float]:
        """Support points (n, 3) in the link frame [m] and pad [m] of all of ``link``'s shapes."""
        shapes = self.scene_shapes(link)
        if not shapes:
            return np.zeros((0, 3)), 0.0
        return np.concatenate([s.points for s in shapes]), max(s.pad for s in shapes)

    def bounding_sphere(self, link: str) -> tuple[np.ndarray, float]:
        """A sphere holding all of ``link``'s collision geometry: centre (3,) in the link frame, radius [m]."""
        return self._spheres[link]

    def closest(self, a: str, ta: np.ndarray, b: str, tb: np.ndarray) -> tuple[float, int, int]:
        """(distance [m], index of a's shape, index of b's shape) of the closest shape pair;
        ``ta``/``tb`` world-from-link (4, 4). Indices are positions in :meth:`scene_shapes`."""
        best = (np.inf, -1, -1)
        distance = self.backend.distance
        for i, sa in enumerate(self.scene_shapes(a)):
            wa = sa.world(ta)
            for j, sb in enumerate(self.scene_shapes(b)):
                d = distance(sa.obj, wa, sb.obj, sb.world(tb))
                if d < best[0]:
                    best = (d, i, j)
        return best

    def placements(self, link: str, frames: np.ndarray) -> list[list[Any]]:
        """Engine transforms of ``link``'s shapes for world-from-link ``frames`` (n, 4, 4): one list
        (a transform per shape) per frame, for the ``placed_`` queries of hot loops."""
        poses = np.stack([s.pose for s in self.scene_shapes(link)])
        world = frames[:, None] @ poses[None]  # (n, shapes, 4, 4)
        place = self.backend.placement
        return [[place(m) for m in row] for row in world]

    def placed_closest(
        self,
        a: str,
        pa: list[Any],
        b: str,
        pb: list[Any],
        lower: np.ndarray | None = None,
        parts: Sequence[ShapePart | None] | None = None,
        parts_a: Sequence[ShapePart | None] | None = None,
    ) -> tuple[float, int, int]:
        """:meth:`closest` with shape transforms from :meth:`placements`, the same result asked
        for less. ``lower`` (n_a, n_b): lower bounds [m] of each shape pair's distance
        (:meth:`placed_hull_distances`); pairs are then queried nearest bound first, and a pair
        whose bound exceeds the smallest distance found (by more than the engines' tolerance)
        is not queried. ``parts`` (``parts_a``): per shape of ``b`` (of ``a``), a part of it
        queried first (:class:`ShapePart`; ``None``: the whole shape); a distance between parts
        at or above the smaller of their ``exact_below`` is asked again of the whole shapes."""
        shapes_a, shapes_b = self.scene_shapes(a), self.scene_shapes(b)
        pairs = [(i, j) for i in range(len(shapes_a)) for j in range(len(shapes_b))]
        if lower is not None:
            pairs = [pairs[k] for k in np.argsort(lower.ravel(), kind="stable")]
        best: tuple[float, int, int] = (np.inf, -1, -1)
        distance = self.backend.placed_distance
        for i, j in pairs:
            if lower is not None and lower[i, j] > best[0] + SEPARATION_MARGIN:
                break  # sorted: every pair left is at least as far
            sa, sb = shapes_a[i], shapes_b[j]
            part_a = parts_a[i] if parts_a is not None else None
            part_b = parts[j] if parts is not None else None
            if part_a is None and part_b is None:
                d = distance(sa.obj, pa[i], sb.obj, pb[j])
            else:
                obj_a, obj_b = (part_a or sa).obj, (part_b or sb).obj
                d = distance(obj_a, pa[i], obj_b, pb[j])
                if d >= min(p.exact_below for p in (part_a, part_b) if p is not None):
                    d = distance(sa.obj, pa[i], sb.obj, pb[j])
            # the first pair (in shape order) of the smallest distance, as a scan in order finds
            if (d, i, j) < best:
                best = (d, i, j)
        return best

    def placed_hull_distances(self, a: str, pa: list[Any], b: str, pb: list[Any]) -> np.ndarray:
        """The convex hulls' distance [m] of every shape pair (n_a, n_b) (primitives are their
        own hull): lower bounds of the shapes' distances where those are positive."""
        hull_distance = self.backend.placed_hull_distance
        shapes_b = self.scene_shapes(b)
        return np.array(
            [
                [hull_distance(sa.obj, pa[i], sb.obj, pb[j]) for j, sb in enumerate(shapes_b)]
                for i, sa in enumerate(self.scene_shapes(a))
            ],
            dtype=float,
        ).reshape(len(self.scene_shapes(a)), len(shapes_b))

    def placed_distance_bound(self, a: str, pa: list[Any], b: str, pb: list[Any]) -> float:
        """:meth:`pair_distance_bound` with shape transforms from :meth:`placements`."""
        return float(self.placed_hull_distances(a, pa, b, pb).min(initial=np.inf))

    def pair_distance(self, a: str, ta: np.ndarray, b: str, tb: np.ndarray) -> float:
        """Smallest distance [m] between the shapes of two links (see the backend conventions)."""
        return self.closest(a, ta, b, tb)[0]

    def pair_distance_bound(self, a: str, ta: np.ndarray, b: str, tb: np.ndarray) -> float:
        """A lower bound of :meth:`pair_distance` when that is positive, from the convex hulls of
        meshes (exact for primitives and convex meshes; much cheaper than mesh queries)."""
        best = np.inf
        hull_distance = self.backend.hull_distance
        for sa in self.scene_shapes(a):
            wa = sa.world(ta)
            for sb in self.scene_shapes(b):
                best = min(best, hull_distance(sa.obj, wa, sb.obj, sb.world(tb)))
        return float(best)

    def pair_nearest(
        self, a: str, ta: np.ndarray, b: str, tb: np.ndarray, hull: bool
    ) -> tuple[float, np.ndarray, np.ndarray]:
        """``(signed distance [m], point of a (3,), point of b (3,))`` of the closest shape pair of
        two links, the points in the frame of ``ta``/``tb`` (4, 4): of the convex hulls when
        ``hull`` (:meth:`pair_distance_bound`), else of the shapes."""
        best: tuple[float, np.ndarray, np.ndarray] = (np.inf, np.zeros(3), np.zeros(3))
        nearest = self.backend.nearest
        for sa in self.scene_shapes(a):
            wa = sa.world(ta)
            for sb in self.scene_shapes(b):
                found = nearest(sa.obj, wa, sb.obj, sb.world(tb), hull)
                if found[0] < best[0]:
                    best = found
        return best

    def pair_collide(self, a: str, ta: np.ndarray, b: str, tb: np.ndarray) -> tuple[bool, float]:
        """(any shape pair in collision, largest penetration depth [m]) of two links."""
        hit, depth = False, 0.0
        for sa in self.scene_shapes(a):
            wa = sa.world(ta)
            for sb in self.scene_shapes(b):
                c, d = self.backend.collide(sa.obj, wa, sb.obj, sb.world(tb))
                if c:
                    hit, depth = True, max(depth, d)
        return hit, depth


__all__ = ["RIM_POINTS", "CollisionScene", "SceneShape", "ShapePart", "UnusableShape"]
