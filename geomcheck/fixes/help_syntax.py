"""A finding's ``help`` in the syntax of its description's format.

The fit and mesh rules write their advice as URDF (``<origin xyz rpy/>`` and the fitted
``<geometry>``, ``filename="..."``): a finding on an MJCF or SDFormat description gets the
same advice in that format, as its fix is written (:mod:`geomcheck.fixes.derive_mjcf`,
:mod:`geomcheck.fixes.derive_sdf`): an MJCF ``<geom type size pos quat/>`` (half extents,
``radius half-length``, ``w x y z``), an SDFormat ``<pose>x y z roll pitch yaw</pose>`` and
``<box><size>``, ``<cylinder><radius><length>``, ``<sphere><radius>``, ``<uri>``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable

from geomcheck.fixes.derive_mjcf import SYNTAX as MJCF
from geomcheck.fixes.derive_mjcf import quat_text, size_text
from geomcheck.fixes.derive_sdf import SYNTAX as SDF
from geomcheck.fixes.derive_sdf import shape_xml

ORIGIN = re.compile(
    r'<origin xyz="(?P<xyz>[^"]*)" rpy="(?P<rpy>[^"]*)"/>'
    r"(?:\n<geometry><(?P<kind>box|cylinder|sphere)(?P<attributes>(?: \w+=\"[^\"]*\")+)/></geometry>)?"
)
ATTRIBUTE = re.compile(r'(\w+)="([^"]*)"')
SET_RPY = re.compile(r'Set rpy="(?P<rpy>[^"]*)" on the cylinder\'s origin: ')
FILENAME = re.compile(r'filename="(?P<name>[^"]*)"')
ADD_COLLISION = "Add a <collision> element"


def _geometry(kind: str, attributes: str) -> dict[str, object]:
    values = dict(ATTRIBUTE.findall(attributes))
    if kind == "box":
        return {"size": [float(v) for v in values["size"].split()]}
    out: dict[str, object] = {"radius": float(values["radius"])}
    if kind == "cylinder":
        out["length"] = float(values["length"])
    return out


QUARTER_TURN_DECIMALS = 5e-5  # help writes angles to 4 decimals: this close to a quarter turn, one [rad]


def _angles(text: str) -> list[float]:
    """Angles as help writes them, those the 4 decimals rounded off a quarter turn snapped back."""
    out = []
    for value in (float(v) for v in text.split()):
        turns = round(value / (0.5 * math.pi))
        out.append(turns * 0.5 * math.pi if abs(value - turns * 0.5 * math.pi) < QUARTER_TURN_DECIMALS else value)
    return out


def _mjcf_origin(match: re.Match[str]) -> str:
    rpy = _angles(match["rpy"])
    placed = f'pos="{match["xyz"]}" quat="{quat_text(rpy)}"'
    if match["kind"] is None:
        return f"<geom {placed}/>"
    size = size_text(match["kind"], _geometry(match["kind"], match["attributes"]))
    return f'<geom type="{match["kind"]}" size="{size}" {placed}/>'


def _sdf_origin(match: re.Match[str]) -> str:
    pose = f"<pose>{match['xyz']} {match['rpy']}</pose>"
    if match["kind"] is None:
        return pose
    return f"{pose}\n<geometry>{shape_xml(match['kind'], _geometry(match['kind'], match['attributes']))}</geometry>"


def _mjcf(text: str) -> str:
    text = SET_RPY.sub(lambda m: f'Set quat="{quat_text(_angles(m["rpy"]))}" on the geom: ', text)
    text = text.replace(ADD_COLLISION, "Add a colliding <geom> (contype or conaffinity not 0)")
    return ORIGIN.sub(_mjcf_origin, text)


def _sdf(text: str) -> str:
    text = SET_RPY.sub(lambda m: f"Set the angles of the collision's <pose> to {m['rpy']}: ", text)
    text = FILENAME.sub(lambda m: f"<uri>{m['name']}</uri>", text)
    return ORIGIN.sub(_sdf_origin, text)


RESTATE: dict[str, Callable[[str], str]] = {MJCF: _mjcf, SDF: _sdf}


def help_in_syntax(text: str, syntax: str) -> str:
    """``text`` (a finding's help) with its URDF snippets written in ``syntax``'s (``urdf``: as is)."""
    restate = RESTATE.get(syntax)
    if restate is None:
        return text
    try:
        return restate(text)
    except (KeyError, ValueError):  # a snippet this module does not read: the advice as the rule wrote it
        return text
