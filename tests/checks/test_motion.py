"""GC420 (geomcheck.checks.motion): a joint that turns fully spins a round part about its own axis."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from geomcheck.checks import CheckContext, motion
from geomcheck.diagnostics import Diagnostic
from geomcheck.load import ExpandedDocument, LoadedDescription, MeshStore, make_bundle
from geomcheck.model import Box, Joint, Limit, Link, Mesh, Pose, Robot, Shape, SourceLocation
from geomcheck.options import CheckOptions

ROOT_FILE = "robot.urdf"
RADIUS, WIDTH = 0.1, 0.04  # a wheel or a flange: a disc round about its local y axis [m]
DISC = Mesh("meshes/disc.stl")
SQUARE = Mesh("meshes/square.stl")


@pytest.fixture
def bundle_dir(tmp_path: Path) -> Path:
    (tmp_path / ROOT_FILE).write_text("<robot name='r'/>\n")
    (tmp_path / "meshes").mkdir()
    disc = trimesh.creation.cylinder(radius=RADIUS, height=WIDTH, sections=48)
    disc.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1, 0, 0)))  # axis z onto y
    disc.export(tmp_path / "meshes" / "disc.stl")
    trimesh.creation.box(extents=(2 * RADIUS, WIDTH, 2 * RADIUS)).export(tmp_path / "meshes" / "square.stl")
    return tmp_path


def robot(axis: tuple[float, float, float], joint_type: str = "continuous", mesh: Mesh = DISC, **kw: object) -> Robot:
    part = Link("part", visuals=(Shape("visual", 0, mesh),), location=SourceLocation(ROOT_FILE, 3))
    joint = Joint("turn", joint_type, "base", "part", Pose((0.5, 0.0, 0.2)), axis=axis, **kw)  # type: ignore[arg-type]
    return Robot("r", links=(Link("base", visuals=(Shape("visual", 0, Box((0.5, 0.5, 0.1))),)), part), joints=(joint,))


def findings(bundle_dir: Path, r: Robot) -> list[Diagnostic]:
    bundle = make_bundle(bundle_dir / ROOT_FILE)
    document = ExpandedDocument(text="", root=ROOT_FILE, sources={}, is_xacro=False)
    loaded = LoadedDescription(bundle=bundle, robot=r, document=document, diagnostics=())
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions(sweep=False))
    return motion.run(ctx).diagnostics


def test_a_wheel_turned_about_its_axle_is_no_finding(bundle_dir: Path) -> None:
    assert findings(bundle_dir, robot((0.0, 1.0, 0.0))) == []
    assert findings(bundle_dir, robot((0.0, -1.0, 0.0))) == []


def test_a_wheel_turned_about_a_diameter(bundle_dir: Path) -> None:
    [d] = findings(bundle_dir, robot((0.0, 0.0, 1.0)))
    assert (d.code, d.joint, d.about) == ("GC420", "turn", "axis")
    assert d.data["part_axis"] == [0.0, 1.0, 0.0] and d.data["angle_deg"] == 90.0
    assert d.data["radius"] == pytest.approx(RADIUS, rel=0.01) and d.data["length"] == pytest.approx(WIDTH, rel=0.01)
    assert d.message.startswith(
        "joint turn turns link part about (0, 0, 1), but the link's geometry is round about (0, 1, 0)"
    )
    assert '<axis xyz="0 1 0"/>' in d.help


def test_a_flange_on_a_wrist_that_turns_more_than_a_full_turn(bundle_dir: Path) -> None:
    limit = Limit(lower=-2 * np.pi, upper=2 * np.pi, effort=1.0, velocity=1.0)
    [d] = findings(bundle_dir, robot((1.0, 0.0, 0.0), "revolute", limit=limit))
    assert d.data["angle_deg"] == 90.0


def test_a_part_tilted_less_than_a_full_turn_is_not_judged(bundle_dir: Path) -> None:
    # a round sensor on a tilt joint turns about a diameter on purpose
    limit = Limit(lower=-0.5, upper=0.5, effort=1.0, velocity=1.0)
    assert findings(bundle_dir, robot((0.0, 0.0, 1.0), "revolute", limit=limit)) == []


def test_a_square_plate_is_not_round(bundle_dir: Path) -> None:
    assert findings(bundle_dir, robot((0.0, 0.0, 1.0), mesh=SQUARE)) == []


def test_a_disc_hanging_off_its_joint_is_not_judged(bundle_dir: Path) -> None:
    # a crank: the joint sits a whole radius off the disc's axis
    part = Link("part", visuals=(Shape("visual", 0, DISC, Pose((RADIUS, 0.0, 0.0))),))
    joint = Joint("turn", "continuous", "base", "part", axis=(0.0, 0.0, 1.0))
    assert findings(bundle_dir, Robot("r", links=(Link("base"), part), joints=(joint,))) == []
