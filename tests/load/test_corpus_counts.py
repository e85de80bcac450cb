"""Every MJCF and SDFormat robot of the corpus: the report counts links and joints as the
format's own tool does (MuJoCo's compiled model: its bodies but the world, ``nbody - 1``, and
``njnt``; SDFormat: the ``<link>`` and ``<joint>`` elements of the model, its nested and
included models', read here without geomcheck's reader), and no finding names an element the
file does not declare (a frame or joint geomcheck adds to model the format).

The reports are the session's (``corpus_reports``: each robot checked once per run).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

from tests.corpustools import CorpusReports, script

pytestmark = pytest.mark.corpus
CORPUS = script("corpus_robots").corpus_from_env()
ROBOTS = [r for r in script("corpus_robots").checked_robots(CORPUS) if r.format in ("mjcf", "sdf")] if CORPUS else []
WORLD = "world"  # the world frame a joint may name as its parent (MJCF's world body, SDFormat's world)


def mujoco_names(root: Path) -> tuple[list[str], list[str]]:
    """MuJoCo's bodies but the world, and its joints, by name (an unnamed body by its id,
    ``body<id>``, as reports name it; ``None`` for an unnamed joint)."""
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(root))
    bodies = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}" for b in range(1, model.nbody)]
    joints = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(model.njnt)]
    return bodies, joints


def parsed(path: Path) -> Any:
    """The root of an SDF file, read as Gazebo reads it: an ``<?xml?>`` declaration after a
    comment is ignored."""
    text = re.sub(r"(?<!^)<\?xml[^>]*\?>", "", path.read_text(encoding="utf-8").lstrip())
    return etree.fromstring(text.encode("utf-8"))


def sdf_model_file(folder: Path) -> Path:
    """The SDF file of a model folder: its model.config's ``<sdf>`` of the highest version."""
    config = parsed(folder / "model.config")
    entries = [
        (tuple(int(v) for v in (e.get("version") or "1.0").split(".")), (e.text or "").strip())
        for e in config.iter("sdf")
    ]
    return folder / max(entries)[1]


def sdf_names(path: Path, packages: dict[str, Path], prefix: str = "") -> tuple[list[str], list[str]]:
    """The scoped names of the ``<link>`` and ``<joint>`` elements of the model in ``path``,
    its nested models' and its includes' (``model://NAME`` on the robot's model path)."""
    model = parsed(path).find("model")
    assert model is not None, path
    return _model_names(model, path.parent, packages, prefix)


def _model_names(model: Any, folder: Path, packages: dict[str, Path], prefix: str) -> tuple[list[str], list[str]]:
    links: list[str] = []
    joints: list[str] = []
    for child in model:
        if child.tag == "link":
            links.append(prefix + child.get("name"))
        elif child.tag == "joint":
            joints.append(prefix + child.get("name"))
        elif child.tag == "model":
            more = _model_names(child, folder, packages, f"{prefix}{child.get('name')}::")
            links += more[0]
            joints += more[1]
        elif child.tag == "include":
            uri = (child.findtext("uri") or "").strip()
            name, _, rest = uri.removeprefix("model://").partition("/")
            target = packages[name] if name in packages else folder.parent / name
            target = target / rest if rest else target
            included = parsed(sdf_model_file(target) if target.is_dir() else target).find("model")
            scope = (child.findtext("name") or "").strip() or included.get("name")
            more = _model_names(included, target, packages, f"{prefix}{scope}::")
            links += more[0]
            joints += more[1]
    return links, joints


def declared(robot: Any) -> tuple[list[str], list[str]]:
    if robot.format == "mjcf":
        bodies, joints = mujoco_names(robot.root)
        return [b for b in bodies if b], [j for j in joints if j]
    return sdf_names(robot.root, dict(robot.packages))


@pytest.mark.parametrize("robot", ROBOTS, ids=[r.name for r in ROBOTS])
def test_counts_are_the_formats_own_and_findings_name_what_the_file_declares(
    corpus_reports: CorpusReports, robot: Any
) -> None:
    report = corpus_reports[robot.name]
    if robot.format == "mjcf":
        bodies, joints = mujoco_names(robot.root)
        expected = (len(bodies), len(joints))
    else:
        links_declared, joints_declared = sdf_names(robot.root, dict(robot.packages))
        expected = (len(links_declared), len(joints_declared))
    assert (report["robot"]["links"], report["robot"]["joints"]) == expected
    links, joints = declared(robot)
    model = report["sections"]["model"]
    assert [e["name"] for e in model["links"]] == links or robot.format == "mjcf"  # MJCF may leave a body unnamed
    assert {e["name"] for e in model["joints"]} >= set(joints)
    known_links, known_joints = {*links, WORLD}, set(joints)
    for d in report["diagnostics"]:
        named = [d["link"]] if d["link"] else list(d["links"] or ())
        assert set(named) <= known_links, (d["code"], d["message"])
        assert d["joint"] is None or d["joint"] in known_joints, (d["code"], d["message"])
        for other in d["data"].get("joints", []) if isinstance(d["data"], dict) else ():
            assert other in known_joints, (d["code"], d["message"])
    for joint in model["joints"]:
        assert joint["parent"] in known_links and joint["child"] in known_links, joint["name"]
