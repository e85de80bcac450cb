"""The collision scene: usable shapes, shared objects, bounds, pair queries."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.collision import CollisionScene, get_backend
from geomcheck.geometry.cover import hull_cover
from geomcheck.load import MeshStore, make_bundle
from geomcheck.model import Box, Cylinder, Joint, Link, Mesh, Pose, Robot, Shape, Sphere


def collision(geometry, xyz=(0, 0, 0), rpy=(0, 0, 0), index=0) -> Shape:
    return Shape("collision", index, geometry, Pose(xyz, rpy))


def fixed(name: str, parent: str, child: str, xyz=(0, 0, 0)) -> Joint:
    return Joint(name, "fixed", parent, child, Pose(xyz))


@pytest.fixture
def meshes(tmp_path: Path) -> MeshStore:
    root = tmp_path / "robot.urdf"
    root.write_text("<robot name='r'/>")
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(tmp_path / "ball.stl")
    return MeshStore(make_bundle(root, display_root=tmp_path))


def robot() -> Robot:
    """base(box) - hub(no geometry) - arm(cylinder + mesh) - tip(missing mesh), base - post(sphere, box)."""
    links = (
        Link("base", collisions=(collision(Box((0.4, 0.4, 0.1))),)),
        Link("hub"),
        Link(
            "arm",
            collisions=(
                collision(Cylinder(0.05, 0.3), xyz=(0.15, 0, 0), rpy=(0, np.pi / 2, 0)),
                collision(Mesh("ball.stl", (2.0, 2.0, 2.0)), xyz=(0.1, 0, 0), index=1),
            ),
        ),
        Link("tip", collisions=(collision(Mesh("missing.stl")),)),
        Link("post", collisions=(collision(Sphere(0.05), xyz=(0, 0, 0.2)), collision(Box((0.4, 0.4, 0.1)), index=1))),
    )
    joints = (
        fixed("base_hub", "base", "hub", (0, 0, 0.3)),
        Joint("hub_arm", "revolute", "hub", "arm", Pose(), (0, 0, 1)),
        fixed("arm_tip", "arm", "tip", (0.5, 0, 0)),
        fixed("base_post", "base", "post", (-0.3, 0, 0)),
    )
    return Robot("r", links, joints)


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_scene_keeps_usable_shapes_and_shares_objects(meshes: MeshStore, backend: str) -> None:
    scene = CollisionScene(robot(), meshes, get_backend(backend))
    assert scene.links == ("base", "arm", "post")
    assert [(u.link, u.shape.label) for u in scene.unusable] == [("tip", "collision[0]")]
    assert "missing.stl" in scene.unusable[0].reason
    # the same box geometry on two links is one engine object
    assert scene.shapes("post")[1][0] is scene.shapes("base")[0][0]
    assert len(scene.shapes("arm")) == 2
    np.testing.assert_allclose(scene.shapes("arm")[0][1][:3, 3], [0.15, 0, 0])


def test_bounding_sphere_holds_the_geometry(meshes: MeshStore) -> None:
    scene = CollisionScene(robot(), meshes, get_backend("coal"))
    centre, radius = scene.bounding_sphere("arm")
    # arm: cylinder along x from 0 to 0.3 (radius 0.05) and a ball of radius 0.1 at x = 0.1
    assert centre == pytest.approx([0.15, 0, 0], abs=1e-9)
    assert radius == pytest.approx(np.hypot(0.15, 0.05), abs=1e-3)
    for shape in robot().link_map["arm"].collisions[:1]:
        g = shape.geometry
        cyl = trimesh.creation.cylinder(radius=g.radius, height=g.length, sections=256)
        cyl.apply_transform(shape.origin.matrix())
        assert np.linalg.norm(cyl.vertices - centre, axis=1).max() <= radius
    centre, radius = scene.bounding_sphere("post")
    # post: a 0.4 x 0.4 x 0.1 box at the origin and a ball of radius 0.05 at z = 0.2
    assert centre == pytest.approx([0, 0, 0.1])
    assert radius == pytest.approx(np.sqrt(0.2**2 + 0.2**2 + 0.15**2))


def test_shapes_place_in_the_world_and_keep_their_sphere_cover(meshes: MeshStore) -> None:
    scene = CollisionScene(robot(), meshes, get_backend("coal"))
    frame = np.eye(4)
    frame[:3, 3] = (1.0, 2.0, 3.0)
    box, ball = scene.scene_shapes("post")[1], scene.scene_shapes("post")[0]
    assert box.at_origin and box.world(frame) is frame
    assert not ball.at_origin
    np.testing.assert_allclose(ball.world(frame)[:3, 3], [1.0, 2.0, 3.2])
    # the cover of the 0.4 x 0.4 x 0.1 box: balls holding its 8 corners, computed once
    assert box.cover is box.cover
    centres = np.array([c for c, _ in box.cover])
    radii = np.array([r for _, r in box.cover])
    gaps = np.linalg.norm(box.points[:, None] - centres[None], axis=2) - radii
    assert len(box.cover) == 9 and (gaps.min(axis=1) <= 0).all()
    assert ball.cover[0][1] == pytest.approx(0.05 + 1e-6, abs=1e-12)


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_pair_queries(meshes: MeshStore, backend: str) -> None:
    scene = CollisionScene(robot(), meshes, get_backend(backend))
    base = np.eye(4)
    arm = np.eye(4)
    arm[:3, 3] = (0, 0, 0.3)
    # base box top at z = 0.05; arm cylinder bottom at z = 0.25, the ball (radius 0.1) reaches z = 0.2
    assert scene.pair_distance("base", base, "arm", arm) == pytest.approx(0.15, abs=2e-3)
    assert scene.pair_collide("base", base, "arm", arm) == (False, 0.0)
    assert scene.closest("base", base, "arm", arm)[1:] == (0, 1)
    arm[:3, 3] = (0, 0, 0.12)
    hit, depth = scene.pair_collide("base", base, "arm", arm)
    assert hit and depth == pytest.approx(0.03, abs=2e-3)  # the ball (as its hull) dips 3 cm into the box
    assert scene.pair_distance("base", base, "arm", arm) == 0.0  # a mesh is involved: contact is 0
    assert scene.pair_distance_bound("base", base, "arm", arm) == pytest.approx(-0.03, abs=2e-3)


class CountingBackend:
    """A backend that counts its exact distance queries."""

    def __init__(self, name: str) -> None:
        self.inner = get_backend(name)
        self.exact = 0

    def __getattr__(self, attr: str):
        return getattr(self.inner, attr)

    def placed_distance(self, *args):
        self.exact += 1
        return self.inner.placed_distance(*args)


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_closest_with_hull_bounds_skips_far_pairs_and_finds_the_same(meshes: MeshStore, backend: str) -> None:
    counting = CountingBackend(backend)
    scene = CollisionScene(robot(), meshes, counting)
    post = np.eye(4)
    arm = np.eye(4)
    arm[:3, 3] = (-0.1, 0, 0.45)  # the arm's ball (radius 0.1) right above the post's sphere (radius 0.05)
    pa, pb = scene.placements("arm", arm[None])[0], scene.placements("post", post[None])[0]
    plain = scene.placed_closest("arm", pa, "post", pb)
    assert counting.exact == 4  # every shape pair
    lower = scene.placed_hull_distances("arm", pa, "post", pb)
    assert lower.shape == (2, 2)
    # ball (z 0.45) to sphere (z 0.2): 0.1, to the box top (z 0.05): 0.3; cylinder (bottom at z 0.4): 0.15, 0.35
    np.testing.assert_allclose(lower, [[0.15, 0.35], [0.1, 0.3]], atol=2e-3)
    assert scene.placed_distance_bound("arm", pa, "post", pb) == pytest.approx(lower.min())
    counting.exact = 0
    pruned = scene.placed_closest("arm", pa, "post", pb, lower)
    assert pruned == plain and plain[1:] == (1, 0)
    assert counting.exact == 1  # the ball-sphere pair: every other pair's bound is beyond its distance


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_closest_breaks_ties_as_a_scan_in_shape_order(meshes: MeshStore, backend: str) -> None:
    scene = CollisionScene(robot(), meshes, get_backend(backend))
    base, post = np.eye(4), np.eye(4)
    base[:3, 3] = (0, 0, 0.5)  # the base box above the post's box and sphere: the sphere is nearer
    pa, pb = scene.placements("base", base[None])[0], scene.placements("post", post[None])[0]
    lower = scene.placed_hull_distances("base", pa, "post", pb)
    # a lower bound that ties every pair: the order of the scan decides, not the bounds' order
    assert scene.placed_closest("base", pa, "post", pb, np.zeros_like(lower)) == scene.placed_closest(
        "base", pa, "post", pb
    )
    assert scene.placed_closest("base", pa, "post", pb, lower)[1:] == (0, 0)


def test_primitive_covers_need_no_hull(meshes: MeshStore, monkeypatch: pytest.MonkeyPatch) -> None:
    # long, turned primitives: several cells, cut along the faces the scene knows
    long = Robot(
        "r",
        (
            Link("beam", collisions=(collision(Box((0.6, 0.08, 0.05)), rpy=(0.3, 0.2, 0.1)),)),
            Link("rod", collisions=(collision(Cylinder(0.03, 0.5), xyz=(0.1, 0, 0), rpy=(0, 1.2, 0.4)),)),
        ),
        (fixed("beam_rod", "beam", "rod"),),
    )
    scene = CollisionScene(long, meshes, get_backend("coal"))
    shapes = [shape for name in scene.links for shape in scene.scene_shapes(name)]
    expected = [hull_cover(np.asarray(shape.points)) for shape in shapes]  # qhull's hull of the support points
    monkeypatch.setattr("geomcheck.geometry.cover._qhull", lambda points: pytest.fail("qhull asked for a primitive"))
    for shape, balls in zip(shapes, expected, strict=True):
        assert len(shape.cover) == len(balls) == 3
        for (c, r), (c0, r0) in zip(shape.cover, balls, strict=True):
            assert np.allclose(c, c0, rtol=0, atol=1e-12) and r == pytest.approx(r0 + shape.pad, abs=1e-12)
