"""GC5xx inertia and mass checks (geomcheck.checks.inertia) on small hand-built robots, and
on the shared corpus."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.inertia import run
from geomcheck.checks.inertia.bodies import rigid_bodies
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.load import ExpandedDocument, LoadedDescription, MeshStore, load_description, make_bundle
from geomcheck.model import Box, Cylinder, Inertial, Joint, Link, Mesh, Pose, Robot, Shape, SourceLocation
from geomcheck.options import CheckOptions
from geomcheck.rules import all_rules
from geomcheck.thresholds import Thresholds

ROOT_FILE = "robot.urdf"
INERTIAL_LINE = 12
LINK_LINE = 10
WHEEL_RADIUS = 0.079  # [m]
WHEEL_WIDTH = 0.034  # [m]
PR2_TENSOR = (0.012411765597, -0.000711733678, 0.00050272983, 0.015218160428, -0.000004273467, 0.011763977943)
PR2_WHEEL_MASS = 0.44036  # [kg]
PR2_HUB_MASS = 3.473082  # [kg]
WHEEL_MESH = Mesh("meshes/wheel.stl")
TURN_Z_ONTO_Y = Pose(rpy=(np.pi / 2, 0.0, 0.0))


@pytest.fixture
def bundle_dir(tmp_path: Path) -> Path:
    """A bundle folder with the root file and a wheel mesh (radius 0.079 m, width 0.034 m, axis y)."""
    (tmp_path / ROOT_FILE).write_text("<robot name='r'/>\n")
    (tmp_path / "meshes").mkdir()
    wheel = trimesh.creation.cylinder(radius=WHEEL_RADIUS, height=WHEEL_WIDTH, sections=64)
    wheel.apply_transform(TURN_Z_ONTO_Y.matrix())
    wheel.export(tmp_path / "meshes" / "wheel.stl")
    return tmp_path


def inertial(mass: float, tensor: tuple[float, ...] = PR2_TENSOR, xyz=(0.0, 0.0, 0.0)) -> Inertial:
    ixx, ixy, ixz, iyy, iyz, izz = tensor
    return Inertial(mass, Pose(xyz), ixx, ixy, ixz, iyy, iyz, izz, location=SourceLocation(ROOT_FILE, INERTIAL_LINE))


def solid_wheel_tensor(mass: float, axis: str = "y") -> tuple[float, ...]:
    """Solid cylinder of the wheel's size with its axis along ``axis``."""
    along = mass * WHEEL_RADIUS**2 / 2
    across = mass * (3 * WHEEL_RADIUS**2 + WHEEL_WIDTH**2) / 12
    m = {a: along if a == axis else across for a in "xyz"}
    return (m["x"], 0.0, 0.0, m["y"], 0.0, m["z"])


def wheel_link(name: str = "wheel", body: Inertial | None = None, mesh: Mesh = WHEEL_MESH) -> Link:
    return Link(
        name,
        inertial=body,
        visuals=(Shape("visual", 0, mesh),),
        collisions=(Shape("collision", 0, Cylinder(0.074792, WHEEL_WIDTH), TURN_Z_ONTO_Y),),
        location=SourceLocation(ROOT_FILE, LINK_LINE),
    )


def robot_of(*links: Link, joint_type: str = "continuous") -> Robot:
    """``base`` (massless root) with each link on its own joint of ``joint_type``."""
    base = Link("base", visuals=(Shape("visual", 0, Box((0.5, 0.5, 0.1))),))
    joints = tuple(Joint(f"{link.name}_joint", joint_type, "base", link.name, axis=(0.0, 1.0, 0.0)) for link in links)
    return Robot("r", links=(base, *links), joints=joints)


def check(bundle_dir: Path, robot: Robot, options: CheckOptions | None = None) -> FamilyResult:
    bundle = make_bundle(bundle_dir / ROOT_FILE)
    document = ExpandedDocument(text="", root=ROOT_FILE, sources={}, is_xacro=False)
    loaded = LoadedDescription(bundle=bundle, robot=robot, document=document, diagnostics=())
    return run(CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=options or CheckOptions()))


def codes(result: FamilyResult) -> list[tuple[str, str | None]]:
    return sorted((d.code, d.link) for d in result.diagnostics)


def only(result: FamilyResult, code: str) -> Diagnostic:
    found = [d for d in result.diagnostics if d.code == code]
    assert len(found) == 1, codes(result)
    return found[0]


def entry(result: FamilyResult, link: str) -> dict:
    return next(e for e in result.sections["inertia"] if e["link"] == link)


