"""Every robot of ``robots.toml`` zipped as its package tree: the root the service takes when a
request names none is the one ``robots.toml`` names, or one that loads the same robot (a MuJoCo
scene around it, a wrapper taking its default variant), or, when the tree holds several robots
nothing in it tells apart (create_1 and create_2, example-robot-data's dozen), none: the
service asks, listing the named root among the equally likely ones.

The zip holds the tree as a person would upload it, meshes included: choosing a root reads
which mesh files are there (a robot whose own meshes the upload lacks is not the one uploaded),
though never their contents, and no check is run here. Images and documents are left out.
"""

from __future__ import annotations

import io
import os
import re
import zipfile
from functools import cache
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from geomcheck.load import load_description, make_bundle
from tests.corpus_robots import corpus_from_env, corpus_robot, corpus_robots

LEFT_OUT = (".png", ".jpg", ".jpeg", ".gif", ".bmp", ".tif", ".zip", ".pdf")
ALL_FORMATS = ("urdf", "mjcf", "sdf")


def tree_of(robot: Any) -> Path:
    """The folder holding the robot's root file and every package it names."""
    folders = [str(p) for p in robot.packages.values()] + [str(robot.root.parent)]
    return Path(os.path.commonpath(folders))


def zipped(tree: Path, folders: list[Path]) -> bytes:
    files = {path for folder in folders for path in folder.rglob("*") if path.is_file()}
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED) as archive:
        for path in sorted(files):
            if not path.name.lower().endswith(LEFT_OUT):
                archive.write(path, path.relative_to(tree).as_posix())
    return buffer.getvalue()


@pytest.fixture(scope="module")
def service(tmp_path_factory: pytest.TempPathFactory) -> Any:
    from api.http.app import create_app
    from api.settings import Settings

    with TestClient(create_app(Settings(data_dir=tmp_path_factory.mktemp("roots") / "data"))) as client:
        yield client


@cache
def answer(service: TestClient, tree: Path, folders: tuple[Path, ...]) -> dict[str, Any]:
    response = service.post(
        "/v1/root-candidates", content=zipped(tree, list(folders)), headers={"content-type": "application/zip"}
    )
    assert response.status_code == 200, response.text
    body: dict[str, Any] = response.json()
    return body


def robot_shape(root: Path, robot: Any) -> tuple[Any, ...]:
    """What makes two roots the same robot: its links with their collision counts, and its joints."""
    loaded = load_description(make_bundle(root, packages=robot.packages), robot.args)
    links = sorted((link.name, len(link.collisions)) for link in loaded.robot.links)
    joints = sorted((joint.name, joint.type) for joint in loaded.robot.joints)
    return links, joints


def params() -> list[Any]:
    corpus = corpus_from_env()
    if corpus is None:
        return []
    return [pytest.param(robot.name, id=robot.name) for robot in corpus_robots(corpus, ALL_FORMATS)]


@pytest.mark.corpus
@pytest.mark.parametrize("name", params())
def test_the_root_chosen_without_root_is_the_named_one_or_the_same_robot(
    service: TestClient, corpus: Path, name: str
) -> None:
    robot = corpus_robot(corpus, name)
    tree = tree_of(robot)
    body = answer(service, tree, tuple([*robot.packages.values(), robot.root.parent]))
    named = robot.root.relative_to(tree).as_posix()
    # roots robots.toml names in the same tree (the PR2 and its base; example-robot-data's robots)
    siblings = {
        r.root.relative_to(tree).as_posix()
        for r in corpus_robots(corpus, ALL_FORMATS)
        if tree_of(r) == tree and r.root.is_relative_to(tree)
    }
    chosen = body["chosen"]
    if chosen is None:  # several robots nothing in the tree tells apart: the named one among them
        tied = re.search(r"nothing in the upload says which: ([^;]+)", body["why"])
        assert tied is not None, body["why"]
        assert len(re.split(r", | and \d+ more", tied.group(1))) >= 2
        assert named in [c["path"] for c in body["candidates"]]
        return
    assert chosen["reason"]
    if chosen["path"] in siblings:
        return
    assert robot_shape(tree / chosen["path"], robot) == robot_shape(robot.root, robot), (chosen, named)
