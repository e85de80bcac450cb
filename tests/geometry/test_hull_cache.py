"""The inertia family's hulls kept in the cache by the exact bytes of their points: a hit
returns equal values, other points miss, and a warm read imports neither scipy nor trimesh."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from geomcheck.cache import Store, using_store
from geomcheck.geometry.hull_cache import (
    DISTANCE_NAMESPACE,
    HULL_NAMESPACE,
    SOLID_NAMESPACE,
    stored_distance_outside,
    stored_hull,
    stored_solid_hull,
)
from geomcheck.geometry.inertia import convex_hull, distance_outside, solid_hull

CUBE = np.array([[x, y, z] for x in (0.0, 0.2) for y in (0.0, 0.1) for z in (0.0, 0.05)])


def count(store: Store, namespace: str) -> int:
    folder = store.root / namespace
    return sum(1 for p in folder.rglob("*") if p.is_file()) if folder.is_dir() else 0


def test_a_stored_hull_equals_the_computed_one_and_other_points_miss(tmp_path: Path) -> None:
    store = Store(tmp_path)
    expected = convex_hull(CUBE)
    with using_store(store):
        first = stored_hull(CUBE)
        second = stored_hull(CUBE)
        stretched = stored_hull(CUBE * [2.0, 1.0, 1.0])
    for hull in (first, second):
        assert hull.volume == expected.volume and abs(hull.volume - 0.001) < 1e-15
        assert np.array_equal(hull.lower, expected.lower) and np.array_equal(hull.upper, expected.upper)
        assert np.array_equal(hull.triangles, expected.triangles)
        assert np.array_equal(hull.equations, expected.equations)
    assert abs(stretched.volume - 0.002) < 1e-15
    assert count(store, HULL_NAMESPACE) == 2 and store.hits == 1


def test_a_stored_distance_and_solid_equal_the_computed_ones(tmp_path: Path) -> None:
    store = Store(tmp_path)
    outside = np.array([0.5, 0.05, 0.025])
    hull = convex_hull(CUBE)
    with using_store(store):
        assert stored_distance_outside(hull, outside) == distance_outside(hull, outside)
        assert stored_distance_outside(hull, outside) == distance_outside(hull, outside)
        assert stored_distance_outside(hull, np.array([0.6, 0.05, 0.025])) == distance_outside(
            hull, np.array([0.6, 0.05, 0.025])
        )
        assert stored_distance_outside(hull, np.array([0.1, 0.05, 0.025])) == 0.0  # inside: not stored
        expected = solid_hull(CUBE)
        assert expected is not None
        for _ in range(2):
            solid = stored_solid_hull(CUBE)
            assert solid is not None and solid.mass == expected.mass
            assert np.array_equal(solid.center_mass, expected.center_mass)
            assert np.array_equal(solid.moment_inertia, expected.moment_inertia)
        flat = CUBE[CUBE[:, 2] == 0.0]
        assert stored_solid_hull(flat) is None and stored_solid_hull(flat) is None
    assert abs(distance_outside(hull, outside) - 0.3) < 1e-12
    assert count(store, DISTANCE_NAMESPACE) == 2 and count(store, SOLID_NAMESPACE) == 2


def test_a_warm_read_imports_neither_scipy_nor_trimesh(tmp_path: Path) -> None:
    probe = f"""
import sys, numpy as np
from pathlib import Path
from geomcheck.cache import Store, using_store
from geomcheck.geometry.hull_cache import stored_hull, stored_solid_hull, stored_distance_outside
cube = np.array({CUBE.tolist()!r})
with using_store(Store(Path(sys.argv[1]))):
    hull = stored_hull(cube)
    stored_distance_outside(hull, np.array([0.5, 0.05, 0.025]))
    stored_solid_hull(cube)
print(sorted(m for m in ("scipy", "trimesh") if m in sys.modules))
"""
    runs = [
        subprocess.run([sys.executable, "-c", probe, str(tmp_path)], capture_output=True, text=True, check=True)
        for _ in range(2)
    ]
    assert runs[0].stdout.split() == ["['scipy']"]  # qhull; trimesh's hull and distances need no trimesh
    assert runs[1].stdout.split() == ["[]"]
