"""Counting a mesh's edges: runs of sorted keys and membership, as numpy's unique and isin give them."""

from __future__ import annotations

import numpy as np

from geomcheck.geometry.orientation import sorted_members, sorted_runs, winding


def test_sorted_runs_and_members_are_numpys_unique_and_isin() -> None:
    rng = np.random.default_rng(5)
    for size in (0, 1, 7, 300):
        values = np.sort(rng.integers(0, 40, size=size))
        keys, counts = sorted_runs(values)
        expected_keys, expected_counts = np.unique(values, return_counts=True)
        assert np.array_equal(keys, expected_keys) and np.array_equal(counts, expected_counts)
        members = np.unique(rng.integers(0, 40, size=size // 2))
        assert np.array_equal(sorted_members(values, members), np.isin(values, members))
    assert sorted_runs(np.array([3, 3, 5]))[1].tolist() == [2, 1]


def test_winding_counts_the_faces_turned_against_their_neighbours() -> None:
    vertices = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    closed = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    assert (winding(vertices, closed).shared, winding(vertices, closed).inconsistent) == (6, 0)
    turned = closed.copy()
    turned[2] = turned[2, ::-1]
    result = winding(vertices, turned)
    assert (result.shared, result.inconsistent, result.closed) == (6, 3, True)
    assert abs(winding(vertices, closed).volume - 1.0 / 6.0) < 1e-12
