"""Reference parsers' own test cases run through geomcheck: the reference's verdict and facts
against geomcheck's.

A :class:`Case` is one test of urdfdom's or libsdformat's own suite (NOTICE.md names the
sources): the file the test loads, transcribed, what the reference does with it (``load`` or
``refuse``), the problem a refusal names (a regular expression) and the facts the test asserts
that geomcheck's JSON report shows (``Fact``: a path into the report and the value).

geomcheck's verdict is read from its report as a user reads it: it *refuses* a file when loading
it fails (an input error, exit 2) or when a GC1xx finding of error severity says the format's
own parser refuses it (one without ``accepted_by``: a finding on a file the parser loads names
that parser in ``accepted_by``). A refused case agrees when geomcheck refuses it, or reports an
error finding of another family, naming the problem (an inertia the parser refuses as invalid is a
GC5xx error); a loaded case agrees when geomcheck loads it with no such claim and every fact
holds.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import geomcheck
from geomcheck.errors import GeomcheckError
from geomcheck.report.json_format import render

Verdict = Literal["load", "refuse"]
SELECTED = ("GC1", "GC502", "GC503", "GC504")  # structure, and the mass and inertia a parser refuses as invalid
TOLERANCE = 1e-6  # [m, rad, kg, kg m^2]: the references compare to 1e-9 or 1e-5, written values to 1e-6


@dataclass(frozen=True)
class Fact:
    """``path`` (words separated by spaces, see :func:`look_up`) and the value the reference asserts."""

    path: str
    value: Any


@dataclass(frozen=True)
class Case:
    """One reference test: ``source`` file and ``test`` name, the ``asset`` it loads (``None``
    for a string in the test), the reference's ``verdict``, the ``problem`` a refusal names
    (a regular expression, case-insensitive), the asserted ``facts``, the file ``text`` (named
    ``filename``) and other ``files`` beside it."""

    source: str
    test: str
    verdict: Verdict
    text: str
    asset: str | None = None
    problem: str = ""
    facts: tuple[Fact, ...] = ()
    filename: str = "robot.urdf"
    files: Mapping[str, str] = field(default_factory=dict)

    @property
    def id(self) -> str:
        return f"{self.test}" + (f"[{self.asset}]" if self.asset else "")


@dataclass(frozen=True)
class Outcome:
    """geomcheck's answer to a case: its verdict, what it said (refusal message, claims of
    refusal, other errors), the facts that did not hold and whether it agrees."""

    case: Case
    verdict: Verdict
    said: tuple[str, ...]
    wrong_facts: tuple[str, ...]
    agrees: bool


def look_up(report: Mapping[str, Any], path: str) -> Any:
    """The value at ``path`` in a JSON report: ``count links``, ``count joints``, ``name``,
    ``root``, ``link NAME`` (whether it exists), ``visuals NAME``, ``collisions NAME``,
    ``shape NAME visual|collision INDEX|NAME KEY`` (``type``, ``name``, ``origin.xyz``, a geometry key),
    ``inertial NAME KEY`` (``mass``, ``origin.xyz``, ``ixx``...), ``joint NAME KEY`` (``type``,
    ``parent``, ``child``, ``axis``, ``axis2``, ``origin.xyz``, ``origin.rpy``, ``origin.quat``,
    ``limit.lower``... ``mimic.multiplier``...), ``children NAME`` (joints whose parent it is),
    ``pose A B`` (link B's frame in link A's, every joint at zero: x y z roll pitch yaw)."""
    words = path.split()
    model = report["sections"]["model"]
    links = {e["name"]: e for e in model["links"]}
    joints = {e["name"]: e for e in model["joints"]}
    head = words[0]
    if head == "count":
        return report["robot"][words[1]]
    if head == "name":
        return report["robot"]["name"]
    if head == "root":
        children = {j["child"] for j in model["joints"]}
        return next((e["name"] for e in model["links"] if e["name"] not in children), None)
    if head == "link":
        return words[1] in links
    if head in ("visuals", "collisions"):
        return len(links[words[1]][head])
    if head == "shape":
        shapes = links[words[1]][f"{words[2]}s"]
        which = words[3]
        shape = shapes[int(which)] if which.isdigit() else next(s for s in shapes if s["name"] == which)
        return _key(shape, words[4], "geometry")
    if head == "inertial":
        inertial = links[words[1]]["inertial"]
        return None if inertial is None else _key(inertial, words[2], "inertia")
    if head == "joint":
        return _joint_key(joints[words[1]], words[2])
    if head == "children":
        return sum(1 for j in model["joints"] if j["parent"] == words[1])
    if head == "pose":
        return _relative(model["joints"], words[1], words[2])
    raise KeyError(path)


def _key(entry: Mapping[str, Any], key: str, inner: str) -> Any:
    parts = key.split(".")
    value: Any = entry
    for part in parts:
        if isinstance(value, Mapping) and part in value:
            value = value[part]
        elif isinstance(value, Mapping) and inner in value and part in value[inner]:
            value = value[inner][part]
        else:
            raise KeyError(key)
    return value


def _joint_key(joint: Mapping[str, Any], key: str) -> Any:
    if key == "origin.quat":
        return quaternion(joint["origin"]["rpy"])
    value: Any = joint
    for part in key.split("."):
        value = None if value is None else value[part]
    return value


def quaternion(rpy: Sequence[float]) -> tuple[float, float, float, float]:
    """(x, y, z, w) of URDF's fixed-axis ``rpy``, with w >= 0."""
    r, p, y = (0.5 * float(v) for v in rpy)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    q = (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )
    return q if q[3] >= 0.0 else (-q[0], -q[1], -q[2], -q[3])