def test_every_rule_is_registered_with_documentation() -> None:
    rules = [r for r in all_rules() if r.family == "GC5"]
    assert [r.code for r in rules] == [*(f"GC50{i}" for i in range(1, 9)), "GC510", "GC511"]
    for rule in rules:
        assert rule.what and rule.why and rule.example and rule.fix and rule.summary
        assert rule.name == rule.name.lower() and " " not in rule.name


def test_solid_wheel_has_no_finding(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS, solid_wheel_tensor(PR2_WHEEL_MASS)))))
    assert result.diagnostics == []
    assert result.skipped == []
    wheel = entry(result, "wheel")
    assert wheel["positive_definite"] and wheel["triangle_ok"] and wheel["within_geometry"]
    assert wheel["com_inside_bounds"] and wheel["com_distance_outside"] == 0.0
    assert max(wheel["reach"]) == pytest.approx(np.hypot(WHEEL_RADIUS, WHEEL_WIDTH / 2), rel=1e-6)
    assert wheel["density"] == pytest.approx(PR2_WHEEL_MASS / (np.pi * WHEEL_RADIUS**2 * WHEEL_WIDTH), rel=0.01)


def test_pr2_wheel_inertia_is_impossible_for_the_wheel(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS))))
    d = only(result, "GC505")
    assert (d.link, d.about, d.severity) == ("wheel", "inertia", Severity.WARNING)
    assert d.location == SourceLocation(ROOT_FILE, INERTIAL_LINE)
    # iyy 0.01522 kg m^2 -> radius of gyration 0.186 m about the axle, against the 0.079 m wheel
    assert d.message.startswith("link wheel's inertia needs a radius of gyration of 0.186 m about the link y axis")
    assert "(moment 0.01522 kg m^2" in d.message
    assert "reaches only 0.079 m from that axis" in d.message
    assert "mass 0.44036 kg" in d.message
    assert d.data["worst"]["direction"] == "link y axis"
    assert d.data["worst"]["bound"] == "moment"
    assert d.data["worst"]["ratio"] == pytest.approx(5.54, abs=0.01)
    assert min(d.data["radius_of_gyration"]) > 2 * WHEEL_RADIUS
    assert entry(result, "wheel")["within_geometry"] is False
    # the help gives the tensor of the wheel's own solid, the one the fix writes (a solid disc about its axle)
    assert d.help is not None and d.help.startswith(
        "Recompute the tensor for this part from CAD; a uniform solid filling its geometry (the convex hull of its "
        "visual and collision shapes) with its 0.44036 kg has ixx "
    )
    iyy = float(re.search(r"iyy ([0-9.e-]+)", d.help).group(1))  # type: ignore[union-attr]
    assert iyy == pytest.approx(d.data["implied_inertia"]["iyy"], rel=1e-3)
    assert iyy == pytest.approx(PR2_WHEEL_MASS * WHEEL_RADIUS**2 / 2, rel=0.01)


def test_tensor_for_the_wrong_axis_is_reported_as_spread(bundle_dir: Path) -> None:
    body = inertial(PR2_WHEEL_MASS, solid_wheel_tensor(PR2_WHEEL_MASS, axis="z"))
    d = only(check(bundle_dir, robot_of(wheel_link(body=body))), "GC505")
    # the cylinder formula about z puts r^2/4 of spread along y: 0.0395 m rms in a 0.017 m half-width
    assert d.message.startswith(f"link {d.link}'s inertia spreads the mass 0.040 m (rms)")
    assert "along the principal axis 2 (the link y axis)" in d.message
    assert "extends only 0.017 m" in d.message
    assert "another orientation" in d.message


def test_triangle_inequality(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(0.1, (0.001, 0.0, 0.0, 0.001, 0.0, 0.005)))))
    d = only(result, "GC504")
    assert d.link == "wheel" and d.about == "inertia"
    assert "A + B = 0.001 + 0.001 = 0.002 kg m^2 is less than C = 0.005 kg m^2" in d.message
    assert d.data["excess"] == pytest.approx(0.003)
    assert entry(result, "wheel")["triangle_ok"] is False


def test_not_positive_definite_states_the_eigenvalues(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(1.0, (0.01, 0.02, 0.0, 0.01, 0.0, 0.01)))))
    d = only(result, "GC503")
    assert d.severity is Severity.ERROR
    assert "negative principal moment (principal moments -0.01, 0.01, 0.03 kg m^2)" in d.message
    assert d.data["principal_moments"] == pytest.approx([-0.01, 0.01, 0.03])
    assert "GC505" not in [c for c, _ in codes(result)]


