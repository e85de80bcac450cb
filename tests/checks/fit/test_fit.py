"""GC3xx fit checks (geomcheck.checks.fit) on small robots built in the tests, and on the
shared corpus (2009 PR2, example-robot-data)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks import fit as fit_family
from geomcheck.checks import meshes as mesh_family
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load import ExpandedDocument, LoadedDescription, MeshStore, make_bundle
from geomcheck.model import (
    Box,
    Cylinder,
    Geometry,
    Joint,
    Limit,
    Link,
    Mesh,
    Pose,
    Robot,
    Shape,
    SourceLocation,
    Sphere,
)
from geomcheck.options import CheckOptions
from geomcheck.rules import all_rules

ROOT_FILE = "robot.urdf"
BOX_SIZE = (0.3, 0.2, 0.1)  # the test link's mesh [m]
WHEEL_RADIUS, WHEEL_WIDTH = 0.079, 0.034  # the 2009 PR2 wheel [m]
Z_ONTO_Y = Pose(rpy=(np.pi / 2, 0.0, 0.0))  # how URDF turns a cylinder onto a wheel axis y
BOX_MESH = Mesh("meshes/box.stl")
WHEEL_MESH = Mesh("meshes/wheel.stl")
COLLISION_LINE = 7


@pytest.fixture
def bundle_dir(tmp_path: Path) -> Path:
    """A bundle: root file, a box mesh (0.3 x 0.2 x 0.1 m) and a wheel mesh (axis y)."""
    (tmp_path / ROOT_FILE).write_text("<robot name='r'/>\n")
    (tmp_path / "meshes").mkdir()
    trimesh.creation.box(extents=BOX_SIZE).export(tmp_path / "meshes" / "box.stl")
    wheel = trimesh.creation.cylinder(radius=WHEEL_RADIUS, height=WHEEL_WIDTH, sections=64)
    wheel.apply_transform(Z_ONTO_Y.matrix())
    wheel.export(tmp_path / "meshes" / "wheel.stl")
    return tmp_path


def collision(geometry: Geometry, origin: Pose = Pose(), index: int = 0) -> Shape:
    return Shape("collision", index, geometry, origin, location=SourceLocation(ROOT_FILE, COLLISION_LINE + index))


def link(name: str, *collisions: Shape, mesh: Mesh = BOX_MESH) -> Link:
    return Link(name, visuals=(Shape("visual", 0, mesh),), collisions=collisions, location=SourceLocation(ROOT_FILE, 3))


def robot_of(*links: Link, joint_type: str = "fixed", axis: tuple[float, float, float] = (0.0, 0.0, 1.0)) -> Robot:
    """``base`` (no geometry) with each link on its own joint, 1 m apart."""
    joints = tuple(
        Joint(f"{lk.name}_joint", joint_type, "base", lk.name, Pose((float(i), 0.0, 0.0)), axis=axis)
        for i, lk in enumerate(links, start=1)
    )
    return Robot("r", links=(Link("base"), *links), joints=joints)


def check(bundle_dir: Path, robot: Robot) -> FamilyResult:
    """The meshes then the fit family on ``robot``, as the pipeline runs them."""
    bundle = make_bundle(bundle_dir / ROOT_FILE)
    document = ExpandedDocument(text="", root=ROOT_FILE, sources={}, is_xacro=False)
    loaded = LoadedDescription(bundle=bundle, robot=robot, document=document, diagnostics=())
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions(sweep=False))
    first, second = mesh_family.run(ctx), fit_family.run(ctx)
    return FamilyResult(
        diagnostics=first.diagnostics + second.diagnostics,
        sections={**first.sections, **second.sections},
        skipped=first.skipped + second.skipped,
    )


def codes(result: FamilyResult) -> list[tuple[str, str | None, str]]:
    return sorted((d.code, d.link, d.about) for d in result.diagnostics)


def only(result: FamilyResult, code: str) -> Diagnostic:
    found = [d for d in result.diagnostics if d.code == code]
    assert len(found) == 1, codes(result)
    return found[0]


def entry(result: FamilyResult, name: str) -> dict:
    return next(e for e in result.sections["links"] if e["link"] == name)


def test_rules_are_registered_with_documentation() -> None:
    rules = [r for r in all_rules() if r.family in ("GC2", "GC3")]
    meshes = [*(f"GC20{i}" for i in range(1, 10)), "GC210", "GC211"]
    assert [r.code for r in rules] == [*meshes, *(f"GC30{i}" for i in range(1, 7))]
    for rule in rules:
        assert rule.what and rule.why and rule.example and rule.fix and rule.summary
        assert rule.name == rule.name.lower() and " " not in rule.name


def test_matching_box_has_no_finding_and_full_metrics(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(Box(BOX_SIZE)))))
    assert result.diagnostics == [] and result.skipped == []
    body = entry(result, "body")
    fit = body["collisions"][0]["fit"]
    assert fit["coverage"] == 1.0 and fit["protrusion_max_mm"] == 0.0 and fit["slack"] == 1.0
    assert fit["gaps_mm"] == dict.fromkeys(("x-", "x+", "y-", "y+", "z-", "z+"), 0.0)
    assert fit["suggested"]["geometry"] == {"size": [0.3, 0.2, 0.1]}
    assert body["visual_meshes"][0]["extents"] == [0.3, 0.2, 0.1]
    assert body["union"]["coverage"] == 1.0
    # an entry for every link, in document order, also the one without geometry
    assert [e["link"] for e in result.sections["links"]] == ["base", "body"]


def test_box_shrunk_30_percent_does_not_cover(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(Box((0.21, 0.2, 0.1))))))
    d = only(result, "GC301")
    assert (d.link, d.about, d.location.line if d.location else None) == ("body", "collision[0]", COLLISION_LINE)
    assert d.data["protrusion_max_mm"] == 45.0 and d.data["gaps_mm"]["x+"] == -45.0
    assert 0.5 <= d.data["coverage"] < 0.9 and d.severity == Severity.WARNING
    assert "covers 70% of the mesh's extent along the link's x axis" in d.message
    assert "the box is 0.21 m long (x -0.105 to 0.105 m), the mesh spans 0.3 m (x -0.15 to 0.15 m)" in d.message
    assert '<box size="0.3 0.2 0.1"/>' in d.help


def test_thin_slab_is_an_error_naming_the_height(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(Box((0.3, 0.2, 0.004)), Pose((0.0, 0.0, 0.048))))))
    d = only(result, "GC301")
    assert d.severity == Severity.ERROR and d.data["coverage"] < 0.5
    assert "covers 4% of the mesh's height" in d.message and "the mesh spans 0.1 m (z -0.05 to 0.05 m)" in d.message


def test_box_offset_by_10_cm_is_misplaced(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(Box(BOX_SIZE), Pose((0.1, 0.0, 0.0))))))
    d = only(result, "GC303")
    assert (d.link, d.about, d.severity) == ("body", "collision[0]", Severity.ERROR)
    assert d.data["offset"] == [-0.1, 0.0, 0.0] and d.data["disjoint"] is False
    assert d.data["protrusion_max_mm"] == 100.0
    assert "is 0.1 m off its mesh" in d.message and '<origin xyz="0 0 0" rpy="0 0 0"/>' in d.help


def test_box_elsewhere_is_disjoint(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(Box(BOX_SIZE), Pose((0.0, 0.0, 1.0))))))
    d = only(result, "GC303")
    assert d.data["disjoint"] is True and d.data["mesh_inside"] == 0.0 and d.data["in_hull"] == 0.0
    assert d.data["offset"] == [0.0, 0.0, -1.0]
    assert "is away from the link's visual geometry" in d.message


def test_small_element_against_the_mesh_stands_for_what_the_visual_does_not_draw(bundle_dir: Path) -> None:
    """A 2 cm sphere 5 mm past the box's +x face, beside the box that covers the mesh: a tooth the
    bone mesh lacks, a bumper pad (info). 30 mm out, farther than its own 10 mm radius, it is away."""

    def gc303(gap: float) -> Diagnostic:
        pad = collision(Sphere(0.01), Pose((BOX_SIZE[0] / 2 + gap + 0.01, 0.0, 0.0)), index=1)
        return only(check(bundle_dir, robot_of(link("body", collision(Box(BOX_SIZE)), pad))), "GC303")

    beside = gc303(0.005)
    assert (beside.about, beside.severity, beside.data["disjoint"]) == ("collision[1]", Severity.INFO, True)
    assert beside.message.endswith("small beside it: it stands for what the visual does not draw")
    # the nearest of the mesh's sample points: 5 mm off the face, at most a sample spacing more
    nearest = float(re.search(r"its nearest mesh point is ([0-9.]+) mm", beside.message).group(1))  # type: ignore[union-attr]
    assert 5.0 <= nearest <= 10.0
    away = gc303(0.03)
    assert (away.about, away.severity) == ("collision[1]", Severity.ERROR)
    assert "stands for" not in away.message


def test_wheel_cylinder_on_the_wrong_axis(bundle_dir: Path) -> None:
    wheel = link("wheel", collision(Cylinder(WHEEL_RADIUS, WHEEL_WIDTH)), mesh=WHEEL_MESH)
    result = check(bundle_dir, robot_of(wheel, joint_type="continuous", axis=(0.0, 1.0, 0.0)))
    d = only(result, "GC304")
    assert (d.link, d.about) == ("wheel", "collision[0]")
    alt = d.data["axis_alternative"]
    assert alt["axis_name"] == "y" and alt["coverage"] == 1.0 and alt["rpy"] == pytest.approx([np.pi / 2, 0, 0])
    assert d.data["coverage"] < 0.5
    assert "lies along the link's z axis but the mesh's axis is the link's y axis" in d.message
    assert 'rpy="1.5708 0 0"' in d.help


def test_wheel_cylinder_with_the_pr2_rotation_is_fine(bundle_dir: Path) -> None:
    wheel = link("wheel", collision(Cylinder(0.074792, WHEEL_WIDTH), Z_ONTO_Y), mesh=WHEEL_MESH)
    result = check(bundle_dir, robot_of(wheel, joint_type="continuous", axis=(0.0, 1.0, 0.0)))
    assert result.diagnostics == []
    fit = entry(result, "wheel")["collisions"][0]["fit"]
    assert fit["protrusion_max_mm"] == pytest.approx(4.2, abs=0.1) and fit["coverage"] == 1.0
    assert fit["suggested"]["origin"]["rpy"] == pytest.approx([np.pi / 2, 0, 0])


def test_mesh_scaled_by_1000_is_a_units_error(bundle_dir: Path) -> None:
    scaled = Mesh("meshes/box.stl", (1000.0, 1000.0, 1000.0))
    result = check(
        bundle_dir,
        robot_of(link("body", collision(Box(BOX_SIZE)), mesh=scaled), link("other", collision(Box(BOX_SIZE)))),
    )
    d = only(result, "GC205")
    assert (d.link, d.about) == ("body", "visual[0]")
    assert d.data["factor"] == 1000.0 and d.data["suggested_scale"] == "1 1 1"
    assert 'scale="1 1 1"' in d.help


def test_removed_collision_element(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body"), joint_type="revolute"))
    d = only(result, "GC305")
    assert (d.link, d.about, d.severity) == ("body", "collision", Severity.WARNING)
    assert d.message.endswith("; it moves (joint body_joint)")
    assert d.data["suggested"]["geometry"] == {"size": [0.3, 0.2, 0.1]}
    assert '<box size="0.3 0.2 0.1"/>' in d.help
    assert (d.data["covered_by"], d.data["reached_by"]) == (None, None)


def test_part_of_the_root_body_out_of_reach_stays_a_warning(bundle_dir: Path) -> None:
    # a cover bolted to the base 1 m from the only moving body (a wheel turning in place at 3 m)
    wheel = link("wheel", collision(Cylinder(WHEEL_RADIUS, WHEEL_WIDTH), Z_ONTO_Y), mesh=WHEEL_MESH)
    robot = robot_of(link("cover"), link("arm", collision(Box(BOX_SIZE))))
    robot = Robot(
        "r",
        links=(*robot.links[:2], wheel),
        joints=(
            robot.joints[0],
            Joint("wheel_joint", "continuous", "base", "wheel", Pose((3.0, 0.0, 0.0)), axis=(0.0, 1.0, 0.0)),
        ),
    )
    d = only(check(bundle_dir, robot), "GC305")
    # no moving body reaches it, but obstacles and the ground do
    assert (d.link, d.severity, d.data["reached_by"]) == ("cover", Severity.WARNING, None)
    assert d.message.endswith(
        "rigidly attached to the robot's root body base: no moving body of the robot can reach it, but obstacles "
        "and the ground can"
    )


def test_part_of_the_root_body_a_moving_arm_sweeps_is_a_warning(bundle_dir: Path) -> None:
    # an arm reaching 0.36 m from its joint, turning about z 0.4 m from the cover's centre, sweeps over its end
    cover, arm = link("cover"), link("arm", collision(Box(BOX_SIZE), Pose((0.2, 0.0, 0.0))))
    robot = Robot(
        "r",
        links=(Link("base"), cover, arm),
        joints=(
            Joint("cover_joint", "fixed", "base", "cover", Pose((1.0, 0.0, 0.0))),
            Joint("arm_joint", "revolute", "base", "arm", Pose((1.4, 0.0, 0.0)), axis=(0.0, 0.0, 1.0)),
        ),
    )
    d = only(check(bundle_dir, robot), "GC305")
    assert (d.link, d.severity, d.data["reached_by"]) == ("cover", Severity.WARNING, "arm")
    assert d.message.endswith("; moving link arm can reach it")


def test_part_inside_the_body_it_is_bolted_to_is_info(bundle_dir: Path) -> None:
    # a wheel-sized part inside a moving body's box collision: touched through the body
    housing = link("housing", collision(Box((0.3, 0.2, 0.2))))
    rotor = link("rotor", mesh=WHEEL_MESH)
    robot = Robot(
        "r",
        links=(Link("base"), housing, rotor),
        joints=(
            Joint("housing_joint", "revolute", "base", "housing", Pose((1.0, 0.0, 0.0)), axis=(0.0, 0.0, 1.0)),
            Joint("rotor_joint", "fixed", "housing", "rotor", Pose()),
        ),
    )
    d = only(check(bundle_dir, robot), "GC305")
    assert (d.link, d.severity, d.data["covered_by"]) == ("rotor", Severity.INFO, "housing")
    assert "its visual lies within the collision geometry of housing, rigidly attached to it" in d.message


def test_small_protrusion_is_info(bundle_dir: Path) -> None:
    # a box 17 mm short at one end of a 0.3 m part (tolerance 15 mm): its end face, 9% of its surface, sticks out
    result = check(bundle_dir, robot_of(link("body", collision(Box((0.283, 0.2, 0.1)), Pose((-0.0085, 0.0, 0.0))))))
    d = only(result, "GC301")
    assert d.data["protrusion_max_mm"] == 17.0 and d.severity == Severity.INFO
    assert entry(result, "body")["union"]["coverage"] >= 0.9
    assert "(joints at zero) 91% of the link's surface is covered: a small part sticks out" in d.message


def test_collision_mesh_reaching_past_the_visual_is_info(bundle_dir: Path) -> None:
    grown = Mesh("meshes/box.stl", (1.3, 1.0, 1.0))
    d = only(check(bundle_dir, robot_of(link("body", collision(grown)))), "GC306")
    assert d.severity == Severity.INFO and d.data["overshoot_max_mm"] == 45.0
    assert "it reaches 45 mm out of the visual's hull" in d.message


def test_collision_mesh_reaching_a_quarter_of_the_part_out_is_a_warning(bundle_dir: Path) -> None:
    # 150 mm out of a 0.3 m part: another shape, or the part's mesh in another place
    grown = Mesh("meshes/box.stl", (2.0, 1.0, 1.0))
    d = only(check(bundle_dir, robot_of(link("body", collision(grown)))), "GC306")
    assert d.severity == Severity.WARNING and d.data["overshoot_max_mm"] == 150.0
    assert "it reaches 0.15 m out of the visual's hull" in d.message


def test_foot_sphere_larger_than_its_mesh_is_info(bundle_dir: Path) -> None:
    # a sphere at the end of a chain of moving joints is its contact shape, sized for contact
    foot = link("foot", collision(Sphere(0.5)))
    d = only(check(bundle_dir, robot_of(foot, joint_type="revolute")), "GC302")
    assert d.severity == Severity.INFO and d.message.endswith(
        "; it ends a chain of moving joints, the chain's contact shape"
    )
    # on the root body it is an ordinary oversized sphere
    assert only(check(bundle_dir, robot_of(link("foot", collision(Sphere(0.5))))), "GC302").severity == Severity.WARNING


def test_oversized_sphere(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(Sphere(0.5)))))
    d = only(result, "GC302")
    assert d.data["slack"] > 4.0 and d.data["suggested"]["slack"] < d.data["slack"] / 1.5


def test_collision_mesh_same_as_visual_matches(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(BOX_MESH))))
    assert result.diagnostics == []
    fit = entry(result, "body")["collisions"][0]["fit"]
    assert fit["coverage"] == 1.0 and fit["overshoot_max_mm"] == 0.0 and fit["suggested"] is None


def test_collision_mesh_that_does_not_match(bundle_dir: Path) -> None:
    shrunk = Mesh("meshes/box.stl", (0.5, 1.0, 1.0))
    result = check(bundle_dir, robot_of(link("body", collision(shrunk))))
    d = only(result, "GC306")
    assert d.data["protrusion_max_mm"] == 75.0 and d.data["coverage"] < 0.9


def test_missing_mesh_skips_the_fit_with_a_reason(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(link("body", collision(Box(BOX_SIZE)), mesh=Mesh("meshes/gone.stl"))))
    assert [d.code for d in result.diagnostics] == ["GC201"]
    [skip] = result.skipped
    assert (skip.check, skip.subject) == ("fit", "body") and "visual[0] mesh not loaded" in skip.reason
    assert entry(result, "body")["collisions"][0]["fit"] is None


def test_union_and_shared_geometry_across_a_joint(bundle_dir: Path) -> None:
    # the box link is covered half by its own box, half by a cylinder of the next link that
    # lies on the revolute axis between them (Franka-style capsules)
    half = collision(Box((0.15, 0.2, 0.1)), Pose((-0.075, 0.0, 0.0)))
    body = link("body", half)
    arm = Link("arm", collisions=(collision(Cylinder(0.13, 0.3)),))
    joints = (
        Joint("body_joint", "fixed", "base", "body"),
        Joint("arm_joint", "revolute", "body", "arm", Pose((0.075, 0.0, 0.0)), axis=(0.0, 0.0, 1.0)),
    )
    result = check(bundle_dir, Robot("r", links=(Link("base"), body, arm), joints=joints))
    assert result.diagnostics == []
    e = entry(result, "body")
    assert e["borrowed"] == [{"link": "arm", "joint": "arm_joint", "about": "collision[0]", "type": "cylinder"}]
    assert e["union"]["coverage"] == 1.0 and e["union"]["borrowed_share"] > 0.3


def hip_and_body() -> tuple[Link, Link, Link]:
    """A body whose mesh spans x -0.225..0.075 about its joint (its box covers the far half), a hip
    without geometry and a link carrying a cylinder that covers the near half about the joint's axis."""
    body = Link(
        "body",
        visuals=(Shape("visual", 0, BOX_MESH, Pose((-0.075, 0.0, 0.0))),),
        collisions=(collision(Box((0.15, 0.2, 0.1)), Pose((-0.15, 0.0, 0.0))),),
        location=SourceLocation(ROOT_FILE, 3),
    )
    return body, Link("hip"), Link("hip_shoulder", collisions=(collision(Cylinder(0.13, 0.3)),))


