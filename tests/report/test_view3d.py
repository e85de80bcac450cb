"""The HTML report's 3D view without a browser: the viewer's data joined from the report
(colours by worst finding, what each finding speaks of, suggestions, sweep poses), the
vendored three.js, and a report without the view."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from lxml import html as lxml_html

from geomcheck.kinematics import Kinematics
from geomcheck.load import load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report import render
from geomcheck.report.html import VIEW3D_SCRIPTS, asset, inline_scripts
from geomcheck.report.model import Report
from geomcheck.report.section_scene import pose_matrix

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"


@pytest.fixture(scope="module")
def example_report() -> Report:
    return run_check(make_bundle(EXAMPLE), CheckOptions())


@pytest.fixture(scope="module")
def payload(example_report: Report) -> dict[str, Any]:
    tree = lxml_html.fromstring(render(example_report, "html"))
    (data,) = tree.xpath("//script[@id='v3d-data']/text()")
    return dict(json.loads(data))


def test_collision_elements_take_the_colour_of_their_worst_finding(payload: dict[str, Any]) -> None:
    colours = {(link["link"], e["label"]): e["severity"] for link in payload["links"] for e in link["collisions"]}
    assert colours[("base_link", "collision[0]")] == "error"  # GC301 error
    for caster in ("fl", "fr", "bl", "br"):  # one GC301 warning, for the four casters drawn alike
        assert colours[(f"{caster}_caster_rotation_link", "collision[0]")] == "warning"
    assert colours[("base_laser_link", "collision[0]")] is None  # inertia findings are not on the collision box
    assert sum(1 for s in colours.values() if s is None) == len(colours) - 5


def test_a_fit_finding_names_its_element_and_its_suggested_box(payload: dict[str, Any]) -> None:
    gc301 = [f for f in payload["findings"] if f["code"] == "GC301"]
    assert [(f["severity"], f["links"], f["elements"]) for f in gc301] == [
        ("error", ["base_link"], [["base_link", "collision[0]"]]),
        (
            "warning",
            [f"{c}_caster_rotation_link" for c in ("bl", "br", "fl", "fr")],
            [[f"{c}_caster_rotation_link", "collision[0]"] for c in ("bl", "br", "fl", "fr")],
        ),
    ]
    base = next(link for link in payload["links"] if link["link"] == "base_link")
    (suggested,) = base["suggested"]
    assert suggested == {
        "for": "collision[0]",
        "origin": {"xyz": [0.0, 0.0, 0.45], "rpy": [0.0, 0.0, 0.0]},
        "geometry": {"type": "box", "size": [0.66, 0.66, 0.9]},
    }
    # findings about files (GC103) speak of no link: not listed beside the view
    assert {f["code"] for f in payload["findings"]} == {"GC301", "GC505", "GC507"}


def test_each_sweep_shows_its_closest_pose_as_the_kinematics_poses_it(
    example_report: Report, payload: dict[str, Any]
) -> None:
    kin = Kinematics(load_description(make_bundle(EXAMPLE)).robot)
    sweeps = {s["joint"]: s for s in payload["sweeps"]}
    caster = sweeps["fl_caster_rotation_joint"]
    assert caster["pair"] == ["base_link", "fl_caster_l_wheel_link"]
    assert caster["clearance"] == pytest.approx(0.087, abs=1e-4)
    assert caster["label"] == "closest 87.0 mm at 161°: base_link / fl_caster_l_wheel_link"
    assert set(caster["poses"]) == {"fl_caster_rotation_link", "fl_caster_l_wheel_link", "fl_caster_r_wheel_link"}
    q = kin.default_configuration({"fl_caster_rotation_joint": caster["angle"]})
    truth = dict(zip(kin.link_names, kin.link_transforms(q[None])[0], strict=True))
    for name, pose in caster["poses"].items():
        assert np.allclose(pose_matrix(pose), truth[name], atol=1e-9), name
    assert math.degrees(caster["angle"]) % 360 == pytest.approx(161, abs=0.5)


def test_the_vendored_three_js_is_whole_licensed_and_cannot_end_its_element() -> None:
    three = str(asset("three.min.js"))
    header = three[:1200]
    assert header.startswith("/*! three.js 0.187.0 (npm three@0.187.0)")
    assert "The MIT License" in header and "Copyright © 2010-2026 three.js authors" in header
    assert "var THREE=(()=>{" in three and "WebGLRenderer" in three and "OrbitControls" in three
    for text in (three, str(asset("view3d.js"))):
        assert "</script" not in text.lower() and "<!--" not in text
    assert [s[1:] for s in inline_scripts()[1:]] == [str(asset(n)) for n in VIEW3D_SCRIPTS]


def test_a_report_without_the_view_has_none_of_it(example_report: Report) -> None:
    data = example_report.to_dict()
    del data["sections"]["scene"]
    page = render(Report.from_dict(data), "html")
    assert 'id="view3d"' not in page and "three.js" not in page and "v3d-data" not in page
    assert len(page) < 400_000
    full = render(example_report, "html")
    assert '<a href="#view3d">3D view<span>5</span></a>' in full
    assert len(full) - len(str(asset("three.min.js"))) < 400_000