def test_point_mass_is_only_a_warning_on_a_fixed_link(bundle_dir: Path) -> None:
    zero = (0.0,) * 6
    moving = check(bundle_dir, robot_of(wheel_link(body=inertial(0.1, zero))))
    assert only(moving, "GC503").severity is Severity.ERROR
    fixed = check(bundle_dir, robot_of(wheel_link(body=inertial(0.1, zero)), joint_type="fixed"))
    d = only(fixed, "GC503")
    assert d.severity is Severity.WARNING
    assert (
        d.message
        == "inertia tensor is not positive definite: it is zero, as for a point mass (principal moments 0, 0, 0 kg m^2)"
    )
    rod = check(
        bundle_dir, robot_of(wheel_link(body=inertial(0.1, (0.01, 0.0, 0.0, 0.01, 0.0, 0.0))), joint_type="fixed")
    )
    assert "it has a zero principal moment (principal moments 0, 0.01, 0.01 kg m^2)" in only(rod, "GC503").message


def test_moving_link_without_inertial(bundle_dir: Path) -> None:
    result = check(bundle_dir, robot_of(wheel_link(), heavy("other", 2.0)))
    d = only(result, "GC501")
    assert (d.link, d.about, d.severity) == ("wheel", "mass", Severity.ERROR)
    assert d.location == SourceLocation(ROOT_FILE, LINK_LINE)
    assert d.message == "link moves on continuous joint wheel_joint but has no <inertial>"
    assert [e["link"] for e in result.sections["inertia"]] == ["other"]


def frame_with_gripper(gripper_mass: float) -> Robot:
    """``base`` (5 kg), ``frame`` on a revolute joint without <inertial>, ``gripper`` (and its
    ``tool0`` frame) hanging below it on fixed joints, the gripper a solid wheel of ``gripper_mass``."""
    base = heavy("base", 5.0)
    frame = Link("frame", visuals=(Shape("visual", 0, Box((0.05, 0.05, 0.05))),))
    gripper = wheel_link("gripper", inertial(gripper_mass, solid_wheel_tensor(max(gripper_mass, 1e-9))))
    tool = Link("tool0")
    joints = (
        Joint("frame_joint", "revolute", "base", "frame", axis=(0.0, 0.0, 1.0)),
        Joint("gripper_joint", "fixed", "frame", "gripper", Pose((0.0, 0.0, 0.2))),
        Joint("tool_joint", "fixed", "gripper", "tool0", Pose((0.0, 0.0, 0.1))),
    )
    return Robot("r", links=(base, frame, gripper, tool), joints=joints)


def test_rigid_bodies_merge_links_across_fixed_joints() -> None:
    bodies = rigid_bodies(frame_with_gripper(PR2_WHEEL_MASS))
    assert bodies["gripper"] is bodies["tool0"] is bodies["frame"]
    body = bodies["frame"]
    assert (body.top, sorted(body.members), body.mass) == ("frame", ["frame", "gripper", "tool0"], PR2_WHEEL_MASS)
    assert body.members["tool0"][:3, 3] == pytest.approx([0.0, 0.0, 0.3])  # the two fixed origins composed
    assert (bodies["base"].top, bodies["base"].merged) == ("base", False)


def test_moving_frame_takes_the_mass_of_what_is_fixed_below_it(bundle_dir: Path) -> None:
    # pinocchio and Gazebo's fixed-joint lumping give frame's body the gripper's 0.44 kg
    assert codes(check(bundle_dir, frame_with_gripper(PR2_WHEEL_MASS))) == []


def test_moving_frame_with_a_massless_body_names_what_is_fixed_below(bundle_dir: Path) -> None:
    d = only(check(bundle_dir, frame_with_gripper(0.0)), "GC501")
    assert (d.link, d.severity) == ("frame", Severity.ERROR)
    assert d.message == (
        "link moves on revolute joint frame_joint but has no <inertial>, "
        "nor do the links fixed below it (gripper, tool0)"
    )
    assert d.data["body_links"] == ["gripper", "tool0"]


def test_zero_mass_on_a_moving_link_is_fine_when_its_body_has_mass(bundle_dir: Path) -> None:
    robot = frame_with_gripper(PR2_WHEEL_MASS)
    frame = replace(robot.links[1], inertial=inertial(0.0, (0.0,) * 6))
    robot = replace(robot, links=(robot.links[0], frame, *robot.links[2:]))
    assert [c for c in codes(check(bundle_dir, robot)) if c[0] in ("GC501", "GC502")] == []


