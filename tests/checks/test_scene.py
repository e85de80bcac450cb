"""The ``scene`` section (what the HTML report's 3D view draws): the links where the
kinematics puts them, the frame tree posing them as Kinematics does for any joint values,
each mesh once, decimated within the budget; for URDF, MJCF and SDFormat alike."""

from __future__ import annotations

import base64
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from geomcheck.checks import CheckContext
from geomcheck.checks import scene as scene_family
from geomcheck.kinematics import Kinematics
from geomcheck.load import LoadedDescription, MeshStore, load_description, make_bundle
from geomcheck.load.meshes import LoadedMesh
from geomcheck.model import Mesh
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report.section_scene import Scene, pose_matrix
from geomcheck.thresholds import Thresholds
from tests.corpus_robots import corpus_robot

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"


def scene_of(loaded: LoadedDescription, options: CheckOptions | None = None) -> dict[str, Any]:
    ctx = CheckContext(loaded=loaded, meshes=MeshStore(loaded.bundle), options=options or CheckOptions())
    sections = scene_family.run(ctx).sections
    return dict(sections["scene"])


@pytest.fixture(scope="module")
def example() -> LoadedDescription:
    return load_description(make_bundle(EXAMPLE))


def assert_placed_as_kinematics_places(loaded: LoadedDescription, section: dict[str, Any]) -> None:
    """World poses at the default pose, and the section's frame tree at random joint values,
    equal Kinematics' transforms."""
    kin = Kinematics(loaded.robot)
    scene = Scene.from_dict(section)
    names = [link.link for link in scene.links]
    assert names == [link.name for link in loaded.robot.links if link.has_geometry and link.name in kin.link_names]
    q0 = kin.default_configuration()
    expected = dict(zip(kin.link_names, kin.link_transforms(q0[None])[0], strict=True))
    for link in scene.links:
        assert np.allclose(pose_matrix(link.pose), expected[link.link], atol=1e-9), link.link
    rng = np.random.default_rng(7)
    for q in kin.sample(3, rng):
        posed = scene.link_poses({j.name: float(v) for j, v in zip(kin.joints, q, strict=True)})
        truth = dict(zip(kin.link_names, kin.link_transforms(q[None])[0], strict=True))
        for name in names:
            assert np.allclose(posed[name], truth[name], atol=1e-9), name


def test_the_example_scene_places_every_link_as_the_kinematics(example: LoadedDescription) -> None:
    section = scene_of(example)
    assert_placed_as_kinematics_places(example, section)
    scene = Scene.from_dict(section)
    assert scene.root == "base_footprint" and scene.unplaced == ()
    assert len(scene.links) == 14 and [v.joint for v in scene.variables][:2] == [
        "fl_caster_rotation_joint",
        "fl_caster_l_wheel_joint",
    ]
    base = next(link for link in scene.links if link.link == "base_link")
    assert base.collisions[0].label == "collision[0]"
    assert base.collisions[0].geometry == {"type": "box", "size": [0.65, 0.65, 0.04]}
    # each mesh file once: the eight wheels and four casters share theirs
    files = [m["file"] for m in scene.meshes]
    assert files == [f"package://pr2_base_example/meshes/{n}.stl" for n in ("base", "laser", "caster", "wheel")]
    assert json.loads(json.dumps(section)) == scene.to_dict()


def test_packed_meshes_decode_to_the_loaded_meshes(example: LoadedDescription) -> None:
    section = scene_of(example)
    store = MeshStore(example.bundle)
    for packed in section["meshes"]:
        loaded = store.get(Mesh(packed["file"], tuple(packed["scale"])))
        assert isinstance(loaded, LoadedMesh)
        grid = np.frombuffer(base64.b64decode(packed["positions"]), dtype="<u2").reshape(-1, 3)
        vertices = np.asarray(packed["origin"]) + packed["step"] * grid
        assert packed["triangles"] == packed["source_triangles"] == len(loaded.faces)  # under the budget: whole
        assert np.allclose(vertices.min(axis=0), loaded.vertices.min(axis=0), atol=packed["step"])
        assert np.allclose(vertices.max(axis=0), loaded.vertices.max(axis=0), atol=packed["step"])


def test_the_budget_decimates_for_display_only(example: LoadedDescription) -> None:
    options = CheckOptions(thresholds=Thresholds().with_overrides({"views": {"scene_triangles": 600}}))
    section = scene_of(example, options)
    counts = {m["file"].rsplit("/", 1)[-1]: (m["triangles"], m["source_triangles"]) for m in section["meshes"]}
    assert counts["wheel.stl"][1] == 768 and counts["wheel.stl"][0] <= 368  # 768 * 600 / 1252
    assert counts["base.stl"] == (64, 64)  # the floor keeps a small mesh whole


def test_view_3d_false_leaves_the_section_out() -> None:
    bundle = make_bundle(EXAMPLE)
    report = run_check(bundle, CheckOptions(view_3d=False, sweep=False))
    assert "scene" not in report.sections and report.options["view_3d"] is False
    assert "views" in report.sections


@pytest.mark.corpus
@pytest.mark.parametrize("name", ["mjcf_trossen_wx250s", "sdf_pioneer2dx", "sdf_mpl_right_arm"])
def test_mjcf_and_sdformat_robots_have_their_scene(corpus: Path, name: str) -> None:
    robot = corpus_robot(corpus, name)
    loaded = load_description(make_bundle(robot.root, packages=robot.packages), robot.args)
    section = scene_of(loaded)
    assert_placed_as_kinematics_places(loaded, section)
    assert section["meshes"] and all(m["triangles"] > 0 for m in section["meshes"])
    assert section["unplaced"] == []
