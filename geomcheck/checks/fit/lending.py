"""Elements lent across a joint: an element lying on a neighbour's mesh rather than its own link's (GC303),
and the spheres that close a link's capsules."""

from __future__ import annotations

import numpy as np

from geomcheck.checks import CheckContext
from geomcheck.checks.fit.shapes import link_visual
from geomcheck.checks.fit.verdicts import _element_diagnostic
from geomcheck.checks.wording import length
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.geometry.elements import CollisionElement, VisualCloud, mm
from geomcheck.geometry.fit import ElementFit, LinkFit
from geomcheck.geometry.neighbours import invariant, neighbours
from geomcheck.model import Cylinder, Link, Shape, Sphere, kind_name
from geomcheck.rules import fit as rules
from geomcheck.thresholds import FitThresholds


def lent_to(ctx: CheckContext, link: Link, element: CollisionElement, th: FitThresholds) -> str | None:
    """The neighbour whose mesh ``element`` covers instead of its own link's, if any: an
    element placed across a joint, the same at every joint position (Franka's capsules)."""
    for n in neighbours(ctx.robot, link.name):
        if not invariant(element, n):
            continue
        cloud = link_visual(ctx, ctx.robot.link_map[n.link], th)
        if not isinstance(cloud, VisualCloud):
            continue
        theirs = cloud.samples @ n.rotation.T + n.translation
        if np.mean(element.signed_distance(theirs) <= th.protrusion_tolerance_m) >= th.offset_overlap_fraction:
            return n.link
    return None


def caps_a_capsule(element: CollisionElement, elements: list[CollisionElement], tolerance: float) -> bool:
    """Whether ``element`` is a sphere that closes a capsule of its own link: centred on an end
    of the axis of one of the link's cylinders, with that cylinder's radius (within
    ``tolerance`` [m]). URDF has no capsule; it is written as a cylinder and two such spheres
    (Franka's collision model), and a cap's reach past the link's mesh is the capsule's rounded
    end, placed with the cylinder: the cap is judged with its capsule (through the cylinder's
    own fit), not as an element lying on a neighbour's mesh."""
    if not isinstance(element.primitive, Sphere):
        return False
    radius = element.primitive.radius
    for other in elements:
        cylinder = other.primitive
        if other is element or not isinstance(cylinder, Cylinder) or abs(cylinder.radius - radius) > tolerance:
            continue
        half = 0.5 * cylinder.length * np.asarray(other.rotation, dtype=float)[:, 2]
        centre = np.asarray(other.translation, dtype=float)
        ends = (centre + half, centre - half)
        if any(np.linalg.norm(np.asarray(element.translation, dtype=float) - end) <= tolerance for end in ends):
            return True
    return False


def _lent(link: Link, shape: Shape, f: ElementFit, neighbour: str, link_fit: LinkFit, th: FitThresholds) -> Diagnostic:
    """GC303 for an element that lies on a neighbour's mesh rather than its own link's: it
    makes the link collide where the link is not, whatever covers the link's mesh."""
    kind = kind_name(shape.geometry)
    inside = f.in_hull if f.in_hull is not None else f.mesh_inside
    covered = link_fit.coverage >= th.min_coverage and link_fit.protrusion_max <= th.protrusion_tolerance_m
    message = rules.COLLISION_OFFSET.message(
        "lent",
        label=shape.label,
        kind=kind,
        link=link.name,
        outside=1.0 - inside,
        neighbour=neighbour,
        link_coverage=link_fit.coverage,
        link_protrusion_max=length(link_fit.protrusion_max),
    )
    data = {
        "element": f.element.type,
        "covers_neighbour": neighbour,
        "outside_own_mesh": round(1.0 - inside, 4),
        "link_coverage": round(link_fit.coverage, 4),
        "link_protrusion_max_mm": mm(link_fit.protrusion_max),
        "tolerance": th.protrusion_tolerance_m,
        "disjoint": True,
        "multi": True,
    }
    if covered:
        fix = (
            f"Move {shape.label} to link {neighbour} (its mesh is where the element is), or onto the part of "
            f"link {link.name} it should cover."
        )
        severity = Severity.WARNING
    else:
        # the element stands for the neighbour's part at every joint position (a motor on the joint's axis,
        # carried by this link): moving it would uncover that part; what is missing is this link's own
        fix = (
            f"Keep {shape.label} if it stands for a part of {neighbour} carried by link {link.name} (a motor on "
            f"the joint's axis: it takes the same space at every joint position), and give link {link.name}'s "
            "own mesh collision geometry of its own; otherwise move it onto that mesh."
        )
        severity = Severity.WARNING
    return _element_diagnostic(rules.COLLISION_OFFSET, link, shape, message, data, fix, severity)
