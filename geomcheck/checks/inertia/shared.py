"""GC507 for one tensor typed on many parts: a value written for every link, not computed for any.

A tensor copied from one link to another is a pair: each copy is its own finding, naming the
link it repeats. When one tensor is written by many ``<inertial>`` elements on parts of very
different masses (MuJoCo's TIAGo: ``diaginertia="0.4 0.4 0.4"`` on 29 bodies from 0.01 to
28 kg), nothing was copied from a part: one value was typed for all of them, and the
maintainer's change is one, computing every part's tensor. It is reported once, on the
lightest part (whose tensor is the most wrong), naming the others; the tensor-against-geometry
findings (GC505) of those parts restate the same mistake and are counted in it, not repeated.
A macro writing one tensor for four casters is one ``<inertial>`` element, not four.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from geomcheck.checks.inertia.tensor import tensor_groups
from geomcheck.checks.inertia.values import rounded, rounded_list, tensor_values, vector_text
from geomcheck.checks.wording import listed
from geomcheck.diagnostics import Diagnostic
from geomcheck.model import Link, Robot
from geomcheck.rules.inertia import COPIED_INERTIA, EXCEEDS_GEOMETRY
from geomcheck.thresholds import InertiaThresholds

LISTED = 5  # other links the grouped finding names in its message


@dataclass(frozen=True)
class SharedTensor:
    """Links (document order) whose ``<inertial>`` elements write one tensor."""

    links: tuple[Link, ...]
    sources: int  # distinct <inertial> elements (file and line) writing it

    @property
    def names(self) -> frozenset[str]:
        return frozenset(link.name for link in self.links)


def shared_tensors(robot: Robot, copies: Mapping[str, Link], th: InertiaThresholds) -> list[SharedTensor]:
    """The tensors copied onto parts of other masses (``copies``, :func:`find_copies`) by
    ``th.shared_tensor_sources`` or more ``<inertial>`` elements, with every link writing them."""
    out = []
    for members in tensor_groups(robot).values():
        # copies written by that many elements: a frame's placeholder that one copy shares with
        # twenty frames of the same mass stays that copy's finding
        copied = {_source(link) for link in members if link.name in copies}
        if len(copied) >= th.shared_tensor_sources:
            out.append(SharedTensor(tuple(members), len({_source(link) for link in members})))
    return out


def _source(link: Link) -> tuple[str, ...]:
    assert link.inertial is not None
    loc = link.inertial.location or link.location
    if loc is None or loc.line is None:
        return ("link", link.name)
    return (str(loc.file), str(loc.line), str(loc.column))


def grouped(diagnostics: Iterable[Diagnostic], shared: list[SharedTensor]) -> list[Diagnostic]:
    """``diagnostics`` with the GC507 and GC505 findings of each shared tensor's links replaced by
    one GC507 for the tensor, at the place of the first of them and at their highest severity."""
    out = list(diagnostics)
    for group in shared:
        absorbed = [d for d in out if d.link in group.names and d.code in (COPIED_INERTIA.code, EXCEEDS_GEOMETRY.code)]
        if not any(d.code == COPIED_INERTIA.code for d in absorbed):
            continue
        finding = _finding(group, absorbed)
        at = out.index(absorbed[0])
        out = [d for d in out if d not in absorbed]
        out.insert(at, finding)
    return out


def _finding(group: SharedTensor, absorbed: list[Diagnostic]) -> Diagnostic:
    def mass(link: Link) -> float:
        assert link.inertial is not None
        return link.inertial.mass

    lightest = min(group.links, key=lambda link: (mass(link), link.name))
    heaviest = min(group.links, key=lambda link: (-mass(link), link.name))
    assert lightest.inertial is not None
    others = sorted(link.name for link in group.links if link is not lightest)
    exceeding = sorted({d.link for d in absorbed if d.code == EXCEEDS_GEOMETRY.code and d.link})
    ratio = mass(heaviest) / mass(lightest) if mass(lightest) > 0.0 else float("inf")
    names = listed(others, LISTED)
    message = COPIED_INERTIA.message(
        "shared",
        tensor=vector_text(tensor_values(lightest.inertial)),
        count=len(group.links),
        written="" if group.sources == len(group.links) else f" (by {group.sources} <inertial> elements)",
        mass=mass(lightest),
        link=lightest.name,
        reference_mass=mass(heaviest),
        reference=heaviest.name,
        ratio=ratio,
        listed=names,
    )
    if exceeding:
        message += COPIED_INERTIA.message("shared_exceeding", exceeding=len(exceeding))
    severity = max((d.severity for d in absorbed), key=lambda s: s.rank)
    return COPIED_INERTIA.diagnose(
        message,
        link=lightest.name,
        about="inertia",
        location=lightest.inertial.location or lightest.location,
        severity=severity,
        data={
            "copied_from": heaviest.name,
            "mass": rounded(mass(lightest)),
            "reference_mass": rounded(mass(heaviest)),
            "mass_ratio": rounded(ratio),
            "tensor": rounded_list(tensor_values(lightest.inertial)),
            "also": others,
            "shared_sources": group.sources,
            "exceeds_geometry": exceeding,
        },
    )