def test_geometry_of_a_link_fixed_to_the_neighbour_across_the_joint_is_shared(bundle_dir: Path) -> None:
    # Laikago's pattern: the cylinder about the thigh joint that covers the thigh's motor belongs to a
    # link fixed to the hip (``hip_shoulder``), not to the hip itself; it is the same at every thigh angle
    body, hip, shoulder = hip_and_body()
    joints = (
        Joint("hip_joint", "fixed", "base", "hip"),
        Joint("shoulder_joint", "fixed", "hip", "hip_shoulder", Pose((1.0, 0.0, 0.05))),
        Joint("body_joint", "revolute", "hip", "body", Pose((1.0, 0.0, 0.0)), axis=(0.0, 0.0, 1.0)),
    )
    result = check(bundle_dir, Robot("r", links=(Link("base"), hip, shoulder, body), joints=joints))
    assert result.diagnostics == []
    e = entry(result, "body")
    assert e["borrowed"] == [
        {"link": "hip_shoulder", "joint": "body_joint", "about": "collision[0]", "type": "cylinder"}
    ]
    assert e["union"]["coverage"] == 1.0 and e["union"]["borrowed_share"] > 0.3


def test_geometry_of_a_link_fixed_to_a_fixed_neighbour_is_not_shared(bundle_dir: Path) -> None:
    # the same cylinder two fixed joints away: a cluster of frames fixed to one another lends only
    # across one fixed joint, or each frame's placeholder would stand for the cluster's geometry
    body, hip, shoulder = hip_and_body()
    joints = (
        Joint("hip_joint", "fixed", "base", "hip"),
        Joint("shoulder_joint", "fixed", "hip", "hip_shoulder", Pose((1.0, 0.0, 0.05))),
        Joint("body_joint", "fixed", "base", "body", Pose((1.0, 0.0, 0.0))),
    )
    result = check(bundle_dir, Robot("r", links=(Link("base"), hip, shoulder, body), joints=joints))
    assert entry(result, "body")["borrowed"] == []
    assert [(d.code, d.link) for d in result.diagnostics] == [("GC301", "body")]


