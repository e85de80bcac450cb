"""The 3D view's model: what the page's viewer draws, joined from the report's sections.

The ``scene`` section places the robot; the findings say which element each one speaks of
(its link and ``about``, the links drawn alike in ``data.also``, a pair's two links, a
joint's child link) and so colour the collision elements (worst severity); the ``links``
section gives each element's suggested primitive; the ``sweeps`` section and the sweep
findings give the joint angles whose poses are shown, posed here from the scene's frame
tree. The viewer script (``templates/view3d.js``) only draws this: it decides nothing.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from markupsafe import Markup

from geomcheck.diagnostics import Diagnostic
from geomcheck.report.html_common import degrees, mm, plural, worst
from geomcheck.report.model import Report
from geomcheck.report.section_links import links_section
from geomcheck.report.section_scene import Scene, matrix_pose, scene_section
from geomcheck.report.section_sweeps import sweeps_section

JSON_ESCAPES = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028", "\u2029": "\\u2029"}
CONTACT_RULES = ("GC403",)  # pairs in collision at the default pose, drawn highlighted throughout


def script_json(value: Any) -> Markup:
    """``value`` as JSON that can stand inside a ``<script type="application/json">``."""
    text = json.dumps(value, separators=(",", ":"), ensure_ascii=False)
    for char, escaped in JSON_ESCAPES.items():
        text = text.replace(char, escaped)
    return Markup(text)


def finding_links(d: Diagnostic, scene: Scene) -> list[str]:
    """The placed links a finding speaks of: its link and those drawn alike, its pair, the
    child link of its joint."""
    placed = {link.link for link in scene.links}
    names = [x for x in (d.link, *(d.links or ())) if x]
    names += [str(x) for x in d.data.get("also") or () if d.link]
    if not names and d.joint:
        names += [f.frame for f in scene.frames if f.joint == d.joint]
    seen: list[str] = []
    for name in names:
        if name in placed and name not in seen:
            seen.append(name)
    return seen


def finding_elements(d: Diagnostic, links: Sequence[str], scene: Scene) -> list[list[str]]:
    """``[link, label]`` of the elements a finding names (its ``about``), on each of its links."""
    if not d.about or d.links:
        return []
    by_name = {link.link: link for link in scene.links}
    out = []
    for name in links:
        labels = {e.label for e in (*by_name[name].visuals, *by_name[name].collisions)}
        if d.about in labels:
            out.append([name, d.about])
    return out


def moved_poses(scene: Scene, joint: str, value: float) -> dict[str, Any]:
    """World poses of the links ``joint`` moves, with it at ``value`` and the rest at the default pose."""
    moved = scene.moved_links(joint)
    if not moved:
        return {}
    poses = scene.link_poses({joint: value})
    return {name: matrix_pose(poses[name]) for name in moved if name in poses}


def pair_poses(scene: Scene, d: Diagnostic, angle: float | None) -> dict[str, Any]:
    """For a sweep finding, the poses of its pair's links that its joint moves, at its angle."""
    if not d.joint or angle is None:
        return {}
    return {name: pose for name, pose in moved_poses(scene, d.joint, angle).items() if name in (d.links or ())}


def sweep_angle(d: Diagnostic) -> float | None:
    angle = d.data.get("angle_deg")
    return math.radians(float(angle)) if isinstance(angle, int | float) and d.joint else None


def suggestions(report: Report) -> dict[tuple[str, str], dict[str, Any]]:
    """``{(link, element label): {origin, geometry}}`` of the fit family's suggested primitives."""
    out = {}
    for link in links_section(report.sections):
        for element in link.collisions:
            suggested = element.fit.suggested if element.fit is not None else None
            if suggested is not None and suggested.geometry:
                geometry = {"type": suggested.type, **suggested.geometry}
                out[(link.link, element.label)] = {"origin": suggested.origin, "geometry": geometry}
    return out


def sweeps_model(report: Report, scene: Scene) -> list[dict[str, Any]]:
    """Per swept joint, its closest non-adjacent pair and the moving links' poses there."""
    out = []
    for sweep in sweeps_section(report.sections):
        pairs = [p for p in sweep.pairs if not p.adjacent and p.min_clearance is not None and p.min_angle is not None]
        if not pairs:
            continue
        closest = min(pairs, key=lambda p: (float(p.min_clearance or 0.0), p.links))
        poses = moved_poses(scene, sweep.joint, float(closest.min_angle or 0.0))
        if not poses:
            continue
        clearance = float(closest.min_clearance or 0.0)
        where = degrees(float(closest.min_angle or 0.0))
        state = f"in contact, {mm(-clearance)} deep" if clearance <= 0.0 else f"closest {mm(clearance)}"
        out.append(
            {
                "joint": sweep.joint,
                "pair": list(closest.links),
                "angle": closest.min_angle,
                "clearance": clearance,
                "label": f"{state} at {where}: {' / '.join(closest.links)}",
                "contact": clearance <= 0.0,
                "poses": poses,
            }
        )
    return out


