"""coal and python-fcl agree on collision and distance for every shape combination."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import trimesh

from geomcheck.collision import get_backend
from geomcheck.errors import UsageError
from geomcheck.model import Box, Capsule, Cylinder, Sphere
from tests.collision.poses import random_pose

POSES_PER_COMBINATION = 300
GEOMETRIES = {
    "box": Box((0.20, 0.12, 0.08)),
    "cylinder": Cylinder(0.06, 0.18),
    "sphere": Sphere(0.07),
    # a non-convex mesh: a box with a cylindrical bore, in its own frame
    "mesh": trimesh.creation.annulus(r_min=0.03, r_max=0.08, height=0.1, sections=24),
}


@pytest.fixture(scope="module")
def backends():
    coal_backend, fcl_backend = get_backend("coal"), get_backend("fcl")
    made = {name: (coal_backend.make(g), fcl_backend.make(g)) for name, g in GEOMETRIES.items()}
    return coal_backend, fcl_backend, made


@pytest.mark.parametrize("pair", list(itertools.combinations_with_replacement(GEOMETRIES, 2)), ids="-".join)
def test_backends_agree(backends, pair: tuple[str, str]) -> None:
    coal_backend, fcl_backend, made = backends
    (ca, fa), (cb, fb) = made[pair[0]], made[pair[1]]
    has_mesh = "mesh" in pair
    # python-fcl's libccd GJK stops about 4e-5 m short of the exact distance (coal is exact
    # to 1e-12 on primitives, see test_coal_is_exact_on_primitives), hence 1e-4 on primitives
    tolerance = 1e-3 if has_mesh else 1e-4
    rng = np.random.default_rng(sum(map(ord, "".join(pair))))
    collisions = separations = 0
    for _ in range(POSES_PER_COMBINATION):
        ta, tb = random_pose(rng, 0.03), random_pose(rng, 0.12)
        dc = coal_backend.distance(ca, ta, cb, tb)
        df = fcl_backend.distance(fa, ta, fb, tb)
        hit_c, depth_c = coal_backend.collide(ca, ta, cb, tb)
        hit_f, depth_f = fcl_backend.collide(fa, ta, fb, tb)
        if any(0 < abs(d) < 1e-4 for d in (dc, df)):
            continue  # grazing contact: the engines' tolerances decide, not the geometry
        assert hit_c == hit_f == (dc <= 0) == (df <= 0), (pair, dc, df, hit_c, hit_f)
        if dc > 0:
            separations += 1
            assert dc == pytest.approx(df, abs=tolerance), (pair, ta, tb)
        else:
            collisions += 1
            assert depth_c > 0 and depth_f > 0
            if has_mesh:
                assert dc == df == 0.0
            else:  # minus the penetration depth (EPA)
                assert dc == pytest.approx(-depth_c, abs=1e-9)
                if "cylinder" not in pair:  # coal's EPA may escape a cylinder radially, not by the shortest way
                    assert depth_c == pytest.approx(depth_f, abs=1e-3)
    assert collisions > 20 and separations > 20, (collisions, separations)


def test_coal_is_exact_on_primitives(backends) -> None:
    coal_backend, _, made = backends
    rng = np.random.default_rng(7)
    half = np.asarray(GEOMETRIES["box"].size) / 2
    radius = GEOMETRIES["sphere"].radius
    checked = 0
    for _ in range(300):
        ta, tb = random_pose(rng, 0.03), random_pose(rng, 0.2)
        centre = (np.linalg.inv(ta) @ tb[:, 3])[:3]
        if np.all(np.abs(centre) <= half):
            continue
        exact = np.linalg.norm(centre - np.clip(centre, -half, half)) - radius
        if exact > 0:
            checked += 1
            assert coal_backend.distance(made["box"][0], ta, made["sphere"][0], tb) == pytest.approx(exact, abs=1e-12)
    assert checked > 100


@pytest.mark.parametrize("name", ["coal", "fcl"])
def test_deep_box_overlap_is_a_collision(name: str) -> None:
    backend = get_backend(name)
    cube, rod = backend.make(Box((0.2, 0.2, 0.2))), backend.make(Box((0.05, 0.05, 0.6)))
    up = np.eye(4)
    up[2, 3] = 0.2  # the rod runs through the cube's top face down to its bottom face
    hit, depth = backend.collide(cube, np.eye(4), rod, up)
    assert hit and depth == pytest.approx(0.125)


@pytest.mark.parametrize("name", ["coal", "fcl"])
@pytest.mark.parametrize(
    ("centre", "depth"),
    [
        ((0.0, 0.0, 0.00405), 0.03195),  # on the axis, 11.95 mm from the cap: out through the cap
        ((0.02, 0.0, 0.012), 0.024),  # off the axis, 4 mm from the cap
        ((0.03, 0.0, 0.0), 0.031),  # nearer the side than a cap: out through the side
    ],
    ids=["axis", "off-axis", "side"],
)
@pytest.mark.parametrize("sphere_first", [True, False], ids=["sphere-cylinder", "cylinder-sphere"])
def test_a_sphere_in_a_short_cylinder_leaves_by_the_nearest_face(
    name: str, centre: tuple[float, float, float], depth: float, sphere_first: bool
) -> None:
    """A foot sphere folded into a 32 mm long hip cylinder (coal 3.0 measured the side alone:
    61 mm on the axis); the depth is the sphere's radius plus its centre's depth in the cylinder."""
    backend = get_backend(name)
    sphere, cylinder = backend.make(Sphere(0.02)), backend.make(Cylinder(0.041, 0.032))
    turned = np.eye(4)
    turned[:3, :3] = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]  # the cylinder's axis along y
    turned[:3, 3] = (0.1, 0.2, 0.3)
    placed = turned.copy()
    placed[:3, 3] = turned[:3, 3] + turned[:3, :3] @ np.array(centre)
    pairs = ((sphere, placed), (cylinder, turned))
    (a, ta), (b, tb) = pairs if sphere_first else pairs[::-1]
    assert backend.distance(a, ta, b, tb) == pytest.approx(-depth, abs=1e-6)
    hit, measured = backend.collide(a, ta, b, tb)
    assert hit and measured == pytest.approx(depth, abs=1e-6)
    assert backend.nearest(a, ta, b, tb, hull=False)[0] == pytest.approx(-depth, abs=1e-6)


@pytest.mark.parametrize("name", ["coal", "fcl"])
def test_a_capsule_collides_as_itself_not_as_its_enclosing_cylinder(name: str) -> None:
    """Two capsules of radius 0.05 m and 0.2 m straight part, end to end and turned 90 degrees at
    one end: their enclosing cylinders' rims overlap; the capsules' hemispheres are 0.1 m
    centre to centre along the diagonal, so they clear by 0.0414 m."""
    backend = get_backend(name)
    capsule = Capsule(0.05, 0.3)  # measured as the enclosing cylinder: 0.3 m long
    assert capsule.straight_length == pytest.approx(0.2)
    a, b = backend.make(capsule), backend.make(capsule)
    cylinders = backend.make(Cylinder(0.05, 0.3)), backend.make(Cylinder(0.05, 0.3))
    ta, tb = np.eye(4), np.eye(4)
    # b lies along x, its near end-centre at (0.1, 0, 0.2): a's top end-centre is (0, 0, 0.1)
    tb[:3, :3] = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]
    tb[:3, 3] = (0.2, 0.0, 0.2)
    expected = float(np.hypot(0.1, 0.1)) - 0.1
    assert backend.distance(a, ta, b, tb) == pytest.approx(expected, abs=1e-5)  # GJK's tolerance
    assert backend.distance(cylinders[0], ta, cylinders[1], tb) < expected - 0.02  # the rims: far closer
    assert backend.collide(a, ta, b, tb) == (False, 0.0)


@pytest.mark.parametrize("name", ["coal", "fcl"])
def test_an_ellipsoid_collides_as_itself_not_as_its_enclosing_box(name: str) -> None:
    """An ellipsoid of semi-axes 0.1, 0.05, 0.05 m (a box marked ``ellipsoid``) and a sphere of
    0.02 m on the box's corner: the box holds the sphere's centre, the ellipsoid clears the
    sphere by 25.1 mm (the corner's distance to the ellipsoid, 45.1 mm by dense sampling of its
    surface, less the radius)."""
    backend = get_backend(name)
    ellipsoid = backend.make(Box((0.2, 0.1, 0.1), ellipsoid=True))
    box = backend.make(Box((0.2, 0.1, 0.1)))
    sphere = backend.make(Sphere(0.02))
    at = np.eye(4)
    at[:3, 3] = (0.1, 0.05, 0.05)  # on the box's corner
    assert backend.distance(box, np.eye(4), sphere, at) < 0.0
    assert backend.distance(ellipsoid, np.eye(4), sphere, at) == pytest.approx(0.02511, abs=1e-4)
    spheroid = backend.make(Cylinder(0.05, 0.2, ellipsoid=True))  # semi-axes 0.05, 0.05, 0.1 m
    tip = np.eye(4)
    tip[:3, 3] = (0.0, 0.0, 0.13)  # 0.03 m past the tip, less the sphere's radius: 0.01 m
    assert backend.distance(spheroid, np.eye(4), sphere, tip) == pytest.approx(0.01, abs=1e-4)


def test_the_same_object_can_be_both_arguments(backends) -> None:
    coal_backend, fcl_backend, made = backends
    shift = np.eye(4)
    shift[0, 3] = 0.3
    for backend, index in ((coal_backend, 0), (fcl_backend, 1)):
        box = made["box"][index]
        assert backend.distance(box, np.eye(4), box, shift) == pytest.approx(0.1)


def test_unknown_backend_names_the_choices() -> None:
    with pytest.raises(UsageError, match=r"invalid collision backend 'bullet'; valid choices: coal, fcl"):
        get_backend("bullet")


@pytest.mark.parametrize("pair", list(itertools.product(GEOMETRIES, repeat=2)), ids="-".join)
@pytest.mark.parametrize("hull", [True, False], ids=["hull", "shapes"])
def test_nearest_points_realise_the_distance(backends, pair: tuple[str, str], hull: bool) -> None:
    coal_backend, fcl_backend, made = backends
    (ca, fa), (cb, fb) = made[pair[0]], made[pair[1]]
    probe = coal_backend.make(Sphere(1e-9))
    measure = coal_backend.hull_distance if hull else coal_backend.distance

    def at(point: np.ndarray) -> np.ndarray:
        m = np.eye(4)
        m[:3, 3] = point
        return m

    rng = np.random.default_rng(sum(map(ord, "".join(pair))) + hull)
    checked = 0
    for _ in range(60):
        ta, tb = random_pose(rng, 0.03), random_pose(rng, 0.3)
        expected = measure(ca, ta, cb, tb)
        if expected < 1e-3:
            continue  # apart only: where they overlap the search checks collision instead
        checked += 1
        for backend, a, b in ((coal_backend, ca, cb), (fcl_backend, fa, fb)):
            d, pa, pb = backend.nearest(a, ta, b, tb, hull)
            # libccd's GJK in python-fcl is off by up to a few 1e-4 m on curved primitives
            assert d == pytest.approx(expected, abs=1e-3), backend.name
            assert np.linalg.norm(pb - pa) == pytest.approx(d, abs=1e-5), backend.name
            # each point is in the world frame, on its own shape: as far from the other shape
            # as the shapes are apart, and (nearly) touching its own
            assert measure(probe, at(pa), cb, tb) == pytest.approx(expected, abs=1e-3), backend.name
            assert measure(probe, at(pb), ca, ta) == pytest.approx(expected, abs=1e-3), backend.name
            assert measure(probe, at(pa), ca, ta) < 1e-3 and measure(probe, at(pb), cb, tb) < 1e-3, backend.name
    assert checked > 20


def test_a_mesh_too_fine_for_an_exact_hull_gets_bounded_sound_support() -> None:
    from geomcheck.collision.base import convex_hull, support_points
    from geomcheck.geometry.surface import ANALYSIS

    mesh = trimesh.creation.icosphere(subdivisions=6, radius=0.1)  # 40,962 vertices, all on the hull
    assert len(mesh.vertices) > ANALYSIS.hull_exact_points
    arrays = convex_hull(mesh)
    hull = trimesh.Trimesh(vertices=arrays.vertices, faces=arrays.faces, process=False)
    assert len(hull.vertices) < 4000
    assert hull.is_winding_consistent and hull.volume > 0.99 * 4.0 / 3.0 * np.pi * 0.1**3
    outer = trimesh.convex.convex_hull(support_points(mesh))
    offsets = np.einsum("ij,ij->i", outer.face_normals, outer.triangles[:, 0])
    # in blocks of vertices: all at once would be a 40,962 x faces matrix of several GB
    heights = [(block @ outer.face_normals.T - offsets).max() for block in np.array_split(mesh.vertices, 64)]
    assert float(max(heights)) <= 1e-9


@pytest.mark.parametrize("name", ["coal", "fcl"])
def test_a_flat_mesh_is_a_thin_solid_not_a_crash(name: str) -> None:
    """A marker plate drawn as one flat 6 cm square (Hello Robot Stretch's ArUco bases): its
    hull gets a micrometre's thickness. coal's own qhull call used to kill the process on it."""
    backend = get_backend(name)
    corners = np.array([[0.03, 0.03, 0.0], [0.03, -0.03, 0.0], [-0.03, 0.03, 0.0], [-0.03, -0.03, 0.0]])
    plate = backend.make(trimesh.Trimesh(corners, [[0, 1, 3], [0, 3, 2]], process=False))
    ball = backend.make(Sphere(0.01))
    above = np.eye(4)
    above[2, 3] = 0.05
    assert backend.distance(plate, np.eye(4), ball, above) == pytest.approx(0.04, abs=1e-5)
    beside = np.eye(4)
    beside[0, 3] = 0.045  # the sphere's edge 5 mm past the plate's +x side
    assert backend.distance(plate, np.eye(4), ball, beside) == pytest.approx(0.005, abs=1e-5)
    touching = np.eye(4)
    touching[2, 3] = 0.005
    assert backend.collide(plate, np.eye(4), ball, touching)[0]