def test_report_section_is_deterministic(bundle_dir: Path) -> None:
    robot = robot_of(link("body", collision(Box((0.21, 0.2, 0.1)))), link("other", collision(Sphere(0.3))))
    first = check(bundle_dir, robot)
    second = check(bundle_dir, robot)
    assert json.dumps(first.sections, sort_keys=True) == json.dumps(second.sections, sort_keys=True)
    assert [d.data for d in first.diagnostics] == [d.data for d in second.diagnostics]
    json.dumps([d.data for d in first.diagnostics])  # JSON-ready


# --- corpus -------------------------------------------------------------------------------


def run_corpus(root: Path, search: Path | None = None, packages: dict[str, Path] | None = None) -> dict:
    """Load a corpus robot and run the meshes and fit families only (the rest is not ours
    and slow); the result shaped like the JSON report's parts we read."""
    from geomcheck.load import load_description
    from geomcheck.report.model import diagnostic_to_dict

    bundle = make_bundle(root, packages=packages, search=[search] if search else [])
    loaded = load_description(bundle)
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions(sweep=False))
    first, second = mesh_family.run(ctx), fit_family.run(ctx)
    diagnostics = sorted(first.diagnostics + second.diagnostics, key=Diagnostic.sort_key)
    return {
        "robot": {"links": len(loaded.robot.links)},
        "diagnostics": [diagnostic_to_dict(d) for d in diagnostics],
        "skipped": [{"check": k.check, "subject": k.subject, "reason": k.reason} for k in second.skipped],
        "sections": second.sections,
    }