def test_kinematics_only_description_is_one_info_finding(bundle_dir: Path) -> None:
    # no link of the robot has an <inertial> (ROS-Industrial support packages): written for planning
    result = check(bundle_dir, robot_of(wheel_link("a"), wheel_link("b"), wheel_link("c")))
    d = only(result, "GC501")
    assert (d.link, d.about, d.severity) == (None, "mass", Severity.INFO)
    assert d.message.startswith("no link has an <inertial>: a kinematics-only description (3 moving links)")
    assert d.data == {"moving_links": 3}
    assert d.help.startswith("Nothing to change for planning and display.")


def test_fixed_and_root_links_may_be_massless(bundle_dir: Path) -> None:
    assert check(bundle_dir, robot_of(wheel_link(), joint_type="fixed")).diagnostics == []
    root_with_zero_mass = Robot("r", links=(wheel_link(body=inertial(0.0, (0.0,) * 6)),))
    assert check(bundle_dir, root_with_zero_mass).diagnostics == []


@pytest.mark.parametrize(
    ("mass", "joint_type", "text"),
    [
        (0.0, "continuous", "mass is 0 kg on a link that moves on continuous joint wheel_joint"),
        (-2.5, "fixed", "mass is negative: -2.5 kg"),
        (float("nan"), "fixed", "mass is nan kg, not a finite number"),
    ],
)
def test_non_positive_mass(bundle_dir: Path, mass: float, joint_type: str, text: str) -> None:
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(mass)), joint_type=joint_type))
    d = only(result, "GC502")
    assert (d.link, d.about, d.message) == ("wheel", "mass", text)
    assert "GC505" not in [c for c, _ in codes(result)]


def test_centre_of_mass_outside_the_geometry(bundle_dir: Path) -> None:
    body = inertial(PR2_WHEEL_MASS, solid_wheel_tensor(PR2_WHEEL_MASS), xyz=(0.0, 0.0, 0.5))
    result = check(bundle_dir, robot_of(wheel_link(body=body)))
    d = only(result, "GC506")
    assert (d.link, d.about, d.severity) == ("wheel", "com", Severity.WARNING)
    assert "centre of mass (0, 0, 0.5) m lies 0.421 m outside the link's geometry" in d.message
    assert d.data["distance"] == pytest.approx(0.5 - WHEEL_RADIUS, abs=1e-6)
    assert entry(result, "wheel")["com_inside_bounds"] is False


def test_copied_inertia_names_the_original(bundle_dir: Path) -> None:
    hub = Link(
        "hub", inertial=inertial(PR2_HUB_MASS, xyz=(0.0, 0.0, 0.0)), visuals=(Shape("visual", 0, Box((0.2, 0.2, 0.2))),)
    )
    left = wheel_link("left_wheel", inertial(PR2_WHEEL_MASS))
    right = wheel_link("right_wheel", inertial(PR2_WHEEL_MASS))
    twin = Link("hub_twin", inertial=inertial(PR2_HUB_MASS), visuals=hub.visuals)
    result = check(bundle_dir, robot_of(hub, left, right, twin))
    copies = [d for d in result.diagnostics if d.code == "GC507"]
    assert [d.link for d in copies] == ["left_wheel", "right_wheel"]
    d = copies[0]
    assert d.severity is Severity.WARNING and d.about == "inertia"
    assert "is exactly that of link hub, although the masses differ by a factor 7.9" in d.message
    assert "(0.44036 kg against 3.47308 kg)" in d.message
    assert d.data["copied_from"] == "hub"
    assert entry(result, "left_wheel")["copied_from"] == "hub"
    assert entry(result, "hub_twin")["copied_from"] is None


def test_one_tensor_typed_on_many_parts_is_one_finding(bundle_dir: Path) -> None:
    """MuJoCo's TIAGo writes diaginertia 0.4 on every body: not a copy from one part but one
    value typed for all; reported once, on the lightest part, its tensor-over-geometry findings
    counted in it."""
    placeholder = (0.4, 0.0, 0.0, 0.4, 0.0, 0.4)

    def typed(mass: float, line: int) -> Inertial:
        return replace(inertial(mass, placeholder), location=SourceLocation(ROOT_FILE, line))

    hub = Link("hub", inertial=typed(28.0, 20), visuals=(Shape("visual", 0, Box((0.6, 0.6, 0.6))),))
    wheels = [wheel_link(f"wheel_{i}", typed(mass, 30 + i)) for i, mass in enumerate((1.8, 1.5, 0.05))]
    result = check(bundle_dir, robot_of(hub, *wheels))
    assert codes(result) == [("GC507", "wheel_2")]
    d = result.diagnostics[0]
    assert (d.severity, d.about, d.location) == (Severity.WARNING, "inertia", SourceLocation(ROOT_FILE, 32))
    assert d.message == (
        "inertia tensor (ixx, ixy, ixz, iyy, iyz, izz) = (0.4, 0, 0, 0.4, 0, 0.4) kg m^2 is written on 4 links whose "
        "masses range from 0.05 kg (wheel_2) to 28 kg (hub), a factor 560: one tensor typed for every part, computed "
        "for none (also on hub, wheel_0, wheel_1); on 3 of them it is more than the part's geometry allows"
    )
    assert d.data["also"] == ["hub", "wheel_0", "wheel_1"]
    assert d.data["exceeds_geometry"] == ["wheel_0", "wheel_1", "wheel_2"]
    assert (d.data["copied_from"], d.data["mass_ratio"], d.data["shared_sources"]) == ("hub", 560.0, 4)


