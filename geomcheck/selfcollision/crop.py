"""A still link's meshes cut down to the triangles that a moving link can come near in a sweep.

An exact distance query between meshes traverses both bounding-volume hierarchies; when a
small moving part (a caster wheel) turns inside a recess of a large still mesh (a robot's
base), most of the traversal is spent in parts of the still mesh the moving one never
reaches. Over a whole sweep the moving link stays inside one sphere (``LinkMotion.sphere``
of :mod:`geomcheck.selfcollision.sweep_plan`, centre ``c``, radius ``r``). A triangle whose
axis-aligned box is at least ``keep`` from that sphere is at least ``keep`` from the moving
link at every angle, so the distance to the triangles kept, when it is below ``keep`` (less
the engines' tolerance), *is* the distance to the whole mesh: the query then costs what the
part costs, and gives the same value (the same closest triangles). A larger distance is
asked again of the whole mesh. ``keep`` scales with the moving link (a fraction of its
sphere's radius, at least the clearance margin the sweep resolves), so most queries of a
sweep, which are the near ones, stay on the part.

When one revolute joint turns the moving link past the still one (a joint's two housings,
nested around its axis), both meshes are cut much closer (:func:`turning_parts`): every
triangle keeps its radius and height about the axis as it turns, so two triangles whose
cylindrical boxes (:func:`geomcheck.selfcollision.turn_bound.triangle_boxes`) are ``keep``
apart in ``(r, z)`` stay that far at every angle. A triangle of either link far in ``(r, z)``
from every triangle of the other is dropped; the distance between the two parts, when below
``keep`` (less the engines' tolerance), is the distance between the whole meshes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geomcheck.collision.base import SEPARATION_MARGIN, MeshArrays
from geomcheck.collision.scene import CollisionScene, SceneShape, ShapePart
from geomcheck.selfcollision.turn_bound import close_pairs, shape_boxes

KEEP_FRACTION = 0.5  # triangles kept within this fraction of the moving link's sphere radius [ratio]
MIN_DROPPED = 0.25  # a part worth its own hierarchy drops at least this share of the triangles [ratio]


@dataclass(frozen=True)
class Reach:
    """Where a moving link can be over a whole sweep: a world sphere, and how far around it the
    still meshes are kept."""

    centre: np.ndarray  # (3,) [m]
    radius: float  # [m]
    keep: float  # [m]


def reach(centre: np.ndarray, radius: float, margin: float) -> Reach:
    """The :class:`Reach` of a link swept inside the sphere (``centre``, ``radius``): triangles
    within ``max(margin, KEEP_FRACTION * radius)`` [m] of it are kept."""
    return Reach(np.asarray(centre, dtype=float), float(radius), max(float(margin), KEEP_FRACTION * float(radius)))


def box_distances(triangles: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Distances [m] from ``point`` (3,) to the axis-aligned boxes of ``triangles`` (n, 3, 3):
    lower bounds of its distances to the triangles."""
    lo, hi = triangles.min(axis=1), triangles.max(axis=1)
    return np.linalg.norm(point - np.clip(point, lo, hi), axis=1)


def kept_faces(triangles: np.ndarray, near: Reach) -> np.ndarray:
    """Indices of the world ``triangles`` (n, 3, 3) that may come within ``near.keep`` of a link
    inside ``near``'s sphere."""
    return np.flatnonzero(box_distances(triangles, near.centre) - near.radius < near.keep)


def part_mesh(mesh: MeshArrays, faces: np.ndarray) -> MeshArrays:
    """The triangles ``faces`` (indices) of ``mesh`` with only the vertices they use, in the
    mesh's frame and order (the same coordinates, so the same distances)."""
    chosen = np.asarray(mesh.faces)[faces]
    used, inverse = np.unique(chosen.ravel(), return_inverse=True)
    return MeshArrays(np.asarray(mesh.vertices)[used], inverse.reshape(-1, 3).astype(np.int64))


def _part(scene: CollisionScene, shape: SceneShape, faces: np.ndarray, keep: float) -> ShapePart | None:
    """The part of ``shape``'s mesh made of ``faces`` (indices), or ``None`` when the whole mesh
    is asked instead: it would keep too much of itself to be worth a hierarchy of its own, or
    nothing (every query is then beyond the part)."""
    assert shape.mesh is not None
    if len(faces) > (1.0 - MIN_DROPPED) * len(shape.mesh.faces) or not len(faces):
        return None
    return ShapePart(scene.backend.part(shape.obj, part_mesh(shape.mesh, faces)), keep - SEPARATION_MARGIN)


def _parts_of(
    scene: CollisionScene, link: str, boxes: list[np.ndarray], near: np.ndarray, keep: float
) -> tuple[ShapePart | None, ...] | None:
    """Per shape of ``link`` (its ``boxes``, :func:`shape_boxes`), its part made of the boxes
    ``near`` (indices into all of them in order)."""
    parts: list[ShapePart | None] = []
    first = 0
    for shape, own in zip(scene.scene_shapes(link), boxes, strict=True):
        if shape.mesh is None or not len(shape.mesh.faces):
            parts.append(None)
        else:
            mine = near[(near >= first) & (near < first + len(own))] - first
            parts.append(_part(scene, shape, mine, keep))
        first += len(own)
    return tuple(parts) if any(p is not None for p in parts) else None


def turning_parts(
    scene: CollisionScene,
    links: tuple[str, str],
    frames: np.ndarray,
    axis: tuple[np.ndarray, np.ndarray],
    keep: float,
) -> tuple[tuple[ShapePart | None, ...] | None, tuple[ShapePart | None, ...] | None]:
    """Per shape of a moving and of a still link (``links``, placed at world ``frames``
    (2, 4, 4)), the part that can come within ``keep`` [m] of the other link while one revolute
    joint turns the moving one about ``axis`` (point, unit direction) (``None``: the whole
    shape; a link's ``None``: every one of its shapes whole)."""
    boxes_a = shape_boxes(scene, links[0], frames[0], *axis)
    boxes_b = shape_boxes(scene, links[1], frames[1], *axis)
    i, j, _ = close_pairs(np.concatenate(boxes_a), np.concatenate(boxes_b), keep)
    parts_a = _parts_of(scene, links[0], boxes_a, np.unique(i), keep)
    return parts_a, _parts_of(scene, links[1], boxes_b, np.unique(j), keep)


def still_parts(
    scene: CollisionScene, link: str, frame: np.ndarray, near: Reach
) -> tuple[ShapePart | None, ...] | None:
    """Per shape of ``link`` placed at world ``frame`` (4, 4), its part near ``near`` (``None``
    for a primitive, or a mesh that would keep too much of itself to be worth a hierarchy of
    its own); ``None`` when no shape has one."""
    parts: list[ShapePart | None] = []
    for shape in scene.scene_shapes(link):
        if shape.mesh is None or not len(shape.mesh.faces):
            parts.append(None)
            continue
        world = frame @ shape.pose
        triangles = shape.mesh.vertices[shape.mesh.faces] @ world[:3, :3].T + world[:3, 3]
        parts.append(_part(scene, shape, kept_faces(triangles, near), near.keep))
    return tuple(parts) if any(p is not None for p in parts) else None


__all__ = [
    "KEEP_FRACTION",
    "Reach",
    "box_distances",
    "kept_faces",
    "part_mesh",
    "reach",
    "still_parts",
    "turning_parts",
]