def _matrix(origin: Mapping[str, Sequence[float]]) -> Any:

    from geomcheck.model import Pose

    return Pose(tuple(origin["xyz"]), tuple(origin["rpy"])).matrix()  # type: ignore[arg-type]


def _relative(joints: Sequence[Mapping[str, Any]], a: str, b: str) -> tuple[float, ...] | None:
    """Link ``b``'s frame in link ``a``'s through the joints between them (at zero)."""
    import numpy as np

    from geomcheck.model import rpy_from_matrix

    edges: dict[str, list[tuple[str, Any]]] = {}
    for j in joints:
        m = _matrix(j["origin"])
        edges.setdefault(j["parent"], []).append((j["child"], m))
        edges.setdefault(j["child"], []).append((j["parent"], np.linalg.inv(m)))
    frames = {a: np.eye(4)}
    stack = [a]
    while stack:
        here = stack.pop()
        for there, m in edges.get(here, ()):
            if there not in frames:
                frames[there] = frames[here] @ m
                stack.append(there)
    if b not in frames:
        return None
    m = frames[b]
    return (*(float(v) for v in m[:3, 3]), *rpy_from_matrix(m[:3, :3]))


def same(found: Any, expected: Any) -> bool:
    """Whether a looked-up value is the asserted one (numbers to :data:`TOLERANCE`; a pose or a
    quaternion as a rotation, whatever its angles)."""
    if isinstance(expected, float) and math.isinf(expected):
        return found is None or found == expected  # an open bound is written as null
    if isinstance(expected, (int, float)) and not isinstance(expected, bool):
        return isinstance(found, (int, float)) and not isinstance(found, bool) and abs(found - expected) <= TOLERANCE
    if isinstance(expected, (tuple, list)):
        if found is None or len(found) != len(expected):
            return False
        if len(expected) == 6 and all(isinstance(v, (int, float)) for v in expected):
            return _same_pose(found, expected)
        if len(expected) == 4 and all(isinstance(v, (int, float)) for v in expected):
            return all(same(f, e) for f, e in zip(found, expected, strict=True)) or all(
                same(f, -e) for f, e in zip(found, expected, strict=True)
            )
        return all(same(f, e) for f, e in zip(found, expected, strict=True))
    return bool(found == expected)


def _same_pose(found: Sequence[float], expected: Sequence[float]) -> bool:
    import numpy as np

    a = _matrix({"xyz": found[:3], "rpy": found[3:]})
    b = _matrix({"xyz": expected[:3], "rpy": expected[3:]})
    return bool(np.allclose(a, b, atol=TOLERANCE))


def run_case(case: Case, folder: Path) -> Outcome:
    """Load ``case`` with geomcheck (files written under ``folder``) and compare."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in {case.filename: case.text, **case.files}.items():
        target = folder / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")
    try:
        report = json.loads(render(geomcheck.check(folder / case.filename, select=list(SELECTED), use_config=False)))
    except GeomcheckError as err:
        said = (str(err),)
        agrees = case.verdict == "refuse" and bool(re.search(case.problem, said[0], re.IGNORECASE))
        return Outcome(case, "refuse", said, (), agrees)
    errors = [d for d in report["diagnostics"] if d["severity"] == "error"]
    claims = [d for d in errors if d["code"].startswith("GC1") and "accepted_by" not in (d["data"] or {})]
    said = tuple(f"{d['code']} {d['message']}" for d in claims or errors)
    verdict: Verdict = "refuse" if claims else "load"
    if case.verdict == "refuse":
        named = [f"{d['code']} {d['message']}" for d in (claims or errors)]
        agrees = any(re.search(case.problem, text, re.IGNORECASE) for text in named)
        return Outcome(case, verdict if claims else ("refuse" if agrees else "load"), said, (), agrees)
    wrong = []
    for fact in case.facts:
        try:
            found = look_up(report, fact.path)
        except (KeyError, IndexError, TypeError, StopIteration) as err:
            wrong.append(f"{fact.path}: not in the report ({err})")
            continue
        if not same(found, fact.value):
            wrong.append(f"{fact.path}: {found!r}, the reference says {fact.value!r}")
    return Outcome(case, verdict, said, tuple(wrong), verdict == "load" and not wrong)


def agreement(outcomes: Sequence[Outcome]) -> tuple[int, int]:
    """(cases that agree, cases)."""
    return sum(1 for o in outcomes if o.agrees), len(outcomes)


def fact(path: str, value: Any) -> Fact:
    return Fact(path, value)


__all__ = ["Case", "Fact", "Outcome", "agreement", "fact", "look_up", "run_case", "same"]