def test_a_tensor_a_macro_writes_for_many_parts_stays_a_copy_per_part(bundle_dir: Path) -> None:
    """Three wheels from one macro line and their hub: two <inertial> elements, a copy, not a
    tensor typed for every part; each wheel keeps its own findings."""
    hub = Link("hub", inertial=inertial(PR2_HUB_MASS), visuals=(Shape("visual", 0, Box((0.2, 0.2, 0.2))),))
    macro = replace(inertial(PR2_WHEEL_MASS), location=SourceLocation(ROOT_FILE, 40))
    result = check(bundle_dir, robot_of(hub, *(wheel_link(f"wheel_{i}", macro) for i in range(3))))
    assert [d.link for d in result.diagnostics if d.code == "GC507"] == ["wheel_0", "wheel_1", "wheel_2"]
    assert [d.link for d in result.diagnostics if d.code == "GC505"] == ["wheel_0", "wheel_1", "wheel_2"]


def test_mass_in_grams_is_implausible_density(bundle_dir: Path) -> None:
    grams = PR2_WHEEL_MASS * 1000
    # tensor scaled with the mass: the radius of gyration is right, only the density gives it away
    body = inertial(grams, solid_wheel_tensor(grams))
    result = check(bundle_dir, robot_of(wheel_link(body=body)))
    assert codes(result) == [("GC508", "wheel")]
    d = result.diagnostics[0]
    assert d.about == "mass"
    assert "average density of 6.616e+05 kg/m^3, 29.3 times that of osmium (22600 kg/m^3)" in d.message
    assert d.help.startswith("The mass looks like grams: 0.44036 kg would give 661.")


def test_a_mass_too_heavy_for_the_part_its_mesh_draws_says_what_the_part_weighs(bundle_dir: Path) -> None:
    """Fourier's hand (robosuite) types 0.5 kg on every finger link: the meshes draw the fingers,
    so the mass is what to change, and the help says what the part weighs in metal."""
    mass = 20.0  # [kg]: 30,000 kg/m^3, and not grams of a real part either (0.02 kg would be 30 kg/m^3)
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(mass, solid_wheel_tensor(mass)))))
    d = only(result, "GC508")
    hull = d.data["hull_volume"]  # the 64-sided wheel's: a little under pi r^2 w
    assert hull == pytest.approx(np.pi * WHEEL_RADIUS**2 * WHEEL_WIDTH, rel=0.01)
    assert d.help.startswith(
        f"The link's meshes draw the part, so the mass is wrong for it: its hull would weigh {hull * 2700:.3g} kg of "
        f"aluminium, {hull * 7850:.3g} kg of steel. "
    )


def test_missing_mesh_skips_the_geometry_checks_only(bundle_dir: Path) -> None:
    body = inertial(PR2_WHEEL_MASS, (0.001, 0.0, 0.0, 0.001, 0.0, 0.005))
    result = check(bundle_dir, robot_of(wheel_link(body=body, mesh=Mesh("meshes/gone.stl"))))
    assert codes(result) == [("GC504", "wheel")]
    [skipped] = result.skipped
    assert (skipped.check, skipped.subject) == ("inertia-geometry", "wheel")
    assert skipped.reason.startswith("visual[0] mesh unavailable: mesh file not found: ")
    assert "gone.stl" in skipped.reason
    assert entry(result, "wheel")["within_geometry"] is None


def test_link_without_geometry_is_skipped(bundle_dir: Path) -> None:
    bare = Link("sensor", inertial=inertial(0.1, (1e-4, 0.0, 0.0, 1e-4, 0.0, 1e-4)))
    result = check(bundle_dir, robot_of(bare))
    assert result.diagnostics == []
    assert [(s.subject, s.reason) for s in result.skipped] == [("sensor", "link has no visual or collision geometry")]


