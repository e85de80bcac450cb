"""trimesh's convex hull and its mass properties, without trimesh, to the last bit."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from geomcheck.geometry.hull_mesh import is_solid, solid_properties, trimesh_hull
from geomcheck.geometry.inertia import solid_hull


def clouds() -> list[np.ndarray]:
    """Point sets whose hulls take each of trimesh's paths; the last three make no solid."""
    rng = np.random.default_rng(7)
    grid = np.stack(np.meshgrid(*[np.linspace(0.0, 0.1, 4)] * 3), axis=-1).reshape(-1, 3)
    near = rng.normal(size=(60, 3))
    return [
        np.asarray(trimesh.creation.box(extents=(0.2, 0.1, 0.05)).vertices),
        np.asarray(trimesh.creation.cylinder(radius=0.05, height=0.3, sections=33).vertices),
        np.asarray(trimesh.creation.icosphere(subdivisions=3, radius=0.01).vertices) + 5.0,
        rng.normal(size=(500, 3)) * 1e-3,
        rng.normal(size=(2000, 3)) * 2.5,
        grid,  # coplanar points on every face: zero-area and unused vertices
        np.concatenate([near, near + rng.normal(size=near.shape) * 1e-10]),  # vertices merged by trimesh
        rng.normal(size=(40, 3)) * [1.0, 1.0, 0.0],  # flat: qhull fails, then joggles; left to trimesh
        np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=float),
    ]


@pytest.mark.parametrize("index", range(len(clouds())))
def test_hull_arrays_equal_trimesh_hull(index: int) -> None:
    points = np.ascontiguousarray(clouds()[index], dtype=np.float64)
    with np.errstate(invalid="ignore"):  # trimesh's centre of mass of a flat hull divides by zero volume
        expected = trimesh.convex.convex_hull(points)
        vertices, faces = trimesh_hull(points)
    assert vertices.dtype == np.float64 and faces.dtype == np.int64
    assert vertices.tobytes() == np.asarray(expected.vertices).tobytes()
    assert faces.tobytes() == np.asarray(expected.faces).tobytes()


@pytest.mark.parametrize("index", range(len(clouds())))
def test_mass_properties_are_trimeshs(index: int) -> None:
    points = clouds()[index]
    with np.errstate(invalid="ignore", divide="ignore"):
        theirs = trimesh.convex.convex_hull(points)
        vertices, faces = trimesh_hull(points)
        solid = is_solid(vertices, faces)
        assert solid is bool(theirs.is_volume) is (index < 6)  # trimesh's welded hull (6) is open
    if not solid:
        assert solid_hull(points) is None
        return
    volume, centre, inertia = solid_properties(vertices, faces)
    assert volume == theirs.volume
    assert np.array_equal(centre, theirs.center_mass)
    assert np.array_equal(inertia, theirs.moment_inertia)
    solid = solid_hull(points)
    assert solid is not None and solid.mass == theirs.mass


def test_a_box_hull_has_the_boxs_volume_and_inertia() -> None:
    vertices, faces = trimesh_hull(clouds()[0])  # a 0.2 x 0.1 x 0.05 m box
    volume, centre, inertia = solid_properties(vertices, faces)
    assert volume == pytest.approx(0.001, rel=1e-12)
    assert np.allclose(centre, 0.0, atol=1e-15)
    expected = [0.001 * (0.01 + 0.0025) / 12, 0.001 * (0.04 + 0.0025) / 12, 0.001 * (0.04 + 0.01) / 12]
    assert np.allclose(np.diag(inertia), expected)


def test_open_or_miswound_surfaces_are_no_solid() -> None:
    box = trimesh.creation.box()
    vertices, faces = np.asarray(box.vertices), np.asarray(box.faces)
    assert is_solid(vertices, faces)
    assert not is_solid(vertices, faces[1:])  # a face missing: open
    flipped = faces.copy()
    flipped[0] = flipped[0][::-1]
    assert not is_solid(vertices, flipped)  # one face wound the other way
    assert not is_solid(vertices, faces[:, ::-1])  # inside out: negative volume
    assert not is_solid(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