def findings(report: dict, prefix: str = "GC3") -> list[dict]:
    return [d for d in report["diagnostics"] if d["code"].startswith(prefix)]


@pytest.mark.corpus
@pytest.mark.parametrize("robot", ["pr2_base.urdf.xacro", "pr2.urdf.xacro"])
def test_pr2_base_box_is_a_thin_slab_and_wheels_are_aligned(pr2_root: Path, robot: str) -> None:
    report = run_corpus(pr2_root / "pr2_description" / "robots" / robot, search=pr2_root)
    [base] = [d for d in findings(report) if d["link"] == "base_link"]
    assert base["code"] == "GC301" and base["severity"] == "error"
    assert "covers 4% of the mesh's height" in base["message"]
    assert "the box is 0.04 m tall (z 0.19 to 0.23 m), the mesh spans 0.903 m (z 0 to 0.903 m)" in base["message"]
    assert base["data"]["gaps_mm"]["z+"] == pytest.approx(-673.2, abs=0.5)
    wheels = [e for e in report["sections"]["links"] if e["link"].endswith("_wheel_link")]
    assert len(wheels) == 8
    assert not [d for d in findings(report) if d["link"].endswith("_wheel_link")]
    for wheel in wheels:
        fit = wheel["collisions"][0]["fit"]
        assert fit["coverage"] == 1.0 and fit["protrusion_max_mm"] == pytest.approx(4.2, abs=0.1)
    assert len(report["sections"]["links"]) == report["robot"]["links"]


