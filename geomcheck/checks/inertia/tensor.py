"""GC503, GC504 and GC507: the inertia tensor on its own, and one copied onto a part of another mass."""

from __future__ import annotations

import math

import numpy as np

from geomcheck.checks.inertia.values import rounded, rounded_list, tensor_values, unique_links, vector_text
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.geometry.inertia import (
    MassProperties,
)
from geomcheck.model import Link, Robot, SourceLocation
from geomcheck.rules.inertia import (
    COPIED_INERTIA,
    NOT_POSITIVE_DEFINITE,
    TRIANGLE_INEQUALITY,
)
from geomcheck.thresholds import InertiaThresholds


def tensor_diagnostics(
    link: Link, props: MassProperties, moves: bool, th: InertiaThresholds, loc: SourceLocation | None
) -> tuple[list[Diagnostic], bool]:
    """GC503 and GC504 on the tensor alone; also whether the triangle inequality holds."""
    out = []
    moments = props.moments
    text = ", ".join(f"{m:.4g}" for m in moments)
    data = {"principal_moments": rounded_list(moments), "mass": rounded(props.mass)}
    if not props.positive_definite:
        semidefinite = props.positive_semidefinite
        severity = Severity.WARNING if semidefinite and not moves else None
        kind = NOT_POSITIVE_DEFINITE.message(
            "zero" if not np.any(moments) else "semidefinite" if semidefinite else "negative"
        )
        out.append(
            NOT_POSITIVE_DEFINITE.diagnose(
                NOT_POSITIVE_DEFINITE.message(kind=kind, moments=text),
                link=link.name,
                about="inertia",
                location=loc,
                data=data | {"point_mass": bool(not np.any(moments))},
                severity=severity,
            )
        )
    a, b, c = moments
    triangle_ok = props.triangle_excess <= th.relative_tolerance * props.scale
    if props.positive_semidefinite and not triangle_ok:
        out.append(
            TRIANGLE_INEQUALITY.diagnose(
                TRIANGLE_INEQUALITY.message(a=a, b=b, sum=a + b, c=c),
                link=link.name,
                about="inertia",
                location=loc,
                data={**data, "excess": rounded(props.triangle_excess)},
            )
        )
    return out, triangle_ok


def tensor_groups(robot: Robot) -> dict[tuple[float, ...], list[Link]]:
    """Links (document order) by the six values of their written tensor; zero and non-finite
    tensors and masses left out (GC503 and GC502 report those)."""
    groups: dict[tuple[float, ...], list[Link]] = {}
    for link in unique_links(robot):
        inertial = link.inertial
        if inertial is None:
            continue
        values = tensor_values(inertial)
        if not all(math.isfinite(v) for v in values) or not any(values) or not math.isfinite(inertial.mass):
            continue
        groups.setdefault(values, []).append(link)
    return groups


def find_copies(robot: Robot, th: InertiaThresholds) -> dict[str, Link]:
    """Links whose written tensor equals another link's while the masses differ by
    ``copied_inertia_mass_ratio`` or more, mapped to that other link.

    Among the links sharing a tensor the reference is the heaviest, ties broken by name: the
    same whatever the order of the ``<link>`` elements (the tensor of the heavier part is
    usually the original; copied onto a lighter part it gives radii of gyration too large).
    """
    out: dict[str, Link] = {}
    for members in tensor_groups(robot).values():
        if len(members) < 2:
            continue
        reference = min(members, key=lambda m: (-m.inertial.mass if m.inertial else 0.0, m.name))
        assert reference.inertial is not None
        for link in members:
            assert link.inertial is not None
            masses = sorted((link.inertial.mass, reference.inertial.mass))
            if link is not reference and masses[0] > 0.0 and masses[1] / masses[0] >= th.copied_inertia_mass_ratio:
                out[link.name] = reference
    return out


def copied_diagnostic(link: Link, reference: Link, location: SourceLocation | None) -> Diagnostic:
    assert link.inertial is not None and reference.inertial is not None
    mass, ref_mass = link.inertial.mass, reference.inertial.mass
    ratio = max(mass, ref_mass) / min(mass, ref_mass)
    values = tensor_values(link.inertial)
    return COPIED_INERTIA.diagnose(
        COPIED_INERTIA.message(
            tensor=vector_text(values), reference=reference.name, ratio=ratio, mass=mass, reference_mass=ref_mass
        ),
        link=link.name,
        about="inertia",
        location=location,
        data={
            "copied_from": reference.name,
            "mass": rounded(mass),
            "reference_mass": rounded(ref_mass),
            "mass_ratio": rounded(ratio),
            "tensor": rounded_list(values),
        },
    )
