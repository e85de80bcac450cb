"""Meshes for the report's 3D view: welded, decimated for display only, quantised and packed.

Nothing here feeds a rule: every analysis reads the full meshes. A mesh is welded (bitwise
equal vertices merged, as :func:`geomcheck.load.stl.weld_indices` groups them), stripped of
faces on non-finite vertices and of degenerate faces, decimated to a triangle budget with
fast-simplification's quadric edge collapse (Garland and Heckbert, as in PyVista) when it has
more, then quantised: every vertex as three unsigned 16-bit integers on a uniform grid
``origin + step * q`` [m] over the mesh's bounding box (1/65,535 of its largest extent: 15 um
for a 1 m part), faces as 16-bit indices when the vertices allow, 32-bit otherwise. The
arrays are stored little-endian and base64-encoded in the report; the viewer decodes them
into typed arrays without parsing numbers. Decimation is deterministic (the same input gives
the same bytes), and its results are kept in the active store by the file's sha256.
"""

from __future__ import annotations

import base64
from dataclasses import dataclass
from typing import Any

import numpy as np

from geomcheck.load.stl import weld_indices

GRID = 65535  # quantisation steps across a mesh's largest extent [count]
FORMAT = 1  # of the stored decimated arrays: raised whenever what is made of a mesh changes


@dataclass(frozen=True)
class DisplayMesh:
    """A mesh ready for the viewer: ``positions`` (n, 3) uint16 on the grid ``origin`` (3,)
    [m] + ``step`` [m] * q, ``indices`` (m, 3) into them, and the ``source_triangles`` of the
    mesh it was made from."""

    origin: tuple[float, float, float]
    step: float
    positions: np.ndarray
    indices: np.ndarray
    source_triangles: int

    @property
    def triangles(self) -> int:
        return len(self.indices)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (the ``scene`` section's ``meshes`` entries, less what names the file)."""
        wide = len(self.positions) > 65536
        indices = self.indices.astype("<u4" if wide else "<u2")
        return {
            "triangles": self.triangles,
            "source_triangles": self.source_triangles,
            "origin": list(self.origin),
            "step": self.step,
            "positions": base64.b64encode(self.positions.astype("<u2").tobytes()).decode("ascii"),
            "indices": base64.b64encode(indices.tobytes()).decode("ascii"),
            "index_bytes": 4 if wide else 2,
        }


def clean_mesh(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The mesh welded, without faces on non-finite vertices and without degenerate faces;
    vertices in order of first use."""
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(vertices) == 0 or len(faces) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    finite = np.asarray(np.isfinite(vertices).all(axis=1), dtype=bool)
    faces = faces[finite[faces].all(axis=1)]
    # the vertices welded, then put in order of first use: what welding every corner gives,
    # for a sixth of the rows (a closed mesh has about six corners per vertex)
    _, group = weld_indices(vertices + 0.0)  # + 0.0: -0.0 and 0.0 are one vertex
    corners = faces.reshape(-1)
    corner_group = group[corners]
    first_use = np.full(len(group), len(corner_group), dtype=np.int64)
    np.minimum.at(first_use, corner_group, np.arange(len(corner_group), dtype=np.int64))
    used = np.flatnonzero(first_use < len(corner_group))
    order = used[np.argsort(first_use[used], kind="stable")]
    rank = np.empty(len(group), dtype=np.int64)
    rank[order] = np.arange(len(order), dtype=np.int64)
    faces = rank[corner_group].reshape(-1, 3)
    faces = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])]
    return vertices[corners[first_use[order]]], faces


def decimate(vertices: np.ndarray, faces: np.ndarray, target: int) -> tuple[np.ndarray, np.ndarray]:
    """At most about ``target`` triangles of a welded mesh (unchanged when it has no more)."""
    if len(faces) <= target:
        return vertices, faces
    import fast_simplification

    points, triangles = fast_simplification.simplify(
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.ascontiguousarray(faces, dtype=np.int32),
        target_count=target,
    )[:2]
    if len(triangles) == 0:  # nothing left worth showing: keep the mesh whole rather than lose it
        return vertices, faces
    return np.asarray(points, dtype=np.float64), np.asarray(triangles, dtype=np.int64)


def quantise(vertices: np.ndarray, faces: np.ndarray, source_triangles: int) -> DisplayMesh:
    """The mesh on its 16-bit grid, unused vertices dropped."""
    used = np.zeros(len(vertices), dtype=bool)
    used[faces.reshape(-1)] = True
    remap = np.cumsum(used) - 1
    vertices, faces = vertices[used], remap[faces]
    if len(vertices) == 0:
        return DisplayMesh((0.0, 0.0, 0.0), 0.0, np.zeros((0, 3), np.uint16), np.zeros((0, 3), np.int64), 0)
    low = np.round(vertices.min(axis=0), 9)
    extent = float((vertices.max(axis=0) - low).max())
    step = float(f"{extent / GRID:.6g}") if extent > 0.0 else 1.0
    grid = np.clip(np.rint((vertices - low) / step), 0, GRID).astype(np.uint16)
    origin = (float(low[0]) + 0.0, float(low[1]) + 0.0, float(low[2]) + 0.0)
    return DisplayMesh(origin, step, grid, faces.astype(np.int64), source_triangles)


def display_mesh(vertices: np.ndarray, faces: np.ndarray, target: int) -> DisplayMesh:
    """``vertices`` (n, 3) [m] and ``faces`` (m, 3) as the viewer draws them, with at most
    about ``target`` triangles."""
    welded, welded_faces = clean_mesh(vertices, faces)
    kept, kept_faces = decimate(welded, welded_faces, target)
    return quantise(kept, kept_faces, len(np.asarray(faces).reshape(-1, 3)))


def display_arrays(mesh: DisplayMesh) -> dict[str, np.ndarray]:
    """``mesh`` as named arrays (for the store)."""
    return {
        "origin": np.asarray(mesh.origin, dtype=np.float64),
        "step": np.asarray([mesh.step], dtype=np.float64),
        "positions": mesh.positions,
        "indices": mesh.indices,
        "source_triangles": np.asarray([mesh.source_triangles], dtype=np.int64),
    }


def display_from_arrays(arrays: Any) -> DisplayMesh:
    origin = np.asarray(arrays["origin"], dtype=np.float64)
    return DisplayMesh(
        (float(origin[0]), float(origin[1]), float(origin[2])),
        float(np.asarray(arrays["step"])[0]),
        np.asarray(arrays["positions"], dtype=np.uint16),
        np.asarray(arrays["indices"], dtype=np.int64),
        int(np.asarray(arrays["source_triangles"])[0]),
    )


__all__ = ["FORMAT", "GRID", "DisplayMesh", "clean_mesh", "decimate", "display_mesh", "quantise"]