def test_section_has_one_entry_per_link_with_inertial_in_order(bundle_dir: Path) -> None:
    links = [wheel_link(name, inertial(PR2_WHEEL_MASS, solid_wheel_tensor(PR2_WHEEL_MASS))) for name in "cab"]
    result = check(bundle_dir, robot_of(links[0], wheel_link("no_inertial"), *links[1:]))
    section = result.sections["inertia"]
    assert [e["link"] for e in section] == ["c", "a", "b"]
    documented = ["link", "mass", "com", "principal_moments", "principal_axes", "geometry_bound"]
    documented += ["radius_of_gyration", "reach", "positive_definite", "triangle_ok", "within_geometry"]
    assert list(section[0])[: len(documented) + 1] == [*documented, "com_inside_bounds"]
    # a solid wheel: two equal moments have no axis of their own (any in their plane is
    # principal, and which one a solver returns depends on the CPU); the wheel's axis is given
    axes = section[0]["principal_axes"]
    (given,) = [a for a in axes if a is not None]
    assert axes.count(None) == 2
    assert given == pytest.approx([0.0, 1.0, 0.0], abs=1e-6)


def test_same_input_gives_the_same_bytes(bundle_dir: Path) -> None:
    robot = robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS)))
    first, second = check(bundle_dir, robot), check(bundle_dir, robot)
    assert json.dumps(first.sections, sort_keys=True) == json.dumps(second.sections, sort_keys=True)
    assert [d.message for d in first.diagnostics] == [d.message for d in second.diagnostics]


# --- the shared corpus ------------------------------------------------------------------

PR2_WHEELS = [f"{c}_caster_{s}_wheel_link" for c in ("bl", "br", "fl", "fr") for s in "lr"]


def check_description(root_file: Path, packages: dict[str, Path] | None = None, search: tuple[Path, ...] = ()):
    """Load a corpus description and run the inertia family alone (fast: no other family)."""
    bundle = make_bundle(root_file, packages=packages, search=search)
    loaded = load_description(bundle)
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions(sweep=False))
    return loaded, run(ctx)


def line_of(path: Path, after: str, text: str) -> int:
    """1-based line of the first ``text`` after the first ``after`` in ``path``."""
    lines = path.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if after in line)
    return next(i for i in range(start, len(lines)) if text in lines[i]) + 1


@pytest.mark.corpus
def test_pr2_2009_base_wheels_are_impossible(pr2_root: Path) -> None:
    package = pr2_root / "pr2_description"
    loaded, result = check_description(package / "robots" / "pr2_base.urdf.xacro", search=(pr2_root,))
    assert len(loaded.robot.links) == 14
    impossible = {d.link: d for d in result.diagnostics if d.code == "GC505"}
    # the eight wheels (0.44036 kg, radius 0.079 m) and the base laser (1 g, 1e-4 kg m^2 in a 1 mm box)
    assert sorted(impossible) == ["base_laser_link", *PR2_WHEELS]
    wheel = impossible["fl_caster_l_wheel_link"]
    assert "radius of gyration of 0.187 m" in wheel.message
    assert "reaches only 0.079 m" in wheel.message
    # principal moments 0.0115 to 0.0154 kg m^2: radii of gyration 0.161 to 0.187 m, over twice the radius
    assert min(wheel.data["radius_of_gyration"]) > 2 * WHEEL_RADIUS
    base_file = package / "urdf" / "base_v0" / "base.urdf.xacro"
    assert wheel.location is not None and wheel.location.file.endswith("urdf/base_v0/base.urdf.xacro")
    assert wheel.location.line == line_of(base_file, 'name="${parent}_${suffix}_wheel_link"', "<inertial>")
    copies = {d.link: d.data["copied_from"] for d in result.diagnostics if d.code == "GC507"}
    assert copies == dict.fromkeys(PR2_WHEELS, "bl_caster_rotation_link")
    hubs = {e["link"]: e for e in result.sections["inertia"] if e["link"].endswith("_caster_rotation_link")}
    assert len(hubs) == 4 and all(e["within_geometry"] and e["com_inside_bounds"] for e in hubs.values())
    base = next(e for e in result.sections["inertia"] if e["link"] == "base_link")
    assert base["within_geometry"] and base["com_inside_bounds"] and base["triangle_ok"]


