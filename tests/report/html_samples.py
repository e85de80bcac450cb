"""A small but complete report for the HTML tests: a PR2-like base with a thin collision
slab, a caster with two wheels, an impossible wheel inertia, a caster sweep that scrapes
the base, a collision matrix, skipped checks. The ``views`` section comes from the real
views family run on meshes written with trimesh; the other sections are written by hand
in the shapes docs/report-schema.md documents.

Loaded by path from the test modules (``load_samples()``), so it works in any pytest
import mode.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from geomcheck.checks import CheckContext
from geomcheck.checks import fit as fit_family
from geomcheck.checks import meshes as meshes_family
from geomcheck.checks import scene as scene_family
from geomcheck.checks import views as views_family
from geomcheck.load import ExpandedDocument, LoadedDescription, MeshStore, make_bundle
from geomcheck.model import Box, Cylinder, Link, Mesh, Pose, Robot, Shape, SourceLocation, Sphere
from geomcheck.options import CheckOptions
from geomcheck.report.model import Report

BASE_URDF = """<robot name="demo_base">
  <link name="base_link">
    <collision>
      <origin xyz="0 0 0.071"/>
      <geometry><box size="0.65 0.65 0.04"/></geometry>
    </collision>
  </link>
</robot>
"""


def write_meshes(folder: Path) -> None:
    """Base shell 0.66 x 0.66 x 0.90 m with a hole through it, a caster housing, a wheel (axis y)."""
    shell = trimesh.creation.box(extents=[0.66, 0.66, 0.9])
    shell.apply_translation([0, 0, 0.45])
    shell.export(folder / "base.stl")
    caster = trimesh.creation.box(extents=[0.15, 0.1, 0.12])
    caster.export(folder / "caster.stl")
    wheel = trimesh.creation.cylinder(radius=0.079, height=0.034, sections=48)
    wheel.apply_transform(trimesh.transformations.rotation_matrix(math.pi / 2, [1, 0, 0]))
    wheel.export(folder / "wheel.stl")
    ring = trimesh.creation.annulus(r_min=0.03, r_max=0.06, height=0.02)
    ring.export(folder / "ring.stl")


def demo_robot() -> Robot:
    loc = SourceLocation("robots/demo.urdf", 3, None, 3)
    return Robot(
        name="demo_base",
        links=(
            Link(
                "base_link",
                visuals=(Shape("visual", 0, Mesh("base.stl")),),
                collisions=(Shape("collision", 0, Box((0.65, 0.65, 0.04)), Pose((0.0, 0.0, 0.071))),),
                location=loc,
            ),
            Link(
                "fl_caster_rotation_link",
                visuals=(Shape("visual", 0, Mesh("caster.stl")),),
                collisions=(Shape("collision", 0, Box((0.16, 0.11, 0.13))),),
            ),
            Link(
                "fl_caster_l_wheel_link",
                visuals=(Shape("visual", 0, Mesh("wheel.stl")),),
                collisions=(Shape("collision", 0, Cylinder(0.074792, 0.034), Pose(rpy=(math.pi / 2, 0.0, 0.0))),),
            ),
            Link(
                "fl_caster_r_wheel_link",
                visuals=(Shape("visual", 0, Mesh("wheel.stl")),),
                collisions=(Shape("collision", 0, Cylinder(0.074792, 0.034), Pose(rpy=(math.pi / 2, 0.0, 0.0))),),
            ),
            Link(
                "laser_ring_link",
                visuals=(Shape("visual", 0, Mesh("ring.stl")),),
                collisions=(Shape("collision", 0, Sphere(0.05)),),
            ),
            Link("base_footprint"),
            Link("lost_link", visuals=(Shape("visual", 0, Mesh("missing.stl")),)),
        ),
    )


def computed_sections(folder: Path) -> dict[str, Any]:
    """The ``links``, ``views`` and ``scene`` sections of the real families run on the demo robot."""
    (folder / "demo.urdf").write_text(BASE_URDF, encoding="utf-8")
    write_meshes(folder)
    bundle = make_bundle(folder / "demo.urdf", display_root=folder)
    loaded = LoadedDescription(bundle, demo_robot(), ExpandedDocument(BASE_URDF, "demo.urdf", {}, False), ())
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions())
    sections: dict[str, Any] = {}
    for family in (meshes_family, fit_family, views_family, scene_family):
        sections |= family.run(ctx).sections
    return sections


def sweep_pair(links: list[str], clearance_of: Any) -> dict[str, Any]:
    angles = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    clearance = np.round(clearance_of(angles), 4)
    k = int(np.argmin(clearance))
    hits = clearance <= 0.0
    ranges = []
    if hits.any():
        idx = np.flatnonzero(hits)
        ranges.append([round(float(angles[idx[0]]), 4), round(float(angles[idx[-1]]), 4)])
    return {
        "links": sorted(links),
        "min_clearance": float(clearance[k]),
        "min_angle": round(float(angles[k]), 4),
        "colliding_ranges": ranges,
        "max_depth": float(max(0.0, -clearance.min())),
        "angles": [round(float(a), 4) for a in angles],
        "clearance": [float(c) for c in clearance],
    }


def sweeps_section() -> list[dict[str, Any]]:
    scrape = sweep_pair(["base_link", "fl_caster_l_wheel_link"], lambda a: 0.02 + 0.03 * np.cos(a - 0.7))
    clear = sweep_pair(["base_link", "fl_caster_r_wheel_link"], lambda a: 0.03 + 0.012 * np.sin(2 * a))
    return [
        {
            "joint": "fl_caster_rotation_joint",
            "moving_joints": ["fl_caster_rotation_joint", "fl_caster_l_wheel_joint", "fl_caster_r_wheel_joint"],
            "moving_links": ["fl_caster_rotation_link", "fl_caster_l_wheel_link", "fl_caster_r_wheel_link"],
            "grid_points": 360,
            "proven": True,
            "pairs": [clear, scrape],
        }
    ]


def matrix_section() -> dict[str, Any]:
    links = [
        "base_link",
        "fl_caster_rotation_link",
        "fl_caster_l_wheel_link",
        "fl_caster_r_wheel_link",
        "laser_ring_link",
    ]
    classes = {
        ("base_link", "fl_caster_rotation_link"): ("adjacent", False, None),
        ("fl_caster_l_wheel_link", "fl_caster_rotation_link"): ("adjacent", False, None),
        ("fl_caster_r_wheel_link", "fl_caster_rotation_link"): ("adjacent", False, None),
        ("base_link", "fl_caster_l_wheel_link"): ("enabled", False, None),
        ("base_link", "fl_caster_r_wheel_link"): ("default", False, None),
        ("base_link", "laser_ring_link"): ("always", False, None),
        ("fl_caster_l_wheel_link", "fl_caster_r_wheel_link"): ("never", True, None),
        ("fl_caster_l_wheel_link", "laser_ring_link"): ("never", False, None),
        ("fl_caster_r_wheel_link", "laser_ring_link"): (
            "enabled",
            False,
            {"configuration": {"fl_caster_rotation_joint": 0.7}, "depth": 0.003},
        ),
        ("fl_caster_rotation_link", "laser_ring_link"): ("never", True, None),
    }
    pairs = []
    for (a, b), (cls, certified, witness) in sorted(classes.items()):
        fraction = {"always": 1.0, "default": 0.4, "enabled": 0.02}.get(cls, 0.0)
        pairs.append(
            {
                "links": sorted([a, b]),
                "class": cls,
                "fraction": fraction,
                "min_distance": 0.0 if fraction else 0.12,
                "certified": certified,
                "witness": witness,
            }
        )
    return {"samples": 1000, "seed": 0, "backend": "coal", "always_fraction": 0.95, "links": links, "pairs": pairs}


def inertia_section() -> list[dict[str, Any]]:
    def entry(link: str, mass: float, moments: list[float], bound: list[float], reach: float, **flags: Any) -> dict:
        return {
            "link": link,
            "mass": mass,
            "com": [0.0, 0.0, 0.0],
            "principal_moments": moments,
            "principal_axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            "geometry_bound": bound,
            "radius_of_gyration": [round(math.sqrt(m / mass), 4) for m in moments],
            "reach": [reach] * 3,
            "positive_definite": True,
            "triangle_ok": True,
            "within_geometry": flags.get("within", True),
            "com_inside_bounds": True,
            "copied_from": flags.get("copied"),
        }

    return [
        entry("base_link", 116.0, [5.65, 5.67, 3.68], [20.1, 20.1, 25.3], 0.56),
        entry("fl_caster_rotation_link", 3.47, [0.0129, 0.0125, 0.0158], [0.025, 0.025, 0.03], 0.11),
        entry(
            "fl_caster_l_wheel_link",
            0.44036,
            [0.0129, 0.0125, 0.0158],
            [0.00275, 0.00275, 0.00275],
            0.079,
            within=False,
            copied="fl_caster_rotation_link",
        ),
    ]


def diagnostics() -> list[dict[str, Any]]:
    def diag(code: str, name: str, severity: str, message: str, help: str, **extra: Any) -> dict[str, Any]:
        out = {
            "code": code,
            "name": name,
            "severity": severity,
            "message": message,
            "help": help,
            "link": None,
            "joint": None,
            "links": None,
            "about": "",
            "location": None,
            "fingerprint": "0" * 16,
            "data": {},
            "excerpt": [],
        }
        out.update(extra)
        return out

    return [
        diag(
            "GC301",
            "collision-does-not-cover-mesh",
            "warning",
            "collision box covers 4% of base mesh height: box is 0.04 m tall, mesh spans 0.90 m in z",
            "Use the suggested box, or a set of primitives that covers the base shell.",
            link="base_link",
            about="collision[0]",
            location={"file": "urdf/base.urdf.xacro", "line": 5, "column": 7, "expanded_line": 41},
            excerpt=[
                [3, "    <collision>"],
                [4, '      <origin xyz="0 0 0.071" rpy="0 0 0"/>'],
                [5, '      <geometry><box size="0.65 0.65 0.04"/></geometry>'],
                [6, "    </collision>"],
                [7, "  </link>"],
            ],
        ),
        diag(
            "GC401",
            "sweep-collision",
            "error",
            "fl_caster_l_wheel_link touches base_link from 158° to 242° of fl_caster_rotation_joint, 10.0 mm deep",
            "Move the caster or shrink the base's collision geometry where the wheel passes.",
            joint="fl_caster_rotation_joint",
            links=["base_link", "fl_caster_l_wheel_link"],
            about="sweep",
        ),
        diag(
            "GC505",
            "inertia-exceeds-geometry",
            "error",
            "principal moment 0.0158 kg m^2 needs a radius of gyration of 0.189 m, but the geometry reaches 0.079 m",
            "Compute the wheel's inertia from its own mass and shape.",
            link="fl_caster_l_wheel_link",
            about="inertia",
            location={"file": "urdf/base.urdf.xacro", "line": 61, "column": None, "expanded_line": 120},
        ),
        diag(
            "GC103",
            "legacy-xacro-syntax",
            "warning",
            "urdf/base.urdf.xacro uses legacy xacro tags: <property> x12, <macro> x3 <&> 'quoted'",
            'Prefix them with xacro: and declare xmlns:xacro="http://www.ros.org/wiki/xacro".',
            location={"file": "urdf/base.urdf.xacro", "line": 2, "column": 3, "expanded_line": None},
            excerpt=[[1, "<robot>"], [2, '  <property name="caster_offset_x" value="0.2225"/>'], [3, ""]],
        ),
        diag(
            "GC507",
            "copied-inertia",
            "warning",
            "fl_caster_l_wheel_link has the inertia tensor of fl_caster_rotation_link (3.47 kg) with 0.44 kg",
            "Compute the tensor for this link.",
            link="fl_caster_l_wheel_link",
            about="inertia-copy",
        ),
    ]


def sample_report_dict(folder: Path) -> dict[str, Any]:
    """The whole report as its JSON document."""
    return {
        "schema": "geomcheck.report/1",
        "tool": {"name": "geomcheck", "version": "0.1.0"},
        "created": "2026-01-01T00:00:00Z",
        "robot": {
            "name": "demo_base",
            "source": "robots/demo.urdf.xacro",
            "links": 7,
            "joints": 6,
            "meshes_total": 5,
            "meshes_loaded": 4,
        },
        "options": {
            "args": {},
            "srdf": None,
            "backend": "coal",
            "matrix": True,
            "sweep": True,
            "samples": 1000,
            "seed": 0,
            "pose": {},
            "pose_name": None,
        },
        "fail_on": "error",
        "verdict": "fail",
        "summary": {"error": 2, "warning": 3, "info": 0},
        "diagnostics": diagnostics(),
        "skipped": [{"check": "fit", "subject": "lost_link", "reason": "no visual mesh loaded"}],
        "sections": {
            "inertia": inertia_section(),
            "sweeps": sweeps_section(),
            "matrix": matrix_section(),
            **computed_sections(folder),
        },
    }


def sample_report(folder: Path) -> Report:
    return Report.from_dict(sample_report_dict(folder))
