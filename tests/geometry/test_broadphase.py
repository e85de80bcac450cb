"""Sphere broad phase: the pairs an all-pairs matrix finds, in its order, without the matrix."""

from __future__ import annotations

import numpy as np
import pytest

from geomcheck.geometry.broadphase import overlapping_spheres


@pytest.mark.parametrize("count", [2, 7, 120])
def test_pairs_equal_the_all_pairs_matrix(count: int) -> None:
    rng = np.random.default_rng(count)
    for _ in range(10):
        centres = rng.random((count, 3))
        radii = rng.random(count) * 0.15
        gap = np.linalg.norm(centres[:, None] - centres[None], axis=2) - radii[:, None] - radii[None]
        expected = np.argwhere(np.triu(gap <= 0.0, k=1))
        assert np.array_equal(overlapping_spheres(centres, radii), expected)


def test_a_long_chain_makes_pairs_only_with_its_neighbours() -> None:
    count = 20_000
    centres = np.zeros((count, 3))
    centres[:, 2] = 0.05 * np.arange(count)
    pairs = overlapping_spheres(centres, np.full(count, 0.026))
    assert pairs.shape == (count - 1, 2)
    assert np.array_equal(pairs[:, 1] - pairs[:, 0], np.ones(count - 1, dtype=np.int64))


def test_margin_and_degenerate_inputs() -> None:
    centres = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    radii = np.array([0.25, 0.25])
    assert overlapping_spheres(centres, radii).shape == (0, 2)
    assert overlapping_spheres(centres, radii, margin=0.5).tolist() == [[0, 1]]
    assert overlapping_spheres(centres[:1], radii[:1]).shape == (0, 2)