@pytest.mark.corpus
def test_pr2_2009_full_robot(pr2_root: Path) -> None:
    root = pr2_root / "pr2_description" / "robots" / "pr2.urdf.xacro"
    loaded, result = check_description(root, search=(pr2_root,))
    assert len(loaded.robot.links) == 72
    assert len(result.sections["inertia"]) == 72
    by_code: dict[str, set[str]] = {}
    for d in result.diagnostics:
        by_code.setdefault(d.code, set()).add(str(d.link))
    assert set(PR2_WHEELS) <= by_code["GC505"]
    # sensor_mount_link and double_stereo_link: ixx = iyy = 0.001, izz = 0.01 kg m^2
    assert by_code["GC504"] == {"double_stereo_link", "sensor_mount_link"}
    # links with CAD inertias and real meshes are consistent with their geometry
    for link in ("base_link", "torso_lift_link", "head_pan_link", "head_tilt_link", "fl_caster_rotation_link"):
        assert link not in by_code["GC505"]
    assert "GC501" not in by_code and "GC502" not in by_code


# Every error- and warning-level GC5xx finding on example-robot-data, looked at one by one:
# - Allegro hand, fingers: the tensors have izz as large as ixx on segments that are long along z
#   (a tensor for another orientation) with large products of inertia; all but the thumb base
#   break the triangle inequality outright (link_1.0: 1.3e-5 + 7.1e-5 < 1e-4 kg m^2), so no body
#   has them (GC505 is not added on top for a tensor that is impossible anyway). MuJoCo refuses
#   them: errors; warnings on the fingertip segments (3.0, 7.0, 11.0, 15.0), whose fixed tips
#   make a merged body with a valid tensor, which is what MuJoCo (fusestatic) and pinocchio build.
#   The palm's centre of mass has the wrong sign of z (GC506).
# - double_pendulum_simple: base_link has 1 kg m^2 on 0.1 kg in a 5 cm box (radius of gyration
#   3.2 m), link2 0.002 kg m^2 on 0.3 kg in a 3.5 cm wide bar: placeholders.
# - Panda: franka's identified inertias (Gaz et al. 2019) are not physically consistent:
#   panda_link1 has ixx = 0.703 kg m^2 for 4.97 kg, a 0.38 m radius of gyration on a link whose
#   mesh reaches 0.16 m from that axis; link2 and link7 likewise; the hand's iyy exceeds its bound
#   by 6% (and link7 merged with the hand still exceeds). panda_collision.urdf has larger
#   collision shapes, so only link1 and link2 remain. Each finger's centre of mass lies outside the
#   finger (a light link: the finding says so and stays a warning). Every phalanx of the Allegro
#   hands has its centre of mass at its joint, 10-27 mm from the phalanx's centroid: one finding.
E, W = Severity.ERROR, Severity.WARNING
ALLEGRO_TIPS = (3, 7, 11, 15)
ERD_FINDINGS: dict[str, set[tuple[str, str, Severity]]] = {
    "allegro_left_hand.urdf": {
        ("GC504", f"link_{i}.0", W if i in ALLEGRO_TIPS else E) for i in (1, 2, 3, 5, 6, 7, 9, 10, 11, 12, 13, 14, 15)
    }
    | {("GC506", "palm_link", W), ("GC511", "link_0.0", W)},
    "double_pendulum.urdf": set(),
    "double_pendulum_continuous.urdf": set(),
    "double_pendulum_simple.urdf": {("GC505", "base_link", W), ("GC505", "link2", W)},
    "laikago.urdf": set(),
    "panda.urdf": {("GC505", f"panda_link{i}", W) for i in (1, 2, 7)}
    | {("GC505", "panda_hand", W)}
    | {("GC506", f"panda_{side}finger", W) for side in ("left", "right")},
    "panda_collision.urdf": {("GC505", "panda_link1", W), ("GC505", "panda_link2", W)}
    | {("GC506", f"panda_{side}finger", W) for side in ("left", "right")},
    "quadruped.urdf": set(),
    "solo.urdf": set(),
    "solo12.urdf": set(),
}
ERD_FINDINGS["allegro_right_hand.urdf"] = ERD_FINDINGS["allegro_left_hand.urdf"]


@pytest.mark.corpus
@pytest.mark.parametrize("name", sorted(ERD_FINDINGS))
def test_example_robot_data_findings_are_the_known_ones(erd_root: Path, name: str) -> None:
    [root] = list((erd_root / "robots").glob(f"*/*/{name}"))
    _, result = check_description(root, packages={"example-robot-data": erd_root})
    found = {(d.code, str(d.link), d.severity) for d in result.diagnostics if d.severity is not Severity.INFO}
    assert found == ERD_FINDINGS[name]


