"""Boxes refitted clear of other links (:func:`geomcheck.fix.clear.clear_boxes`)."""

from __future__ import annotations

import numpy as np
import pytest

from geomcheck.fix.clear import (
    MAX_BOXES,
    Motion,
    Voxels,
    _clear,
    _largest_move,
    _within,
    clear_boxes,
    obstacles,
    partition,
)
from geomcheck.model import Pose, Sphere


def cross(n: int = 40) -> np.ndarray:
    """Points of a cross of two 0.6 x 0.2 x 0.2 m arms: the wells in its corners are empty."""
    u = np.linspace(-0.3, 0.3, n)
    v = np.linspace(-0.1, 0.1, n // 3)
    z = np.linspace(0.0, 0.2, n // 3)
    a = np.array(np.meshgrid(u, v, z)).reshape(3, -1).T
    return np.concatenate((a, a[:, [1, 0, 2]]))


def wheel_wells() -> np.ndarray:
    """A sphere of 0.08 m in each corner, 0.1 m from both arms' sides' corners."""
    rng = np.random.default_rng(0)
    d = rng.normal(size=(500, 3))
    ball = 0.08 * d / np.linalg.norm(d, axis=1)[:, None]
    return np.concatenate([ball + np.array([x, y, 0.1]) for x in (-0.22, 0.22) for y in (-0.22, 0.22)])


def test_boxes_enclose_the_mesh_and_keep_clear_of_the_wells() -> None:
    points, keep = cross(), wheel_wells()
    boxes = clear_boxes(points, keep, 0.005, points)
    assert boxes is not None and 1 < len(boxes) <= MAX_BOXES
    inside = np.zeros(len(points), dtype=bool)
    for lo, hi in boxes:
        inside |= np.all((points >= lo - 1e-12) & (points <= hi + 1e-12), axis=1)
        outside = np.maximum(np.maximum(lo - keep, keep - hi), 0.0)
        assert np.linalg.norm(outside, axis=1).min() > 0.005
    assert inside.all()


def test_no_boxes_when_the_mesh_itself_reaches_the_other_link() -> None:
    points = cross()
    assert clear_boxes(points, points[::50] + 0.001, 0.005, points) is None


def test_one_box_when_nothing_is_near() -> None:
    points = cross()
    boxes = clear_boxes(points, wheel_wells() + np.array([0.0, 0.0, 1.0]), 0.005, points)
    assert boxes is not None and len(boxes) == 1


def test_voxel_centres_are_the_occupied_cubes_in_lexicographic_order() -> None:
    points = np.random.default_rng(5).normal(scale=0.2, size=(50_000, 3)) - 0.3
    voxel = 0.013
    expected = np.unique(np.floor(points / voxel), axis=0) * voxel + 0.5 * voxel
    voxels = Voxels(points.min(axis=0), points.max(axis=0), voxel)
    voxels.mark(points[:25_000])
    voxels.mark(points[25_000:])  # a chunk at a time: the union's cubes
    centres = voxels.centres()
    assert centres.shape == expected.shape and np.array_equal(centres, expected)
    assert np.abs(points[:, None, :][:100] - centres[None, :, :]).max(axis=2).min(axis=1).max() <= 0.5 * voxel + 1e-12


def turning(n: int) -> np.ndarray:
    """``n`` placements (n, 4, 4) of a full turn about z through (0.3, 0.3, 0): a caster's swivel."""
    out = np.repeat(np.eye(4)[None], n, axis=0)
    for k, a in enumerate(np.linspace(-np.pi, np.pi, n, endpoint=False)):
        c, s = np.cos(a), np.sin(a)
        out[k, :3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        out[k, :3, 3] = np.array([0.3, 0.3, 0.0]) - out[k, :3, :3] @ np.array([0.3, 0.3, 0.0])
    return out


def test_the_largest_move_from_the_hull_corners_is_that_of_every_point() -> None:
    points = np.random.default_rng(2).normal(scale=0.05, size=(3000, 3)) + np.array([0.2, 0.25, 0.1])
    relative = turning(40)
    moved = points @ relative[:, :3, :3].transpose(0, 2, 1) + relative[:, None, :3, 3]
    every = float(np.linalg.norm(moved - np.roll(moved, 1, axis=0), axis=-1).max())
    assert _largest_move(points, relative, [40]) == 0.5 * every
    assert _largest_move(points, relative[:1], []) == 0.0


def test_obstacles_a_chunk_at_a_time_are_those_of_the_whole_motion() -> None:
    # the other link's geometry moved by every configuration at once and thinned as clear_boxes
    # thins it gives the same boxes, voxels and nearest distance as the chunked stream
    points, wells = cross(), wheel_wells()[:500]
    motion = Motion(wells - np.array([-0.22, -0.22, 0.0]) + np.array([0.3, 0.3, 0.0]), turning(36))
    whole = np.concatenate(list(motion.moved(chunk=36)))
    near = (points.min(axis=0) - 0.1, points.max(axis=0) + 0.1)
    whole = whole[_within(whole.T, *near)]
    rotation = np.eye(3)
    ball = (Sphere(0.05), Pose((0.0, 0.0, 0.1)))
    found = obstacles([motion], near, rotation, (points.min(axis=0), points.max(axis=0)), 0.005, ball)
    expected = float((np.linalg.norm(whole - np.array([0.0, 0.0, 0.1]), axis=1) - 0.05).min())
    assert found.nearest == pytest.approx(expected, abs=1e-12)
    chunked, at_once = partition(points, found.keep, found.margin, points), clear_boxes(points, whole, 0.005, points)
    assert chunked is not None and at_once is not None and 1 < len(chunked) <= MAX_BOXES
    assert [(lo.tolist(), hi.tolist()) for lo, hi in chunked] == [(lo.tolist(), hi.tolist()) for lo, hi in at_once]


def test_a_box_is_clear_exactly_when_every_point_is_farther_than_the_margin() -> None:
    # points on both sides of the margin around random boxes (inside, beside a face, past an
    # edge or a corner): the search of the grown box answers as the distance to every point does
    rng = np.random.default_rng(3)
    margin = 0.01
    answers = []
    for _ in range(300):
        lo = rng.uniform(-0.2, 0.0, 3)
        hi = lo + rng.uniform(0.01, 0.2, 3)
        points = rng.uniform(lo - 3.0 * margin, hi + 3.0 * margin, (rng.integers(1, 4), 3))
        outside = np.maximum(np.maximum(lo - points, points - hi), 0.0)
        expected = bool((outside**2).sum(axis=1).min() > margin**2)
        assert _clear(lo, hi, np.ascontiguousarray(points.T), margin) is expected
        answers.append(expected)
    assert 30 < sum(answers) < 270  # both answers were asked for
    assert _clear(np.zeros(3), np.ones(3), np.zeros((3, 0)), margin) is True
    just_past = np.array([[1.0 + margin * 1.001], [0.5], [0.5]])
    assert _clear(np.zeros(3), np.ones(3), just_past, margin) is True
    assert _clear(np.zeros(3), np.ones(3), just_past - 0.002 * margin, margin) is False
