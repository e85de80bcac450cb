"""Sphere covers of convex hulls (the matrix's broad phase and certificates rely on them)."""

from __future__ import annotations

import numpy as np
import pytest

from geomcheck.geometry.cover import hull_cover


def test_sphere_covers_hold_the_whole_hull() -> None:
    rng = np.random.default_rng(0)
    for scale in (0.3, 1.0, 3.0):
        points = rng.normal(size=(300, 3)) * np.array([0.4, 0.1, 0.03]) * scale
        cover = hull_cover(points)
        centres = np.array([c for c, _ in cover])
        radii = np.array([r for _, r in cover])
        assert 1 < len(cover) <= 16
        # points of the hull: convex combinations weighted towards the vertices, and the vertices
        inside = rng.dirichlet(np.full(len(points), 0.05), 20000) @ points
        gaps = np.linalg.norm(np.concatenate([inside, points])[:, None] - centres[None], axis=2) - radii
        assert (gaps.min(axis=1) <= 0).all()
        assert radii.max() < 0.5 * np.linalg.norm(points - points.mean(axis=0), axis=1).max()


def test_a_short_wide_hull_is_one_ball_and_tiny_sets_are_enclosed() -> None:
    cube = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * 0.05
    [(centre, radius)] = hull_cover(cube)
    assert np.allclose(centre, 0.0) and radius == pytest.approx(np.sqrt(3) * 0.05 + 1e-6, abs=1e-12)
    [(centre, radius)] = hull_cover(np.array([[0.0, 0.0, 0.0], [0.2, 0.0, 0.0]]))
    assert np.allclose(centre, [0.1, 0.0, 0.0]) and radius == pytest.approx(0.1 + 1e-6, abs=1e-12)
    assert hull_cover(np.zeros((0, 3))) == []


def _box(size: tuple[float, float, float], turn: float) -> np.ndarray:
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * size
    c, s = np.cos(turn), np.sin(turn)
    return corners @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).T + np.array([0.3, -0.2, 0.1])


BOX_FACES = ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5))  # corners 4x + 2y + z


def test_known_faces_give_the_hull_cover_without_a_hull(monkeypatch: pytest.MonkeyPatch) -> None:
    short, long = _box((0.05, 0.045, 0.04), 0.4), _box((0.4, 0.05, 0.03), 0.4)
    expected = {id(short): hull_cover(short), id(long): hull_cover(long)}
    assert len(expected[id(short)]) == 1 and len(expected[id(long)]) == 3
    calls: list[int] = []
    monkeypatch.setattr("geomcheck.geometry.cover._qhull", lambda points: calls.append(len(points)))
    [(centre, radius)] = hull_cover(short, BOX_FACES)
    assert np.array_equal(centre, expected[id(short)][0][0]) and radius == expected[id(short)][0][1]  # bit for bit
    got = hull_cover(long, BOX_FACES)
    assert calls == []  # qhull was never asked
    assert len(got) == 3
    for (c, r), (c0, r0) in zip(got, expected[id(long)], strict=True):
        assert np.allclose(c, c0, rtol=0, atol=1e-12) and r == pytest.approx(r0, abs=1e-12)


def test_a_box_of_zero_width_with_known_faces_is_covered_as_qhull_covers_it() -> None:
    flat = _box((0.6, 0.2, 0.0), 0.3)  # long enough for several cells, no thickness: faces without area
    with np.errstate(all="raise"):  # no normal computed from a face without area
        got = hull_cover(flat, BOX_FACES)
    assert len(got) == len(hull_cover(flat)) == 1
    centre, radius = got[0]
    assert np.linalg.norm(flat - centre, axis=1).max() <= radius + 1e-12
