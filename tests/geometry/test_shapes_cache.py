"""A mesh's load and its hull are kept on disk by the file's content, a primitive's solid by the
primitive, and come back equal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

from geomcheck.cache import open_store, using_store
from geomcheck.geometry.shapes import mesh_solid_in, primitive_solid
from geomcheck.geometry.surface import Solid
from geomcheck.load import MeshStore, make_bundle
from geomcheck.model import Cylinder, Mesh
from geomcheck.thresholds import AnalysisThresholds

ANALYSIS = AnalysisThresholds(hull_exact_points=1000)  # the sphere's hull is approximated


def solid_in(root: Path, scale: tuple[float, float, float] = (1.0, 1.0, 1.0)) -> Solid:
    solid = mesh_solid_in(MeshStore(make_bundle(root, search=[])), Mesh("ball.stl", scale), ANALYSIS)
    assert isinstance(solid, Solid)
    return solid


def assert_same(a: Solid, b: Solid) -> None:
    assert a.hull is not None and b.hull is not None
    assert np.array_equal(a.surface.vertices, b.surface.vertices)
    assert np.array_equal(a.surface.faces, b.surface.faces)
    assert np.array_equal(a.vertices, b.vertices)
    assert np.array_equal(a.hull.vertices, b.hull.vertices)
    assert np.array_equal(a.hull.equations, b.hull.equations)
    assert (a.hull.volume, a.hull.tolerance) == (b.hull.volume, b.hull.tolerance)


def test_mesh_load_and_hull_are_cached_by_content_and_scale(tmp_path: Path) -> None:
    trimesh.creation.icosphere(subdivisions=4, radius=0.1).export(tmp_path / "ball.stl")
    root = tmp_path / "robot.urdf"
    root.write_text('<robot name="r"/>')
    uncached = solid_in(root)
    store = open_store(tmp_path / "cache")
    with using_store(store):
        first = solid_in(root)
        entries = sorted(
            p.relative_to(tmp_path / "cache").parts[0] for p in (tmp_path / "cache").rglob("*") if p.is_file()
        )
        second = solid_in(root)
        halved = solid_in(root, (0.5, 0.5, 0.5))
    assert entries.count("mesh-load") == 1 and entries.count("mesh-solid") == 1
    assert_same(uncached, first)
    assert_same(first, second)
    assert first.hull is not None and first.hull.tolerance > 0.0
    assert halved.hull is not None and abs(halved.hull.volume - first.hull.volume / 8.0) < 1e-12
    # the same bytes under another name are the same mesh
    (tmp_path / "ball.stl").rename(tmp_path / "other.stl")
    (tmp_path / "ball.stl").write_bytes((tmp_path / "other.stl").read_bytes())
    with using_store(store):
        assert_same(first, solid_in(root))
    files = [p for p in (tmp_path / "cache").rglob("*") if p.is_file() and p.parts[-3] in ("mesh-load", "mesh-solid")]
    assert len(files) == 3  # one load, the solid at scale 1 and at scale 0.5


def test_a_primitive_solid_is_cached_by_the_primitive(tmp_path: Path) -> None:
    uncached = primitive_solid(Cylinder(radius=0.1, length=0.4))
    store = open_store(tmp_path / "cache")
    with using_store(store):
        first = primitive_solid(Cylinder(radius=0.1, length=0.4))
        second = primitive_solid(Cylinder(radius=0.1, length=0.4))
        longer = primitive_solid(Cylinder(radius=0.1, length=0.8))
    assert_same(uncached, first)
    assert_same(first, second)
    assert first.hull is not None and longer.hull is not None
    assert abs(longer.hull.volume - 2.0 * first.hull.volume) < 1e-12
    files = [p for p in (tmp_path / "cache" / "primitive-solid").rglob("*") if p.is_file()]
    assert len(files) == 2 and store.hits >= 1
