"""Links drawn alike are analysed once, and only links truly alike share results; the
structure and self-collision broad phases stay linear in the number of links."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import trimesh

from geomcheck.checks.structure import cycles
from geomcheck.load import load_description, make_bundle
from geomcheck.pipeline import run_check

WHEEL = '<origin rpy="1.5708 0 0"/><geometry><cylinder radius="0.08" length="0.04"/></geometry>'


def report_of(folder: Path, body: str) -> dict[str, Any]:
    root = folder / "robot.urdf"
    root.write_text(f'<robot name="r">{body}</robot>\n')
    return run_check(make_bundle(root, search=[])).to_dict()


def wheel_link(name: str, collision: str = WHEEL) -> str:
    return (
        f'<link name="{name}"><visual><geometry><mesh filename="wheel.stl"/></geometry></visual>'
        f"<collision>{collision}</collision></link>"
    )


def fixed(name: str, parent: str, child: str, x: float) -> str:
    return (
        f'<joint name="{name}" type="fixed"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{x} 0 0"/></joint>'
    )


def test_alike_links_get_equal_fits_and_unlike_ones_their_own(tmp_path: Path) -> None:
    wheel = trimesh.creation.cylinder(radius=0.08, height=0.04, sections=48)
    wheel.apply_transform(trimesh.transformations.rotation_matrix(1.5708, (1, 0, 0)))
    wheel.export(tmp_path / "wheel.stl")
    small = WHEEL.replace('radius="0.08"', 'radius="0.05"')
    body = '<link name="base"/>' + "".join(
        [
            wheel_link("w1") + fixed("j1", "base", "w1", 0.0),
            wheel_link("w2") + fixed("j2", "base", "w2", 1.0),
            wheel_link("w3", small) + fixed("j3", "base", "w3", 2.0),
            # w4 is drawn like w1 and w2, but a fixed neighbour's sphere covers it too
            wheel_link("w4") + fixed("j4", "base", "w4", 3.0),
            '<link name="cap"><collision><geometry><sphere radius="0.09"/></geometry></collision></link>',
            fixed("j5", "w4", "cap", 0.0),
        ]
    )
    links = {entry["link"]: entry for entry in report_of(tmp_path, body)["sections"]["links"]}
    fits = {name: links[name]["collisions"][0]["fit"] for name in ("w1", "w2", "w3", "w4")}
    assert fits["w1"] == fits["w2"]
    assert fits["w1"]["coverage"] == 1.0
    assert fits["w3"]["coverage"] < 0.9 and fits["w3"]["protrusion_max_mm"] == 30.0
    assert links["w4"]["borrowed"] == [{"link": "cap", "joint": "j5", "about": "collision[0]", "type": "sphere"}]
    assert links["w1"]["borrowed"] == []
    assert links["w4"]["union"]["borrowed_share"] > 0.0 == links["w1"]["union"]["borrowed_share"]


def test_a_long_chain_ending_in_a_loop_is_walked_once(tmp_path: Path) -> None:
    count = 20_000
    links = "".join(f'<link name="l{i}"/>' for i in range(count))
    joints = "".join(
        f'<joint name="j{i}" type="fixed"><parent link="l{i - 1}"/><child link="l{i}"/></joint>'
        for i in range(1, count)
    )
    # the chain's first link hangs from its second: every walk up the chain ends in that loop
    loop = '<joint name="back" type="fixed"><parent link="l1"/><child link="l0"/></joint>'
    root = tmp_path / "chain.urdf"
    root.write_text(f'<robot name="chain">{links}{joints}{loop}</robot>\n')
    robot = load_description(make_bundle(root, search=[])).robot
    found = list(cycles(robot))
    assert [(d.code, d.data["links"]) for d in found] == [("GC116", ["l0", "l1"])]