@pytest.mark.corpus
def test_full_pr2_fit_findings(pr2_root: Path) -> None:
    report = run_corpus(pr2_root / "pr2_description" / "robots" / "pr2.urdf.xacro", search=pr2_root)
    reported = sorted(
        (d["severity"], d["code"], d["link"]) for d in findings(report) if d["severity"] in ("error", "warning")
    )
    # The 2009 collision model is a set of hand-made boxes, most of them far from the meshes
    # (the later PR2 descriptions replaced them with convex meshes). The arm links whose
    # convex/*.stlb meshes are absent from the corpus are fitted with the source meshes the
    # build decomposes (GC201, info), and fit; the gripper links of the missing pr2_defs
    # package are skipped (GC202). The small roll links (upper arm, forearm, wrist) and the
    # head pan are covered at rest by the adjacent links' collision geometry: info.
    assert reported == [
        ("error", "GC301", "base_link"),  # 4% of the base's height
        ("error", "GC301", "high_def_frame"),  # 1 cm placeholder box on a 4 cm camera
        ("error", "GC301", "high_def_optical_frame"),
        ("error", "GC301", "laser_tilt_mount_link"),  # 1 mm box on the 0.11 m tilting laser
        ("warning", "GC301", "bl_caster_rotation_link"),  # a 13 mm plate in a 0.19 m caster
        ("warning", "GC301", "br_caster_rotation_link"),  # (57% covered with the wheels' cylinders)
        ("warning", "GC301", "fl_caster_rotation_link"),
        ("warning", "GC301", "fr_caster_rotation_link"),
        ("warning", "GC301", "head_tilt_link"),  # 64 mm box, 182 mm head
        ("warning", "GC301", "torso_lift_link"),  # a 2 cm plate in the 0.8 m torso
    ]
    skipped = {s["subject"] for s in report["skipped"] if s["check"] == "fit"}
    assert "r_gripper_palm_link" in skipped and "l_upper_arm_link" not in skipped
    arm = next(e for e in report["sections"]["links"] if e["link"] == "l_upper_arm_link")
    assert arm["collisions"][0]["fit"]["coverage"] == 1.0


ERD_ERRORS = {
    # Laikago's thigh boxes are 34 mm wide while the thigh mesh carries the 81 mm knee motor
    # housing: the motor sticks out 64 mm, 41 to 43% of the thigh's surface is out (with the
    # tolerance of 15 mm for a 0.31 m thigh): a real under-approximation, a warning. The
    # Allegro phalanx boxes run joint to joint; the knuckles reaching 6 to 9 mm past each joint
    # lie in the next box: info.
    "laikago_description/urdf/laikago.urdf": [],
}


@pytest.mark.corpus
@pytest.mark.parametrize(
    "urdf",
    [
        "allegro_hand_description/urdf/allegro_left_hand.urdf",
        "allegro_hand_description/urdf/allegro_right_hand.urdf",
        "double_pendulum_description/urdf/double_pendulum.urdf",
        "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
        "double_pendulum_description/urdf/double_pendulum_simple.urdf",
        "laikago_description/urdf/laikago.urdf",
        "panda_description/urdf/panda.urdf",
        # Franka's capsules run joint to joint on the joint axes: a link's arm is covered by its
        # neighbour's capsule at every angle, which the fit counts (no finding).
        "panda_description/urdf/panda_collision.urdf",
        "quadruped_description/urdf/quadruped.urdf",
        "solo_description/robots/solo.urdf",
        "solo_description/robots/solo12.urdf",
    ],
)
def test_example_robot_data_errors_are_the_defended_ones(erd_root: Path, urdf: str) -> None:
    report = run_corpus(erd_root / "robots" / urdf, packages={"example-robot-data": erd_root})
    errors = sorted(
        (d["code"], d["link"])
        for d in report["diagnostics"]
        if d["code"][:3] in ("GC2", "GC3") and d["severity"] == "error"
    )
    assert errors == ERD_ERRORS.get(urdf, [])
    assert not [s for s in report["skipped"] if s["check"] == "fit"]
    assert len(report["sections"]["links"]) == report["robot"]["links"]


