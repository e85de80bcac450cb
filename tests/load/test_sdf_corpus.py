"""The corpus's Gazebo models: counts, meshes, wheel joints, and SDFormat 1.4 files meaning what
their 1.5 conversions say."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.load import load_description, make_bundle
from geomcheck.load.meshes import MeshStore
from geomcheck.model import Mesh
from tests.load.sdftools import assert_pose, world


def sdf_robots(corpus: Path) -> dict[str, dict[str, object]]:
    with (corpus / "robots.toml").open("rb") as handle:
        return {k: v for k, v in tomllib.load(handle).items() if v.get("format") == "sdf"}


def declared(path: Path, packages: dict[str, Path]) -> tuple[int, int, int]:
    """Links, joints and collision geometries a model file declares, its nested and included
    models counted (read with lxml alone, model:// through ``packages``)."""
    data = path.read_bytes()
    root = etree.fromstring(data[data.find(b"<?xml") :] if data.find(b"<?xml") > 0 else data)
    counts = np.zeros(3, dtype=int)

    def visit(model: etree._Element) -> None:
        counts[0] += len(model.findall("link"))
        counts[1] += len(model.findall("joint"))
        counts[2] += len(model.findall("link/collision"))
        for nested in model.findall("model"):
            visit(nested)
        for include in model.findall("include"):
            name = include.findtext("uri").strip().removeprefix("model://")  # type: ignore[union-attr]
            included = etree.parse(str(packages[name] / "model.sdf")).getroot()
            visit(included.find("model"))

    visit(root.find("model"))
    return int(counts[0]), int(counts[1]), int(counts[2])


@pytest.mark.parametrize("how", ["packages", "model path"])
def test_corpus_sdf_counts_and_meshes(corpus: Path, how: str) -> None:
    robots = sdf_robots(corpus)
    assert len(robots) == 7
    for name, entry in robots.items():
        root = (corpus / str(entry["root"])).resolve()
        packages = {k: (corpus / str(v)).resolve() for k, v in dict(entry["packages"]).items()}  # type: ignore[call-overload]
        if how == "packages":
            bundle = make_bundle(root, packages, display_root=corpus)
        else:  # each sdf/<folder>/ is a Gazebo model path: --search names it
            bundle = make_bundle(root, search=[root.parent.parent], display_root=corpus)
        loaded = load_description(bundle)
        robot = loaded.robot
        links, joints, collisions = declared(root, packages)
        assert len([link for link in robot.links if not link.synthetic]) == links, name
        anchors = [j for j in robot.joints if j.type == "fixed" and robot.link_map[j.parent].synthetic]
        assert len(robot.joints) - len(anchors) == joints, name
        assert sum(len(link.collisions) for link in robot.links) == collisions, name
        store = MeshStore(loaded.bundle)
        meshes = [s.geometry for link in robot.links for s in (*link.visuals, *link.collisions)]
        for mesh in meshes:
            if isinstance(mesh, Mesh):
                path = store.resolve(mesh.filename)
                assert isinstance(path, Path) and path.is_file(), (name, mesh.filename)
        assert all(s.location is not None and s.location.line for link in robot.links for s in link.collisions)


def test_corpus_pioneer_wheels_turn_about_their_joint_frames(corpus: Path) -> None:
    root = corpus / "sdf/pioneer2dx/pioneer2dx/model.sdf"
    robot = load_description(make_bundle(root, display_root=corpus)).robot
    hinge = robot.joint_map["left_wheel_hinge"]
    # the joint sits 0.03 along the wheel's z from its origin, the axis (0 1 0) in the model frame
    assert hinge.child == "left_wheel::left_wheel_hinge"
    frames = world(robot)
    axis_world = frames[hinge.child][:3, :3] @ np.asarray(hinge.axis)
    np.testing.assert_allclose(axis_world, (0, 1, 0), atol=1e-6)
    assert_pose(frames["left_wheel"], (0.1, 0.17, -0.05), frames["left_wheel"][:3, :3])  # chassis at z 0.16


@pytest.mark.parametrize("model", ["pioneer2dx", "simple_arm", "create"])
def test_corpus_sdformat_1_4_files_mean_what_their_1_5_conversions_say(corpus: Path, model: str) -> None:
    # Gazebo's model folders keep the 1.4 file beside the 1.5 one, into which libsdformat's
    # conversion wrote <use_parent_model_frame>true: the 1.4 axes are in the model frame
    folder = corpus / "sdf" / model / model
    old = load_description(make_bundle(folder / "model-1_4.sdf", display_root=corpus)).robot
    new = load_description(make_bundle(folder / "model.sdf", display_root=corpus)).robot
    assert [link.name for link in old.links] == [link.name for link in new.links]
    for a, b in zip(old.joints, new.joints, strict=True):
        assert (a.name, a.type, a.parent, a.child) == (b.name, b.type, b.parent, b.child)
        np.testing.assert_allclose(a.axis, b.axis, atol=1e-12, err_msg=a.name)
        np.testing.assert_allclose(a.origin.matrix(), b.origin.matrix(), atol=1e-12, err_msg=a.name)
    # pioneer's wheels are turned: its axis (0 1 0) read in the joint frame would be another one
    if model == "pioneer2dx":
        assert not np.allclose(new.joint_map["left_wheel_hinge"].axis, (0, 1, 0))
