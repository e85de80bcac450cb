"""GC506: a centre of mass outside its part; GC511: one inside it but where no real part has it.

GC511 looks for two signs of a centre of mass that was never computed for the part, judged against the centroid of
the part's geometry (its convex hull taken as solid, uniform density) and the part's size:

- written as the link origin, ``0 0 0``, what a template leaves, while the part's geometry centres
  at least `com_origin_fraction` (a third) of its extent away (a finger's centre of mass at its
  joint, the phalanx reaching away from it);
- two of its coordinates swapped: exchanged back, it lands at least `com_swap_gain` (3) times
  nearer the centroid, from at least `com_swap_fraction` (a fifth) of the part's extent away.
"""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np

from geomcheck.checks.inertia.values import metres_list, rounded, rounded_list, vector_text
from geomcheck.checks.wording import listed
from geomcheck.diagnostics import Diagnostic
from geomcheck.geometry.hull_cache import stored_solid_hull
from geomcheck.geometry.inertia import Hull, MassProperties
from geomcheck.model import Link, SourceLocation
from geomcheck.rules.inertia import COM_MISPLACED, COM_OUTSIDE
from geomcheck.thresholds import InertiaThresholds

AXES = "xyz"
LISTED = 5  # other links a grouped finding names in its message


def com_diagnostic(
    link: Link, props: MassProperties, hull: Hull, distance: float, loc: SourceLocation | None
) -> Diagnostic:
    spans = ", ".join(f"{a} {lo:.3f}..{hi:.3f}" for a, lo, hi in zip("xyz", hull.lower, hull.upper, strict=True))
    return COM_OUTSIDE.diagnose(
        COM_OUTSIDE.message(com=vector_text(props.com), distance=distance, bounds=spans),
        link=link.name,
        about="com",
        location=loc,
        data={
            "com": rounded_list(props.com),
            "distance": rounded(distance),
            "bounds": [metres_list(hull.lower), metres_list(hull.upper)],
        },
    )


def misplaced_com(
    link: Link, props: MassProperties, points: np.ndarray, th: InertiaThresholds, loc: SourceLocation | None
) -> Diagnostic | None:
    """GC511 for ``link`` whose centre of mass ``props.com`` lies inside its geometry ``points``
    (n, 3, link frame) but at the link origin or with two coordinates swapped (see the module)."""
    solid = stored_solid_hull(points)
    if solid is None or link.inertial is None:
        return None
    centroid = np.asarray(solid.center_mass, dtype=float)
    size = float(np.ptp(points, axis=0).max())
    if size <= 0.0:
        return None
    com = np.asarray(props.com, dtype=float)
    off = float(np.linalg.norm(com - centroid))
    data = {
        "com": [round(float(v), 9) + 0.0 for v in com],
        "centroid": [round(float(v), 9) + 0.0 for v in centroid],
        "distance": round(off, 9),
        "size": round(size, 9),
    }
    written = link.inertial.origin.xyz
    if not any(written) and off >= th.com_origin_fraction * size:
        return COM_MISPLACED.diagnose(
            COM_MISPLACED.message("origin", distance=off * 1000, centroid=_text(centroid), share=off / size),
            link=link.name,
            about="com",
            location=loc,
            data=data | {"swapped": None},
        )
    if off < th.com_swap_fraction * size:
        return None
    for i, j in itertools.combinations(range(3), 2):
        swapped = com.copy()
        swapped[[i, j]] = swapped[[j, i]]
        nearer = float(np.linalg.norm(swapped - centroid))
        if nearer * th.com_swap_gain <= off:
            pair = f"{AXES[i]}{AXES[j]}"
            return COM_MISPLACED.diagnose(
                COM_MISPLACED.message(
                    "swapped", a=AXES[i], b=AXES[j], distance=off * 1000, nearer=nearer * 1000, swapped=_text(swapped)
                ),
                link=link.name,
                about="com",
                location=loc,
                data=data | {"swapped": pair},
            )
    return None


def template_origins(findings: list[Diagnostic], least: int) -> list[Diagnostic]:
    """``findings`` with the GC511 findings of centres of mass left at the link origin reported
    once when ``least`` links or more share that pattern: one template left unfilled, the first
    finding naming the others (``also``)."""
    origins = [d for d in findings if d.code == COM_MISPLACED.code and d.data.get("swapped") is None]
    if len(origins) < least:
        return findings
    # the link named first stands for the group, whatever the order of the file
    first = min(origins, key=lambda d: d.link or "")
    others = sorted(d.link or "" for d in origins if d is not first)
    names = listed(others, LISTED)
    grouped = replace(
        first,
        message=f"{first.message} (also in {names}: {len(origins)} links left at the template's origin)",
        data={**first.data, "also": others},
    )
    return [grouped if d is first else d for d in findings if d is first or d not in origins]


def _text(v: np.ndarray) -> str:
    # to a nanometre: a centroid on an axis reads 0, not a solver's 5.7e-18
    return "(" + ", ".join(f"{round(float(c), 9) + 0.0:.4g}" for c in v) + ")"
