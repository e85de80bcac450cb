"""Meshes for the 3D view: welded, decimated for display, quantised to 16 bits and packed."""

from __future__ import annotations

import base64

import numpy as np
import trimesh

from geomcheck.checks.scene import mesh_targets
from geomcheck.geometry.display_mesh import GRID, clean_mesh, decimate, display_mesh, quantise
from geomcheck.thresholds import ViewThresholds


def soup(mesh: trimesh.Trimesh) -> tuple[np.ndarray, np.ndarray]:
    """The mesh as an STL reader without welding gives it: three vertices per face."""
    corners = mesh.vertices[mesh.faces].reshape(-1, 3)
    return corners, np.arange(len(corners)).reshape(-1, 3)


def decoded(packed: dict[str, object]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices [m] and faces as the viewer decodes the packed arrays."""
    grid = np.frombuffer(base64.b64decode(str(packed["positions"])), dtype="<u2").reshape(-1, 3)
    kind = "<u4" if packed["index_bytes"] == 4 else "<u2"
    faces = np.frombuffer(base64.b64decode(str(packed["indices"])), dtype=kind).reshape(-1, 3)
    origin = np.asarray(packed["origin"], dtype=float)
    return origin + float(packed["step"]) * grid, faces  # type: ignore[arg-type]


def test_a_triangle_soup_is_welded_and_broken_faces_dropped() -> None:
    vertices, faces = soup(trimesh.creation.box(extents=(0.3, 0.2, 0.1)))
    vertices = np.vstack([vertices, [[np.nan, 0.0, 0.0], [1.0, 1.0, 1.0]]])
    faces = np.vstack([faces, [[36, 37, 0], [0, 0, 1]]])  # a face on a NaN vertex, a degenerate face
    welded, welded_faces = clean_mesh(vertices, faces)
    assert welded.shape == (8, 3) and welded_faces.shape == (12, 3)
    assert np.array_equal(np.sort(np.unique(welded_faces)), np.arange(8))
    assert np.allclose(np.ptp(welded, axis=0), (0.3, 0.2, 0.1))


def test_welding_keeps_the_first_corner_of_each_vertex_in_order_of_first_use() -> None:
    """Vertices come out in the order faces first use them, each as its first corner wrote it
    (a -0.0 kept as written, though it welds with 0.0); unused and repeated vertices go."""
    vertices = np.array(
        [[9.0, 9.0, 9.0], [0.0, -0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]
    )
    faces = np.array([[2, 4, 1], [3, 5, 4], [1, 2, 4]])  # face 2 repeats face 0 through equal vertices
    welded, welded_faces = clean_mesh(vertices, faces)
    assert np.array_equal(welded, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    assert np.array_equal(welded_faces, [[0, 1, 2], [2, 0, 1], [2, 0, 1]])
    # (0, 0, 1) is first written by vertex 1, as (0, -0.0, 1): that corner is the one kept
    assert np.array_equal(np.signbit(welded), [[False] * 3, [False] * 3, [False, True, False]])
    assert clean_mesh(vertices, np.zeros((0, 3), dtype=int))[0].shape == (0, 3)


def test_quantised_vertices_are_within_half_a_step() -> None:
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.4)
    mesh.apply_translation((1.0, -2.0, 0.5))
    shown = quantise(np.asarray(mesh.vertices), np.asarray(mesh.faces), len(mesh.faces))
    assert shown.positions.dtype == np.uint16 and shown.positions.max() == GRID
    assert shown.step == float(f"{0.8 / GRID:.6g}") or abs(shown.step - 0.8 / GRID) < 1e-9
    packed = shown.to_dict()
    vertices, faces = decoded(packed)
    assert packed["index_bytes"] == 2 and packed["triangles"] == len(mesh.faces) == 1280
    assert np.abs(vertices - mesh.vertices).max() <= shown.step / 2 + 1e-12
    assert np.array_equal(faces, mesh.faces)


def test_more_than_65536_vertices_take_32_bit_indices() -> None:
    rng = np.random.default_rng(0)
    vertices = rng.uniform(-1.0, 1.0, size=(70_000, 3))
    faces = np.arange(69_999).reshape(-1, 3)
    packed = quantise(vertices, faces, len(faces)).to_dict()
    assert packed["index_bytes"] == 4
    _, decoded_faces = decoded(packed)
    assert np.array_equal(decoded_faces, faces)


def test_decimation_keeps_the_shape_within_the_budget_and_is_deterministic() -> None:
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=0.1)  # 20,480 faces
    vertices, faces = soup(sphere)
    first = display_mesh(vertices, faces, 2000)
    again = display_mesh(vertices, faces, 2000)
    assert first.source_triangles == 20_480 and 1800 <= first.triangles <= 2000
    assert first.to_dict() == again.to_dict()
    points, _ = decoded(first.to_dict())
    radii = np.linalg.norm(points, axis=1)
    assert radii.max() < 0.101 and radii.min() > 0.099  # still the sphere, to a millimetre (1%)
    # under the budget, nothing is decimated
    kept, kept_faces = decimate(np.asarray(sphere.vertices), np.asarray(sphere.faces), 50_000)
    assert len(kept_faces) == 20_480 and kept is not None


def test_the_robots_budget_is_shared_in_proportion_with_a_floor() -> None:
    params = ViewThresholds(scene_triangles=10_000, scene_mesh_triangles=300)
    small = {("a.stl", (1.0, 1.0, 1.0)): 4000, ("b.stl", (1.0, 1.0, 1.0)): 5000}
    assert mesh_targets(small, params) == small
    sizes = {("a.stl", (1.0, 1.0, 1.0)): 30_000, ("b.stl", (1.0, 1.0, 1.0)): 9000, ("c.stl", (2.0, 2.0, 2.0)): 1000}
    targets = mesh_targets(sizes, params)
    assert targets == {
        ("a.stl", (1.0, 1.0, 1.0)): 7500,
        ("b.stl", (1.0, 1.0, 1.0)): 2250,
        ("c.stl", (2.0, 2.0, 2.0)): 300,
    }
