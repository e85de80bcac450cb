"""Rasterising a mesh by faces in blocks sets exactly the cells of rasterising each triangle."""

from __future__ import annotations

import numpy as np
import trimesh

from geomcheck.geometry.raster import Grid, _unique_edges, rasterize_cells, rasterize_faces


def side_view_cells(mesh: trimesh.Trimesh, extent: float) -> tuple[Grid, np.ndarray, np.ndarray, np.ndarray]:
    """``mesh`` seen along y on a 160-cell grid over ``extent`` [m]: the grid, its vertices in
    cells, its faces, and the cells rasterising each triangle on its own marks."""
    points = np.asarray(mesh.vertices)[:, [0, 2]]
    grid = Grid.covering(points.min(axis=0), points.max(axis=0), pixel=extent / 160)
    cells = grid.to_cells(points)
    faces = np.asarray(mesh.faces)
    expected = np.zeros(grid.shape, dtype=bool)
    rasterize_cells(cells[faces[:, 0]], cells[faces[:, 1]], cells[faces[:, 2]], expected)
    return grid, cells, faces, expected


def test_faces_in_blocks_mark_the_cells_of_every_triangle() -> None:
    # a fine sphere (triangles below a cell) joined with a coarse box (triangles over many cells)
    fine = trimesh.creation.icosphere(subdivisions=5, radius=0.1)
    coarse = trimesh.creation.box(extents=(0.3, 0.05, 0.2))
    coarse.apply_translation((0.12, 0.0, 0.0))
    grid, cells, faces, expected = side_view_cells(trimesh.util.concatenate([fine, coarse]), 0.4)
    for block in (7, 1000, len(faces)):
        got = np.zeros(grid.shape, dtype=bool)
        rasterize_faces(cells, faces, got, block)
        assert np.array_equal(got, expected)
    assert 2000 < int(expected.sum()) < grid.shape[0] * grid.shape[1]


def test_shared_edges_of_thin_triangles_are_traced_once_and_mark_the_same_cells() -> None:
    # a cylinder seen from its side: its wall is long slivers sharing their long edges
    wall = trimesh.creation.cylinder(radius=0.05, height=0.4, sections=200)
    grid, cells, faces, expected = side_view_cells(wall, 0.4)
    got = np.zeros(grid.shape, dtype=bool)
    rasterize_faces(cells, faces, got, len(faces))
    assert np.array_equal(got, expected)
    start, end = _unique_edges(faces, len(cells))
    assert len(faces) == 800 and len(start) == 1200  # a closed surface: each edge of two faces, once
    assert (start < end).all()