def test_finger_tolerance_follows_its_size(bundle_dir: Path) -> None:
    # a 1 cm x 1 cm x 11 cm finger whose box stops 8 mm short of the tip: within the fixed
    # 10 mm, but 8 mm is most of the finger's thickness (tolerance: a quarter of 1 cm)
    trimesh.creation.box(extents=(0.01, 0.01, 0.11)).export(bundle_dir / "meshes" / "finger.stl")
    short = collision(Box((0.01, 0.01, 0.102)), Pose((0.0, 0.0, -0.004)))
    result = check(bundle_dir, robot_of(link("finger", short, mesh=Mesh("meshes/finger.stl"))))
    d = only(result, "GC301")
    assert d.link == "finger" and d.data["tolerance"] == pytest.approx(0.0025)
    assert d.data["protrusion_max_mm"] == 8.0
    # the same defect on the 0.3 x 0.2 x 0.1 m body stays within its 10 mm tolerance
    body = collision(Box((0.3, 0.2, 0.092)), Pose((0.0, 0.0, -0.004)))
    assert check(bundle_dir, robot_of(link("body", body))).diagnostics == []


def test_capsule_cap_past_the_mesh_is_judged_with_its_capsule(bundle_dir: Path) -> None:
    # a capsule along z (cylinder from z = 0 to 0.2 m, radius 5 cm, a sphere of that radius on each end of its
    # axis) beside the box covering the 0.1 m tall mesh: the upper cap lies wholly past the mesh (Franka's
    # capsules run to the joint), the capsule's rounded end, not a displaced element
    def arm(dx: float) -> Link:
        return link(
            "arm",
            collision(Box(BOX_SIZE)),
            collision(Cylinder(0.05, 0.2), Pose((0.0, 0.0, 0.1)), 1),
            collision(Sphere(0.05), Pose((0.0, 0.0, 0.0)), 2),
            collision(Sphere(0.05), Pose((dx, 0.0, 0.2)), 3),
        )

    result = check(bundle_dir, robot_of(arm(0.0)))
    assert result.diagnostics == []
    assert [c["fit"]["capsule_cap"] for c in entry(result, "arm")["collisions"]] == [False, False, True, True]
    # 5 mm off the cylinder's end it caps nothing: a sphere away from the mesh
    result = check(bundle_dir, robot_of(arm(0.005)))
    d = only(result, "GC303")
    assert (d.link, d.about, d.severity) == ("arm", "collision[3]", Severity.ERROR)
    assert "sphere is away from the link's visual geometry" in d.message
    assert entry(result, "arm")["collisions"][3]["fit"]["capsule_cap"] is False


def test_element_on_the_neighbours_mesh_is_reported_for_its_own_link(bundle_dir: Path) -> None:
    # body's only collision cylinder sits on the revolute axis inside arm's mesh, 0.5 m away: it
    # takes arm's space at every joint position (a motor on the axis, carried by body: Unitree's
    # hips), and body's own mesh is left uncovered: a warning whose fix keeps the cylinder
    moved = collision(Cylinder(0.06, 0.1), Pose((0.5, 0.0, 0.0)))
    body = link("body", moved)
    arm = link("arm", collision(Box(BOX_SIZE)))
    joints = (
        Joint("body_joint", "fixed", "base", "body"),
        Joint("arm_joint", "revolute", "body", "arm", Pose((0.5, 0.0, 0.0)), axis=(0.0, 0.0, 1.0)),
    )
    result = check(bundle_dir, Robot("r", links=(Link("base"), body, arm), joints=joints))
    d = only(result, "GC303")
    assert (d.link, d.about, d.severity) == ("body", "collision[0]", Severity.WARNING)
    assert d.help is not None and d.help.startswith("Keep collision[0] if it stands for a part of arm carried by")
    assert d.data["covers_neighbour"] == "arm" and d.data["outside_own_mesh"] == 1.0
    assert d.data["link_coverage"] == 0.0
    assert "lies mostly outside link body's own mesh: 100% of it is outside" in d.message
    assert "on the mesh of neighbour arm" in d.message


def test_knuckle_past_the_joint_inside_the_next_box_is_info(bundle_dir: Path) -> None:
    # two 0.3 m links 0.2 m apart, their boxes meeting at the joint: each mesh reaches 50 mm
    # past the joint, into the next link's box (a finger's knuckles)
    first = link("first", collision(Box((0.25, 0.2, 0.1)), Pose((-0.025, 0.0, 0.0))))
    second = link("second", collision(Box((0.25, 0.2, 0.1)), Pose((0.025, 0.0, 0.0))))
    robot = Robot(
        "r",
        links=(Link("base"), first, second),
        joints=(
            Joint("first_joint", "fixed", "base", "first", Pose()),
            Joint("second_joint", "revolute", "first", "second", Pose((0.2, 0.0, 0.0)), axis=(0.0, 1.0, 0.0)),
        ),
    )
    result = check(bundle_dir, robot)
    found = {d.link: d for d in result.diagnostics if d.code == "GC301"}
    assert sorted(found) == ["first", "second"]
    assert {d.data["protrusion_max_mm"] for d in found.values()} == {50.0}
    assert all(d.severity == Severity.INFO for d in found.values())
    assert entry(result, "second")["union"]["coverage_at_rest"] == 1.0