@pytest.mark.corpus
def test_allegro_palm_centre_of_mass_has_the_wrong_sign(erd_root: Path) -> None:
    root = erd_root / "robots" / "allegro_hand_description" / "urdf" / "allegro_right_hand.urdf"
    _, result = check_description(root, packages={"example-robot-data": erd_root})
    d = only(result, "GC506")
    # <inertial><origin xyz="0 0 0.0475"/> while the palm (and its collision box at z -0.0475) lies below z = 0.002
    assert d.link == "palm_link"
    assert d.data["com"] == [0.0, 0.0, 0.0475]
    assert d.data["distance"] == pytest.approx(0.0455, abs=0.001)


def test_impossible_tensor_is_not_also_reported_against_the_geometry(bundle_dir: Path) -> None:
    # moments 0.001, 0.001, 0.05 kg m^2 on 0.44 kg: breaks A + B >= C, and exceeds the wheel too
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS, (0.001, 0.0, 0.0, 0.001, 0.0, 0.05)))))
    assert codes(result) == [("GC504", "wheel")]
    assert entry(result, "wheel")["within_geometry"] is False


def test_thresholds_are_read_from_the_options(bundle_dir: Path) -> None:
    def options(**values: float) -> CheckOptions:
        return CheckOptions(thresholds=Thresholds().with_overrides({"inertia": values}))

    pr2_wheel = robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS)))
    assert codes(check(bundle_dir, pr2_wheel)) == [("GC505", "wheel")]
    # its worst ratio is a spread 35 times the bound
    assert check(bundle_dir, pr2_wheel, options(relative_tolerance=40.0)).diagnostics == []
    high_com = robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS, solid_wheel_tensor(PR2_WHEEL_MASS), (0, 0, 0.1))))
    assert codes(check(bundle_dir, high_com)) == [("GC506", "wheel")]  # 21 mm above the wheel
    assert check(bundle_dir, high_com, options(com_margin_m=0.05)).diagnostics == []


def heavy(name: str, mass: float) -> Link:
    """A link whose tensor is that of a solid wheel of ``mass``: consistent, no finding."""
    return wheel_link(name, inertial(mass, solid_wheel_tensor(mass)))


def codes_of(result: FamilyResult) -> list[str]:
    return [d.code for d in result.diagnostics]


def test_a_tensor_about_a_centre_of_mass_off_the_part_is_given_about_its_centroid_too(bundle_dir: Path) -> None:
    # the PR2 wheel's too-large tensor, its centre of mass 0.2 m off the wheel (GC506): the solid's
    # tensor about that point carries m d^2 = 0.44 kg * 0.04 m^2; the help gives the one about the
    # wheel's own centroid as well, for the corrected centre of mass
    result = check(bundle_dir, robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS, xyz=(0.0, 0.0, 0.2)))))
    assert {d.code for d in result.diagnostics} >= {"GC505", "GC506"}
    d = only(result, "GC505")
    assert d.help is not None and " The centre of mass it states is off the part (200 mm from its centroid)" in d.help
    about_stated = float(re.search(r"has ixx ([0-9.e-]+)", d.help).group(1))  # type: ignore[union-attr]
    about_centroid = float(re.search(r"write ixx ([0-9.e-]+)", d.help).group(1))  # type: ignore[union-attr]
    assert about_stated - about_centroid == pytest.approx(PR2_WHEEL_MASS * 0.2**2, rel=0.01)
    # a centre of mass on the part: no caveat
    plain = only(check(bundle_dir, robot_of(wheel_link(body=inertial(PR2_WHEEL_MASS)))), "GC505")
    assert plain.help is not None and "off the part" not in plain.help


def test_several_moving_links_without_an_inertial_are_one_finding(bundle_dir: Path) -> None:
    # three wheels without an <inertial> beside one with: one omission, one error on the first
    # naming the others, which stay as info saying so
    wheels = [wheel_link(f"wheel_{i}") for i in range(3)]
    result = check(bundle_dir, robot_of(*wheels, wheel_link("spare", body=inertial(PR2_WHEEL_MASS))))
    found = [d for d in result.diagnostics if d.code == "GC501"]
    loud = [d for d in found if d.severity is not Severity.INFO]
    assert [(d.link, d.severity) for d in loud] == [("wheel_0", Severity.ERROR)]
    assert loud[0].message == (
        "link moves on continuous joint wheel_0_joint but has no <inertial>; 2 more moving links have none: "
        "wheel_1, wheel_2"
    )
    assert loud[0].data["also_links"] == ["wheel_1", "wheel_2"]
    quiet = {d.link: d.message for d in found if d.severity is Severity.INFO}
    assert sorted(quiet) == ["wheel_1", "wheel_2"]
    assert quiet["wheel_2"].endswith("(one of several moving links without one, reported once, on wheel_0)")
