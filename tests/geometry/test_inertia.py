"""Mass properties and the bounds a link's geometry puts on them (geomcheck.geometry.inertia)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from geomcheck.geometry.inertia import (
    combined,
    convex_hull,
    distance_outside,
    exceedance,
    geometry_bounds,
    mass_properties,
    principal_axes,
    reach,
)
from geomcheck.model import Inertial, Pose

WHEEL_RADIUS = 0.079  # [m]
WHEEL_WIDTH = 0.034  # [m]
WHEEL_MASS = 0.44036  # [kg]


def cylinder_inertial(mass: float, radius: float, length: float, axis: str, xyz=(0.0, 0.0, 0.0)) -> Inertial:
    """Solid cylinder of ``length`` along ``axis`` ('x', 'y' or 'z'), about its centre."""
    along = mass * radius**2 / 2
    across = mass * (3 * radius**2 + length**2) / 12
    moments = {a: (along if a == axis else across) for a in "xyz"}
    return Inertial(mass, Pose(xyz), ixx=moments["x"], iyy=moments["y"], izz=moments["z"])


def wheel_points() -> np.ndarray:
    """Vertices of a wheel of radius 0.079 m, width 0.034 m, axis y, shape (n, 3) [m]."""
    mesh = trimesh.creation.cylinder(radius=WHEEL_RADIUS, height=WHEEL_WIDTH, sections=64)
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1.0, 0.0, 0.0)))
    return np.asarray(mesh.vertices)


def test_principal_axes_sorted_with_stable_signs() -> None:
    moments, axes = principal_axes(np.diag([3.0, 1.0, 2.0]))
    assert moments.tolist() == [1.0, 2.0, 3.0]
    assert np.allclose(axes, [[0, 0, 1], [1, 0, 0], [0, 1, 0]])
    flipped_moments, flipped_axes = principal_axes(-np.diag([3.0, 1.0, 2.0]) * -1)
    assert np.array_equal(flipped_axes, axes)
    assert np.array_equal(flipped_moments, moments)


def test_mass_properties_rotate_the_tensor_into_the_link_frame() -> None:
    # A rod along the inertial frame's x axis, turned 90 degrees about z: along the link's y axis.
    inertial = Inertial(2.0, Pose((0.1, 0.2, 0.3), (0.0, 0.0, np.pi / 2)), ixx=0.001, iyy=0.05, izz=0.05)
    props = mass_properties(inertial)
    assert props.com.tolist() == [0.1, 0.2, 0.3]
    assert np.allclose(np.diag(props.tensor), [0.05, 0.001, 0.05])
    assert np.allclose(props.moments, [0.001, 0.05, 0.05])
    assert np.allclose(np.abs(props.axes[:, 0]), [0.0, 1.0, 0.0])


@pytest.mark.parametrize(
    ("values", "pd", "psd"),
    [
        ((0.01, 0.0, 0.0, 0.01, 0.0, 0.01), True, True),
        ((0.01, 0.0, 0.0, 0.01, 0.0, 0.0), False, True),  # a rod: one zero moment
        ((0.01, 0.02, 0.0, 0.01, 0.0, 0.01), False, False),  # moments -0.01, 0.01, 0.03
    ],
)
def test_definiteness(values: tuple[float, ...], pd: bool, psd: bool) -> None:
    ixx, ixy, ixz, iyy, iyz, izz = values
    props = mass_properties(Inertial(1.0, Pose(), ixx, ixy, ixz, iyy, iyz, izz))
    assert props.positive_definite is pd
    assert props.positive_semidefinite is psd


def test_triangle_excess_is_c_minus_a_plus_b() -> None:
    props = mass_properties(Inertial(1.0, Pose(), ixx=0.001, iyy=0.002, izz=0.01))
    assert props.triangle_excess == pytest.approx(0.007)
    assert mass_properties(cylinder_inertial(1.0, 0.1, 0.01, "z")).triangle_excess < 0.0


def test_reach_of_a_cylinder_from_its_axis_and_mid_plane() -> None:
    axis_reach, plane_reach = reach(wheel_points(), np.zeros(3), np.eye(3))
    assert axis_reach[1] == pytest.approx(WHEEL_RADIUS)
    assert plane_reach[1] == pytest.approx(WHEEL_WIDTH / 2)
    assert axis_reach[0] == pytest.approx(np.hypot(WHEEL_RADIUS, WHEEL_WIDTH / 2))
    assert plane_reach[0] == pytest.approx(WHEEL_RADIUS)


def test_solid_wheel_is_within_its_geometry() -> None:
    props = mass_properties(cylinder_inertial(WHEEL_MASS, WHEEL_RADIUS, WHEEL_WIDTH, "y"))
    bounds = geometry_bounds(props, wheel_points())
    assert bounds.labels[3:] == ("link x axis", "link y axis", "link z axis")
    assert bounds.moment_bound[4] == pytest.approx(WHEEL_MASS * WHEEL_RADIUS**2)
    assert (exceedance(bounds.moments, bounds.moment_bound) <= 1.0).all()
    assert (exceedance(bounds.spread, bounds.spread_bound) <= 1.0).all()
    # spread along the axis of a solid cylinder: m h^2 / 12
    assert bounds.spread[4] == pytest.approx(WHEEL_MASS * WHEEL_WIDTH**2 / 12)


def test_pr2_wheel_tensor_exceeds_the_wheel() -> None:
    tensor = (0.012411765597, -0.000711733678, 0.00050272983, 0.015218160428, -0.000004273467, 0.011763977943)
    inertial = Inertial(WHEEL_MASS, Pose(), *tensor)
    bounds = geometry_bounds(mass_properties(inertial), wheel_points())
    gyration = np.sqrt(bounds.moments[:3] / WHEEL_MASS)
    assert gyration.min() > 2 * WHEEL_RADIUS
    assert exceedance(bounds.moments, bounds.moment_bound).min() > 3.9  # moments over 3.9 times the bound


def test_tensor_for_the_wrong_axis_breaks_only_the_spread_bound() -> None:
    # Solid-cylinder inertia computed for an axis along z, on a wheel whose axis is y.
    props = mass_properties(cylinder_inertial(WHEEL_MASS, WHEEL_RADIUS, WHEEL_WIDTH, "z"))
    bounds = geometry_bounds(props, wheel_points())
    assert (exceedance(bounds.moments, bounds.moment_bound) <= 1.0).all()
    spread = exceedance(bounds.spread, bounds.spread_bound)
    assert spread[4] > 5.0  # along the link's y axis: r^2/4 of spread in a 17 mm half-width
    assert spread[3] <= 1.0


def test_exceedance_of_zero_bounds() -> None:
    ratio = exceedance(np.array([0.0, 1.0, 2.0, -1.0]), np.array([0.0, 0.0, 4.0, 1.0]))
    assert ratio.tolist() == [0.0, np.inf, 0.5, 0.0]


def test_distance_outside_the_hull_of_a_cube() -> None:
    hull = convex_hull(np.asarray(trimesh.creation.box(extents=(1.0, 1.0, 1.0)).vertices))
    assert hull.volume == pytest.approx(1.0)
    assert distance_outside(hull, np.array([0.2, -0.3, 0.1])) == 0.0
    assert distance_outside(hull, np.array([1.5, 0.0, 0.0])) == pytest.approx(1.0)
    assert distance_outside(hull, np.array([1.5, 1.5, 1.5])) == pytest.approx(np.sqrt(3.0))


def test_distance_outside_the_hull_of_a_disc() -> None:
    # The corner of a disc's bounding box is outside the disc: the hull sees it, a box would not.
    hull = convex_hull(wheel_points())
    corner = np.array([WHEEL_RADIUS, 0.0, WHEEL_RADIUS]) * 0.95
    assert distance_outside(hull, corner) == pytest.approx(np.hypot(*corner[[0, 2]]) - WHEEL_RADIUS, abs=5e-4)


def test_flat_geometry_falls_back_to_its_bounding_box() -> None:
    square = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]])
    hull = convex_hull(square)
    assert hull.volume == 0.0
    assert distance_outside(hull, np.array([0.5, 0.5, 0.0])) == 0.0
    assert distance_outside(hull, np.array([0.5, 0.5, 0.25])) == pytest.approx(0.25)


def test_combined_parts_are_the_solid_they_make() -> None:
    # two 0.1 m cubes of 2 kg side by side along x, centres at x = 0.05 and 0.15 (an L of frames does
    # not matter: the parts are given in one frame) make a 0.2 x 0.1 x 0.1 m box of 4 kg centred on x = 0.1
    a, m = 0.1, 2.0
    cube = np.eye(3) * m * a * a / 6
    body = combined([(m, np.array([0.05, 0.0, 0.0]), cube), (m, np.array([0.15, 0.0, 0.0]), cube)])
    box = trimesh.creation.box(extents=(2 * a, a, a))
    box.density = 2 * m / box.volume
    assert body.mass == pytest.approx(4.0)
    assert body.com == pytest.approx([0.1, 0.0, 0.0])
    assert body.tensor == pytest.approx(box.moment_inertia, abs=1e-12)
    assert body.moments == pytest.approx([4 * (2 * a * a) / 12, 4 * (5 * a * a) / 12, 4 * (5 * a * a) / 12])
