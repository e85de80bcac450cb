"""Values typed for "unknown": one ``<inertial>`` on every link, powers of ten, round tensors."""

from __future__ import annotations

import math

from geomcheck.checks.inertia.values import tensor_values, unique_links
from geomcheck.model import Inertial, Robot

ROUND_PRODUCTS = 1e-2  # products of inertia under this share of a round tensor's moments are negligible [ratio]
MIN_PLACEHOLDER_LINKS = 3  # this many links or more sharing one <inertial>, and no other: placeholders


def uniform_placeholder(robot: Robot) -> int:
    """How many links carry one identical ``<inertial>`` when every link that has one carries
    that same one and there are at least ``MIN_PLACEHOLDER_LINKS``, else 0: a real robot's
    parts never share mass, centre of mass and tensor; a macro's default values do."""
    written = [link.inertial for link in unique_links(robot) if link.inertial is not None]
    distinct = {(i.mass, i.origin.xyz, i.origin.rpy, *tensor_values(i)) for i in written}
    return len(written) if len(distinct) == 1 and len(written) >= MIN_PLACEHOLDER_LINKS else 0


def power_of_ten(value: float) -> bool:
    """Whether ``value`` is 10^k for an integer k (0.001, 1e-4, 0.1): a value typed for "unknown"."""
    if not (value > 0.0 and math.isfinite(value)):
        return False
    exponent = round(math.log10(value))
    return math.isclose(value, 10.0**exponent, rel_tol=1e-9)


def round_tensor(inertial: Inertial | None) -> bool:
    """Whether ``inertial`` pairs a computed mass (not a power of ten) with a round tensor: one power
    of ten on every axis, products negligible beside it (iCub's 0.01 kg m^2 on its light links, raised
    for stability, the CAD's products of 1e-7 kept)."""
    if inertial is None or power_of_ten(inertial.mass):
        return False
    moments = {inertial.ixx, inertial.iyy, inertial.izz}
    products = (inertial.ixy, inertial.ixz, inertial.iyz)
    # the products may keep the CAD's values, negligible beside the raised moments
    small = all(abs(v) <= ROUND_PRODUCTS * inertial.ixx for v in products)
    return len(moments) == 1 and power_of_ten(inertial.ixx) and small


def round_placeholder(inertial: Inertial | None) -> bool:
    """Whether ``inertial`` is a placeholder typed for "unknown": its mass and diagonal moments
    powers of ten and no products of inertia (a frame's 0.01 kg with 0.001 kg m^2 on each axis)."""
    if inertial is None:
        return False
    products = (inertial.ixy, inertial.ixz, inertial.iyz)
    moments = (inertial.ixx, inertial.iyy, inertial.izz)
    return all(v == 0.0 for v in products) and all(power_of_ten(v) for v in (inertial.mass, *moments))
