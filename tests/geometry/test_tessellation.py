"""The primitives' meshes are trimesh's, value for value, without importing trimesh."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import trimesh

from geomcheck.geometry import tessellation
from geomcheck.geometry.shapes import CYLINDER_SECTIONS, SPHERE_SUBDIVISIONS, tessellate
from geomcheck.model import Box, Cylinder, Sphere

# nanometres to tens of metres, log-uniform, and the edge cases: zero, the sizes where
# trimesh's area threshold (1e-8 m^2) starts dropping a 64-wedge cylinder's triangles
SIZES = np.concatenate([10.0 ** np.random.default_rng(7).uniform(-9, 1.5, 120), [0.0, 1e-12, 4.47e-4, 4.48e-4, 1.0]])


def same(ours: tuple[np.ndarray, np.ndarray], theirs: trimesh.Trimesh) -> bool:
    vertices, faces = ours
    return (
        vertices.dtype == np.float64
        and faces.dtype == np.int64
        and faces.shape == theirs.faces.shape
        and np.array_equal(vertices, theirs.vertices)
        and np.array_equal(faces, theirs.faces)
    )


def test_box_is_trimeshs_box() -> None:
    for size in ((0.1, 0.2, 0.3), (1e-9, 5.0, 0.0), (0.0, 0.0, 0.0), tuple(SIZES[:3])):
        ours = tessellation.box(size)
        assert ours[0].shape == (8, 3) and ours[1].shape == (12, 3)
        assert same(ours, trimesh.creation.box(extents=np.asarray(size, dtype=float)))


@pytest.mark.parametrize("length_of", [lambda r, other: other, lambda r, other: 0.0, lambda r, other: -r])
def test_cylinder_is_trimeshs_cylinder(length_of) -> None:  # type: ignore[no-untyped-def]
    welded = 0
    for radius, other in zip(SIZES, SIZES[::-1], strict=True):
        length = length_of(radius, other)
        theirs = trimesh.creation.cylinder(radius=radius, height=length, sections=CYLINDER_SECTIONS)
        ours = tessellation.cylinder(radius, length, CYLINDER_SECTIONS)
        assert same(ours, theirs), (radius, length)
        welded += len(ours[0]) < 4 * CYLINDER_SECTIONS
    assert welded == len(SIZES)  # the centres of both caps are always welded into one vertex each


def test_a_usual_cylinder_has_two_rims_and_two_centres() -> None:
    vertices, faces = tessellation.cylinder(0.05, 0.2, CYLINDER_SECTIONS)
    assert vertices.shape == (2 * CYLINDER_SECTIONS + 2, 3)
    assert faces.shape == (4 * CYLINDER_SECTIONS, 3)  # a cap triangle, two side triangles, a cap triangle per wedge
    assert np.allclose(np.hypot(vertices[:, 0], vertices[:, 1]).max(), 0.05)
    assert sorted(set(np.round(vertices[:, 2], 12))) == [-0.1, 0.1]


@pytest.mark.parametrize("subdivisions", [0, 1, 2, 3, 4])
def test_icosphere_is_trimeshs_icosphere(subdivisions: int) -> None:
    for radius in (*SIZES[SIZES > 0][:40], 0.7, 1.0):
        theirs = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
        ours = tessellation.icosphere(subdivisions, radius)
        assert same(ours, theirs), (subdivisions, radius)
        assert len(ours[1]) == 20 * 4**subdivisions


def test_shapes_tessellate_without_importing_trimesh() -> None:
    code = (
        "import sys\n"
        "from geomcheck.geometry.shapes import tessellate\n"
        "from geomcheck.model import Box, Cylinder, Sphere\n"
        "tessellate(Box(size=(1.0, 2.0, 3.0)))\n"
        "for g in (Cylinder(radius=0.1, length=0.2), Sphere(radius=0.3), Sphere(radius=1e-30)):\n"
        "    tessellate(g)\n"
        "print(sorted(m for m in ('trimesh', 'scipy') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_tiny_sphere_is_a_scaled_unit_sphere() -> None:
    tiny = tessellate(Sphere(radius=1e-30))
    unit = trimesh.creation.icosphere(subdivisions=SPHERE_SUBDIVISIONS, radius=1.0)
    assert np.array_equal(tiny["vertices"], unit.vertices * 1e-30)
    assert np.array_equal(tessellate(Box(size=(1.0, 2.0, 3.0)))["faces"], trimesh.creation.box().faces)
    assert tessellate(Cylinder(radius=0.1, length=0.2))["vertices"].shape == (2 * CYLINDER_SECTIONS + 2, 3)
