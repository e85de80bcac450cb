"""GC501, GC502 and GC508: a moving link without mass, a mass that is not one, a density no material has."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

from geomcheck.checks.inertia.bodies import Body
from geomcheck.checks.inertia.values import moving_joint, rounded, tensor_values, unique_links
from geomcheck.checks.wording import listed
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.model import Joint, Link, Mesh, Robot, SourceLocation
from geomcheck.rules.inertia import (
    IMPLAUSIBLE_DENSITY,
    MISSING_INERTIAL,
    NON_POSITIVE_MASS,
)
from geomcheck.thresholds import InertiaThresholds

GRAMS_PER_KG = 1000.0
ALUMINIUM_KG_M3 = 2700.0  # the metal of most robot links' shells [kg/m^3]
STEEL_KG_M3 = 7850.0  # of shafts, gears and motors [kg/m^3]
PLAUSIBLE_MIN_DENSITY_KG_M3 = 100.0  # lighter than foam-filled plastic parts: not a real average [kg/m^3]


def mass_diagnostics(
    link: Link, joint: Joint | None, body: Body, th: InertiaThresholds, loc: SourceLocation | None
) -> list[Diagnostic]:
    """GC502 for a negative or non-finite mass anywhere, or a non-positive one on a moving
    link whose body (the link and the links fixed below it) has no mass either."""
    assert link.inertial is not None
    mass = link.inertial.mass
    data: dict[str, Any] = {"mass": rounded(mass), "min_mass_kg": th.min_mass_kg}
    if not math.isfinite(mass):
        message = NON_POSITIVE_MASS.message("not_finite", mass=mass)
    elif mass < 0.0:
        message = NON_POSITIVE_MASS.message("negative", mass=mass)
    elif joint is not None and mass <= th.min_mass_kg and body.mass <= th.min_mass_kg:
        message = NON_POSITIVE_MASS.message("moving", mass=mass, joint_type=joint.type, joint=joint.name)
        if body.merged:
            message += NON_POSITIVE_MASS.message("body", links=body.others_text(link.name))
            data["body_links"] = body.others(link.name)
    elif mass == 0.0 and any(v != 0.0 for v in tensor_values(link.inertial)):
        # rotational inertia is mass times squared distance: none without mass; consumers that merge the
        # link add a tensor with no mass to its body
        largest = max(abs(v) for v in tensor_values(link.inertial))
        message = NON_POSITIVE_MASS.message("massless_tensor", largest=largest)
        # a massless link is a frame, or a root PyBullet keeps static: its tensor is what is wrong
        fix = (
            "Delete the tensor (zero inertia) if the link is meant to be massless (a frame, or a root a simulator "
            "keeps static), or give the link its real mass in kilograms."
        )
        return [
            NON_POSITIVE_MASS.diagnose(
                message, link=link.name, about="mass", location=loc, data=data, severity=Severity.WARNING, help=fix
            )
        ]
    else:
        return []
    return [NON_POSITIVE_MASS.diagnose(message, link=link.name, about="mass", location=loc, data=data)]


def missing_diagnostic(link: Link, joint: Joint, body: Body) -> Diagnostic:
    message = MISSING_INERTIAL.message(joint_type=joint.type, joint=joint.name)
    data: dict[str, Any] = {"joint": joint.name, "joint_type": joint.type}
    if body.merged:
        message += MISSING_INERTIAL.message("body", links=body.others_text(link.name))
        data["body_links"] = body.others(link.name)
    return MISSING_INERTIAL.diagnose(message, link=link.name, about="mass", location=link.location, data=data)


def missing_once(found: list[Diagnostic]) -> list[Diagnostic]:
    """``found`` with the GC501 findings of several moving links (above info) reported once, on
    the first, naming the others, which stay as info saying so: inertials left out together are
    one omission (Schunk's SVH hand: 13 of its 20 moving links without one, its fingertips with)."""
    loud = [d for d in found if d.code == MISSING_INERTIAL.code and d.link and d.severity is not Severity.INFO]
    if len(loud) < 2:
        return found
    first, others = loud[0], loud[1:]
    names = listed([d.link or "" for d in others], 5)
    message = first.message + MISSING_INERTIAL.message("others", count=len(others), links=names)
    grouped = replace(first, message=message, data={**first.data, "also_links": [d.link for d in others]})
    note = MISSING_INERTIAL.message("reported_with", link=first.link)
    ids = {id(d) for d in others}
    return [grouped if d is first else d.grouped_under(first, note) if id(d) in ids else d for d in found]


def kinematics_only_diagnostic(robot: Robot) -> Diagnostic | None:
    """One GC501 (info) for a description in which no link has an ``<inertial>``: written for
    planning and display (MoveIt, RViz), not for simulation, on purpose. ``None`` when some
    link has one, or nothing moves."""
    if any(link.inertial is not None for link in robot.links):
        return None
    moving = [link.name for link in unique_links(robot) if moving_joint(robot, link) is not None]
    if not moving:
        return None
    return MISSING_INERTIAL.diagnose(
        MISSING_INERTIAL.message("kinematics_only", count=len(moving)),
        help="Nothing to change for planning and display. To simulate the robot, give every moving link an "
        "<inertial> (mass, centre of mass and tensor from CAD, or the formulas of a box, cylinder or sphere "
        "enclosing the part).",
        about="mass",
        severity=Severity.INFO,
        data={"moving_links": len(moving)},
    )


def density_diagnostic(
    link: Link, mass: float, volume: float, th: InertiaThresholds, loc: SourceLocation | None
) -> Diagnostic:
    density = mass / volume
    as_grams = mass / GRAMS_PER_KG
    # A mass written in grams reads as a number of a real part (>= 1) and gives a density of real material.
    if mass >= 1.0 and PLAUSIBLE_MIN_DENSITY_KG_M3 <= density / GRAMS_PER_KG <= th.max_density_kg_m3:
        hint = f"The mass looks like grams: {as_grams:.6g} kg would give {density / GRAMS_PER_KG:.4g} kg/m^3. "
    elif any(isinstance(shape.geometry, Mesh) for shape in (*link.visuals, *link.collisions)):
        # the link draws its part: the mass is what is wrong (a placeholder typed on every link of a hand)
        hint = (
            f"The link's meshes draw the part, so the mass is wrong for it: its hull would weigh "
            f"{volume * ALUMINIUM_KG_M3:.3g} kg of aluminium, {volume * STEEL_KG_M3:.3g} kg of steel. "
        )
    else:
        hint = "If the link's shapes are placeholders smaller than the part, give it its real geometry. "
    return IMPLAUSIBLE_DENSITY.diagnose(
        IMPLAUSIBLE_DENSITY.message(
            mass=mass,
            volume=volume,
            density=density,
            times=density / th.max_density_kg_m3,
            max_density=th.max_density_kg_m3,
        ),
        help=hint + IMPLAUSIBLE_DENSITY.fix,
        link=link.name,
        about="mass",
        location=loc,
        data={"mass": rounded(mass), "hull_volume": rounded(volume), "density": rounded(density)},
    )
