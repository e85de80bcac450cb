"""MuJoCo's legacy binary mesh format (``.msh``), read with numpy.

A ``.msh`` file is four little-endian ``int32`` counts (vertices, normals, texture
coordinates, faces), then the vertex positions (``float32`` x 3), the normals (``float32`` x 3),
the texture coordinates (``float32`` x 2) and the faces (``int32`` x 3), and nothing else:
MuJoCo refuses a file whose size differs from what its counts give, and so does this reader.
Only MuJoCo reads the format, so only an MJCF description's meshes are read from it
(:func:`geomcheck.load.meshes.mesh_formats`).
"""

from __future__ import annotations

import numpy as np

HEADER_BYTES = 16


def read_msh(data: bytes) -> tuple[np.ndarray, np.ndarray] | None:
    """``(vertices (n, 3) float64, faces (m, 3) int64)`` of a ``.msh`` file's bytes, or ``None``
    when they are no well-formed ``.msh`` (counts negative or not matching the size, a face
    naming a vertex the file does not have)."""
    if len(data) < HEADER_BYTES:
        return None
    vertices_n, normals_n, texcoords_n, faces_n = (int(v) for v in np.frombuffer(data, dtype="<i4", count=4))
    if min(vertices_n, normals_n, texcoords_n, faces_n) < 0:
        return None
    faces_at = HEADER_BYTES + 12 * vertices_n + 12 * normals_n + 8 * texcoords_n
    if len(data) != faces_at + 12 * faces_n:
        return None
    vertices = np.frombuffer(data, dtype="<f4", count=3 * vertices_n, offset=HEADER_BYTES).reshape(-1, 3)
    faces = np.frombuffer(data, dtype="<i4", count=3 * faces_n, offset=faces_at).reshape(-1, 3)
    if faces.size and (int(faces.min()) < 0 or int(faces.max()) >= vertices_n):
        return None
    return vertices.astype(np.float64), faces.astype(np.int64)


__all__ = ["read_msh"]