def test_part_turning_inside_the_body_it_hangs_from_is_info(bundle_dir: Path) -> None:
    # a wheel-sized part on a revolute joint (+-0.1 rad about y) inside the collision box of the
    # body it hangs from: it stays inside at every position of the joint
    body = link("body", collision(Box((0.3, 0.3, 0.3))))
    rocker = link("rocker", mesh=WHEEL_MESH)
    limit = Limit(-0.1, 0.1)
    robot = Robot(
        "r",
        links=(Link("base"), body, rocker),
        joints=(
            Joint("body_joint", "fixed", "base", "body", Pose()),
            Joint("rocker_joint", "revolute", "body", "rocker", Pose(), axis=(0.0, 1.0, 0.0), limit=limit),
        ),
    )
    d = only(check(bundle_dir, robot), "GC305")
    assert (d.link, d.severity, d.data["covered_by"]) == ("rocker", Severity.INFO, "body")
    assert "stays within the collision geometry of body at every position of joint rocker_joint" in d.message
    # swinging a full turn about x, 0.2 m off centre, it leaves the box: a moving link without collision
    swing = Joint("rocker_joint", "continuous", "body", "rocker", Pose((0.0, 0.0, 0.2)), axis=(1.0, 0.0, 0.0))
    robot = Robot("r", links=robot.links, joints=(robot.joints[0], swing))
    d = only(check(bundle_dir, robot), "GC305")
    assert (d.severity, d.data["covered_by"]) == (Severity.WARNING, None)


def test_part_held_at_rest_by_the_links_around_it_is_info(bundle_dir: Path) -> None:
    # a 0.3 x 0.2 x 0.1 m knee housing with no collision between a thigh and a shin, each with a
    # box reaching over half of it; the hip between the thigh and the base has no collision
    # geometry and is passed through
    half = Box((0.16, 0.2, 0.1))
    thigh = link("thigh", collision(half, Pose((0.5 - 0.07, 0.0, 0.0))))
    knee, hip = link("knee"), Link("hip")
    shin = link("shin", collision(half, Pose((-0.07, 0.0, 0.0))))
    z = (0.0, 0.0, 1.0)
    robot = Robot(
        "r",
        links=(Link("base"), hip, thigh, knee, shin),
        joints=(
            Joint("hip_joint", "revolute", "base", "hip", Pose(), axis=z),
            Joint("thigh_joint", "fixed", "hip", "thigh", Pose()),
            Joint("knee_joint", "revolute", "thigh", "knee", Pose((0.5, 0.0, 0.0)), axis=z),
            Joint("shin_joint", "revolute", "knee", "shin", Pose((0.15, 0.0, 0.0)), axis=z),
        ),
    )
    result = check(bundle_dir, robot)
    d = next(d for d in result.diagnostics if d.code == "GC305" and d.link == "knee")
    assert (d.severity, d.data["held_at_rest_by"], d.data["covered_by"]) == (Severity.INFO, ["thigh", "shin"], None)
    assert d.message.endswith(
        "; at rest 100% of its visual lies within the collision geometry of the links around it (thigh, shin)"
    )
    # without the shin's box the thigh's holds half of it: a moving part without collision
    bare = Robot("r", links=(*robot.links[:4], link("shin")), joints=robot.joints)
    d = next(d for d in check(bundle_dir, bare).diagnostics if d.code == "GC305" and d.link == "knee")
    assert (d.severity, "held_at_rest_by" in d.data) == (Severity.WARNING, False)
    assert d.message.endswith("; it moves (joint knee_joint)")


def test_a_link_a_closing_constraint_holds_lends_its_collision_geometry_at_rest(bundle_dir: Path) -> None:
    # a finger whose own box covers its outer half, and an inner knuckle (another branch of the
    # tree) pinned to it by a loop-closing constraint, whose box covers the inner half at rest
    half = Box((0.15, 0.2, 0.1))
    finger = link("finger", collision(half, Pose((-0.075, 0.0, 0.0))))
    knuckle = Link("knuckle", collisions=(collision(half, Pose((0.075, 0.0, 0.0))),))
    z = (0.0, 0.0, 1.0)
    joints = (
        Joint("finger_joint", "revolute", "base", "finger", Pose((1.0, 0.0, 0.0)), axis=z),
        Joint("knuckle_joint", "revolute", "base", "knuckle", Pose((1.0, 0.0, 0.0)), axis=z),
    )
    open_chain = Robot("r", links=(Link("base"), finger, knuckle), joints=joints)
    result = check(bundle_dir, open_chain)
    coverage = entry(result, "finger")["union"]["coverage_at_rest"]
    assert 0.5 < coverage < 0.6 and only(result, "GC301").severity == Severity.WARNING
    closed = Robot("r", links=open_chain.links, joints=joints, closures=(("knuckle", "finger"),))
    result = check(bundle_dir, closed)
    assert entry(result, "finger")["union"]["coverage_at_rest"] == 1.0
    assert only(result, "GC301").severity == Severity.INFO


def test_a_wheel_judged_by_its_tyre(bundle_dir: Path) -> None:
    # a cylinder of the wheel's radius and half its width: the rest of the wheel lies within the tyre's
    # radius (a hub, a motor cover), which is not where a wheel touches anything
    tyre = collision(Cylinder(WHEEL_RADIUS, WHEEL_WIDTH / 2), Z_ONTO_Y)
    wheel = link("wheel", tyre, mesh=WHEEL_MESH)
    d = only(check(bundle_dir, robot_of(wheel, joint_type="continuous", axis=(0.0, 1.0, 0.0))), "GC301")
    assert d.severity is Severity.INFO
    assert "; the rest lies within the tyre's radius (a hub, a motor cover)" in d.message
    # the same cylinder on a link that does not spin is only half a part
    fixed = only(check(bundle_dir, robot_of(link("wheel", tyre, mesh=WHEEL_MESH))), "GC301")
    assert fixed.severity is not Severity.INFO and "tyre" not in fixed.message