def view3d_model(report: Report, findings: Sequence[Mapping[str, Any]]) -> dict[str, Any] | None:
    """The 3D view of the page: the viewer's data (``payload``) and the list beside it;
    ``None`` when the report has no ``scene`` section (``view_3d = false``, an older report)."""
    scene = scene_section(report.sections)
    if scene is None:
        return None
    placed = PlacedFindings.of(report, findings, scene)
    sweeps = sweeps_model(report, scene)
    payload = {
        "robot": report.robot.name,
        "root": scene.root,
        "frames": [f.to_dict() for f in scene.frames],
        "variables": [v.to_dict() for v in scene.variables],
        "links": scene_links(report, scene, placed.severities),
        "meshes": [dict(m) for m in scene.meshes],
        "findings": placed.shown,
        "sweeps": sweeps,
        "contacts": placed.contacts,
    }
    hidden = len(report.diagnostics) - len(placed.shown)
    return {
        "payload": script_json(payload),
        "findings": placed.shown,
        "sweeps": sweeps,
        "variables": len(scene.variables),
        "note": scene_note(scene),
        "unplaced": list(scene.unplaced),
        "hidden": f"{plural(hidden, 'finding')} about files or the whole robot" if hidden else "",
    }


@dataclass
class PlacedFindings:
    """The findings the 3D view can place on the robot: their entries (``shown``), the severities
    of each collision element ``(link, label)`` they speak of, and the pairs in contact to highlight."""

    shown: list[dict[str, Any]] = field(default_factory=list)
    severities: dict[tuple[str, str], list[str]] = field(default_factory=dict)
    contacts: list[list[str]] = field(default_factory=list)

    @classmethod
    def of(cls, report: Report, findings: Sequence[Mapping[str, Any]], scene: Scene) -> PlacedFindings:
        out = cls()
        diagnostics = sorted(report.diagnostics, key=Diagnostic.sort_key)
        collision_labels = {link.link: [e.label for e in link.collisions] for link in scene.links}
        for d, f in zip(diagnostics, findings, strict=True):
            subjects = finding_links(d, scene)
            if not subjects:
                continue
            elements = finding_elements(d, subjects, scene)
            on = elements if elements else []
            if d.links:  # a pair speaks of both links' collision geometry
                on = [[name, label] for name in subjects for label in collision_labels.get(name, [])]
                if d.code in CONTACT_RULES:
                    out.contacts.append(list(d.links))
            for name, label in on:
                out.severities.setdefault((name, label), []).append(d.severity.value)
            angle = sweep_angle(d)
            out.shown.append(
                {
                    "id": f["id"],
                    "code": d.code,
                    "severity": d.severity.value,
                    "subject": d.subject,
                    "about": d.about,
                    "message": d.message,
                    "links": subjects,
                    "elements": elements,
                    "pair": list(d.links) if d.links else None,
                    "joint": d.joint,
                    "poses": pair_poses(scene, d, angle),
                }
            )
        return out


def scene_links(report: Report, scene: Scene, severities: Mapping[tuple[str, str], list[str]]) -> list[dict[str, Any]]:
    """Each placed link's entry for the viewer: its collision elements coloured by their worst
    finding, and the primitives suggested for them."""
    suggested = suggestions(report)
    links: list[dict[str, Any]] = []
    for link in scene.links:
        entry = link.to_dict()
        entry["collisions"] = [
            {**e.to_dict(), "severity": worst(severities.get((link.link, e.label), []))} for e in link.collisions
        ]
        entry["suggested"] = [
            {"for": e.label, **suggested[(link.link, e.label)]}
            for e in link.collisions
            if (link.link, e.label) in suggested
        ]
        links.append(entry)
    return links


def scene_note(scene: Scene) -> str:
    """What the view draws: links, mesh files and triangles (and whether they were decimated)."""
    source = sum(int(m.get("source_triangles") or 0) for m in scene.meshes)
    decimated = scene.triangles < source
    files = plural(len(scene.meshes), "mesh file")
    note = f"{plural(len(scene.links), 'link')}, {files} of {scene.triangles:,} triangles"
    if decimated:
        note += f" (decimated for display from {source:,})"
    return note
