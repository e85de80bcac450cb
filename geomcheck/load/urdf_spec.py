"""The URDF core: which elements and attributes the specification defines where.

Source: the URDF XML specification (wiki.ros.org/urdf/XML) and urdfdom's parser. Elements
outside the core (``<gazebo>``, ``<transmission>``, sensors, namespaced elements) are
extensions and are not checked; inside the core, anything not listed here is a typo or an
extension in the wrong place and is reported (GC105/GC106) with the closest valid name.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass


@dataclass(frozen=True)
class ElementSpec:
    attributes: frozenset[str] = frozenset()
    children: frozenset[str] = frozenset()
    # children and attributes that are not URDF but are written there by well-known tools
    # or by older URDF versions: ignored quietly
    tolerated: frozenset[str] = frozenset()
    tolerated_attributes: frozenset[str] = frozenset()


def _spec(attributes: str = "", children: str = "", tolerated: str = "", tolerated_attributes: str = "") -> ElementSpec:
    return ElementSpec(
        frozenset(attributes.split()),
        frozenset(children.split()),
        frozenset(tolerated.split()),
        frozenset(tolerated_attributes.split()),
    )


SPEC: Mapping[str, ElementSpec] = {
    "robot": _spec("name version", "link joint material"),
    "link": _spec("name type", "inertial visual collision", tolerated="contact self_collision_checking"),
    "inertial": _spec("", "origin mass inertia"),
    "visual": _spec("name", "origin geometry material"),
    "collision": _spec("name group", "origin geometry", tolerated="verbose contact_coefficients"),
    # <geometry name> was written by 2009-era URDF tools (the PR2 of that year has it everywhere)
    # <capsule> is URDF 1.1 (the parser reads it by the file's version: GC129 in a 1.0 file)
    "geometry": _spec("", "box cylinder sphere mesh capsule", tolerated_attributes="name"),
    "material": _spec("name", "color texture"),
    "joint": _spec("name type", "origin parent child axis calibration dynamics limit mimic safety_controller"),
    "origin": _spec("xyz rpy quat_xyzw"),  # quat_xyzw: URDF 1.1
    "mass": _spec("value"),
    "inertia": _spec("ixx ixy ixz iyy iyz izz"),
    "box": _spec("size"),
    "cylinder": _spec("radius length"),
    "sphere": _spec("radius"),
    "capsule": _spec("radius length"),
    "mesh": _spec("filename scale"),
    "color": _spec("rgba"),
    "texture": _spec("filename"),
    "parent": _spec("link"),
    "child": _spec("link"),
    "axis": _spec("xyz"),
    # acceleration, deceleration and jerk: URDF 1.2, read by urdfdom whatever the file's version
    "limit": _spec("lower upper effort velocity", tolerated_attributes="acceleration deceleration jerk"),
    "mimic": _spec("joint multiplier offset"),
    "calibration": _spec("rising falling reference_position"),
    "dynamics": _spec("damping friction"),
    "safety_controller": _spec("soft_lower_limit soft_upper_limit k_position k_velocity"),
}

# Attributes that are not URDF but that a well-known tool writes on a core element and reads
# there: (element, attribute) -> the tool. They are extensions, not typos (no GC106), and a
# misspelling of one is offered the right name.
EXTENSION_ATTRIBUTES: Mapping[tuple[str, str], str] = {
    # Franka's joint friction model, written by franka_description (franka_ros) on every arm joint
    **{("dynamics", a): "Franka's franka_description" for a in ("D", "K", "mu_coulomb", "mu_viscous")},
    # PyBullet's URDF reader: a static triangle mesh instead of its convex hull, and a collision filter mask
    ("collision", "concave"): "PyBullet",
    ("collision", "mask"): "PyBullet",
    # Isaac Gym's URDF importer merges fixed joints unless the joint says dont_collapse="true"
    # (Unitree's and legged_gym's feet)
    ("joint", "dont_collapse"): "Isaac Gym",
}


def extension_attributes(element: str) -> frozenset[str]:
    """The attributes :data:`EXTENSION_ATTRIBUTES` knows on ``element``."""
    return frozenset(a for (e, a) in EXTENSION_ATTRIBUTES if e == element)


# Top-level elements are extensions unless they look like a misspelt core element.
TOP_LEVEL_CORE = ("link", "joint", "material")
TOP_LEVEL_SIMILARITY = 0.75  # difflib ratio above which a top-level element is taken as a typo [ratio]
DID_YOU_MEAN_CUTOFF = 0.6  # difflib ratio for suggestions [ratio]


def closest(name: str, choices: Iterable[str], cutoff: float = DID_YOU_MEAN_CUTOFF) -> str | None:
    """The choice most similar to ``name`` (difflib), or ``None``."""
    matches = difflib.get_close_matches(name, sorted(choices), n=1, cutoff=cutoff)
    return matches[0] if matches else None


def did_you_mean(name: str, choices: Iterable[str]) -> str:
    """``"; did you mean X?"`` or ``""``."""
    match = closest(name, choices)
    return f"; did you mean {match!r}?" if match else ""


# The versions urdfdom reads (``<robot version>``; absent is 1.0): 1.1 brought capsules and
# ``<origin quat_xyzw>``, 1.2 acceleration, deceleration and jerk limits
URDF_VERSIONS = ((1, 0), (1, 1), (1, 2))
FIRST_CAPSULE_VERSION = (1, 1)


def urdf_version(text: str) -> tuple[int, int] | str:
    """``(major, minor)`` of a ``<robot version>``, read as urdfdom reads it, or urdfdom's
    reason to refuse it (its own words)."""
    parts = text.split(".")
    if parts[-1] == "":  # urdfdom's split keeps no empty field after the last dot
        parts.pop()
    if len(parts) != 2:
        return "The version attribute should be in the form 'x.y'"
    out = []
    for part in parts:
        if not part:
            return "One of the fields of the version attribute is blank"
        digits = len(part) - len(part.lstrip("+-"))
        body = part[digits:]
        head = len(body) - len(body.lstrip("0123456789"))
        if head == 0 or digits > 1:
            return "Version attribute is not an integer"
        if head < len(body):
            return "Extra characters after the version number"
        value = int(part[: digits + head])
        if value < 0:
            return "Version number must be positive"
        out.append(value)
    return out[0], out[1]