def test_an_element_reaching_across_a_roll_joint_onto_the_next_link_is_not_misplaced(bundle_dir: Path) -> None:
    """Baxter's wrist cylinder runs past its own mesh down the forearm, coaxial with the roll joint
    between them, so it stays there at every angle: deliberate, not an element to move. Off the
    joint's axis it would turn with the joint: then it is misplaced."""

    rod = trimesh.creation.cylinder(radius=0.05, height=0.1, sections=64)
    rod.export(bundle_dir / "meshes" / "rod.stl")
    mesh = Mesh("meshes/rod.stl")

    def robot(x: float) -> Robot:
        # the body's rod (z -0.05 to 0.05) in a cylinder from z -0.02 to 0.18: 30 mm of the rod below it,
        # the upper 0.13 m over the arm's rod (z 0.05 to 0.15), past the roll joint at z 0.1
        body = link("body", collision(Cylinder(0.055, 0.2), Pose((x, 0.0, 0.08))), mesh=mesh)
        arm = link("arm", collision(Cylinder(0.055, 0.1)), mesh=mesh)
        joints = (
            Joint("body_joint", "fixed", "base", "body"),
            Joint("arm_joint", "revolute", "body", "arm", Pose((0.0, 0.0, 0.1)), axis=(0.0, 0.0, 1.0)),
        )
        return Robot("r", links=(Link("base"), body, arm), joints=joints)

    across = [d for d in check(bundle_dir, robot(0.0)).diagnostics if d.link == "body"]
    assert [d.code for d in across] == ["GC301"]
    assert across[0].data["protrusion_max_mm"] == pytest.approx(30.0, abs=1.0)
    # a fitted cylinder in its place would uncover the arm: the help keeps what covers it
    assert across[0].help == (
        "Enlarge the cylinder over the part of link body's mesh it leaves out, keeping the part that covers "
        "neighbour arm's mesh across the joint (it stays there at every joint position): a fitted replacement "
        "would leave that uncovered."
    )
    off_axis = [d for d in check(bundle_dir, robot(0.02)).diagnostics if d.link == "body"]
    assert [d.code for d in off_axis] == ["GC303"]
    assert "off its mesh" in off_axis[0].message


def test_a_placeholder_on_a_part_held_by_another_link_s_collision_is_info(bundle_dir: Path) -> None:
    """Baxter's head carries a 2 mm placeholder sphere, and two spheres on links fixed to the torso
    hold its mesh at every position of the head's pan: contacts reach the head through them."""

    def robot(shell_radius: float) -> Robot:
        # as on Baxter, the spheres hang from the base beside the torso the head turns on
        head = link("head", collision(Sphere(0.001)))
        torso = Link("torso", visuals=(Shape("visual", 0, Box((0.05, 0.05, 0.05)), Pose((0.0, 0.0, -0.5))),))
        shell = Link("shell", collisions=(collision(Sphere(shell_radius)),))
        joints = (
            Joint("torso_joint", "fixed", "base", "torso"),
            Joint("shell_joint", "fixed", "base", "shell", Pose((0.05, 0.0, 0.0))),  # off the pan axis
            Joint("head_pan", "revolute", "torso", "head", axis=(0.0, 0.0, 1.0)),
        )
        return Robot("r", links=(Link("base"), torso, shell, head), joints=joints)

    # the 0.3 x 0.2 x 0.1 m head reaches 0.187 m from the pan axis's origin: a 0.3 m sphere 50 mm off it holds
    # the head at every pan angle
    [held] = [d for d in check(bundle_dir, robot(0.3)).diagnostics if d.link == "head"]
    assert (held.code, held.severity, held.data["held_by"]) == ("GC301", Severity.INFO, "shell")
    assert held.message.endswith(
        "; the link's mesh stays within the collision geometry of shell at every position of joint head_pan: "
        "contacts reach the part through that geometry"
    )
    [bare] = [d for d in check(bundle_dir, robot(0.1)).diagnostics if d.link == "head"]
    assert (bare.code, bare.severity) == ("GC301", Severity.ERROR) and "held_by" not in bare.data


def test_a_description_without_collision_is_one_finding_and_its_moving_parts_still_reach(bundle_dir: Path) -> None:
    # an exported hand: a palm, a plate bolted to it and a finger, drawn and without any collision
    # element: one warning on the root link says it, each link's own finding is info naming it; the
    # finger, drawn only, still sweeps its space: it reaches the plate (a part no collision stands for
    # still moves), which is not "out of reach of every moving body"
    palm = link("palm")
    plate = link("plate")
    finger = link("finger")
    joints = (
        Joint("plate_joint", "fixed", "palm", "plate", Pose((0.0, 0.0, 0.1))),
        Joint("finger_joint", "revolute", "palm", "finger", Pose((0.3, 0.0, 0.0)), axis=(0.0, 1.0, 0.0)),
    )
    result = check(bundle_dir, Robot("r", links=(palm, plate, finger), joints=joints))
    found = [d for d in result.diagnostics if d.code == "GC305"]
    loud = [d for d in found if d.severity is not Severity.INFO]
    assert [(d.link, d.about, d.severity) for d in loud] == [("palm", "every link", Severity.WARNING)]
    assert loud[0].message.startswith("none of the description's 3 links has collision geometry: 3 are drawn")
    assert sorted(loud[0].data["links_without"]) == ["finger", "palm", "plate"]
    quiet = {d.link: d.message for d in found if d.severity is Severity.INFO}
    assert sorted(quiet) == ["finger", "palm", "plate"]
    assert quiet["plate"].endswith(
        "one of 3 links drawn without collision in a description that has none (reported once, on palm)"
    )
    assert "moving link finger can reach it" in quiet["plate"]
