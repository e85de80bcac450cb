"""Numbers beyond the load limits are refused at load in every format, naming the element, and
the work an expansion would do is counted before it is done: an MJCF file's nested
``<replicate>``s and an SDFormat fan-out of includes are refused at once, naming the
construct; a long but legal chain of SDFormat frames loads."""

from __future__ import annotations

import json
import math
import re
import time
from pathlib import Path

import pytest

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.cli import main
from geomcheck.errors import InputError, LimitExceeded
from geomcheck.load import load_description, make_bundle

BOX = "0.1 0.1 0.1"
HUGE = {
    "mjcf": '<mujoco><worldbody><body name="b"><geom name="g" type="box" size="{size}"/></body></worldbody></mujoco>',
    "sdf": '<sdf version="1.7"><model name="m"><link name="l"><collision name="c"><geometry><box><size>{size}</size>'
    "</box></geometry></collision></link></model></sdf>",
    "urdf": '<robot name="r"><link name="l"><collision><geometry><box size="{size}"/></geometry></collision>'
    "</link></robot>",
}


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("size", ["1e308 1 1", "1e300 1 1", "inf 1 1"])
def test_mjcf_sizes_beyond_the_limits_are_an_input_error_naming_the_geom(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], size: str
) -> None:
    root = write(tmp_path / "robot.xml", HUGE["mjcf"].format(size=size))
    shown = re.escape(size.split()[0].replace("1e3", "1e+3"))
    with pytest.raises(InputError, match=rf"robot\.xml:1: <geom name='g'> size {shown} is beyond the limit of 100000"):
        load_description(make_bundle(root, display_root=tmp_path))
    # was: "internal error: ValueError: Out of range float values are not JSON compliant: inf"
    assert main(["check", str(root), "--no-untrusted", "--no-cache", "--format", "json"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("geomcheck: error: ") and "internal error" not in err and "max_length_m" in err


@pytest.mark.parametrize(
    ("body", "fragment"),
    [
        ('<body name="b" pos="1e200 0 0"><geom type="sphere" size="1"/></body>', "<body name='b'> pos 1e+200"),
        ('<body name="b"><geom type="sphere" size="1" mass="1e300"/></body>', "<body name='b'> mass 1e+300"),
        ('<body name="b"><geom type="sphere" size="1e-20"/></body>', "below the smallest size of 1e-09"),
        (
            '<body name="b"><joint name="s" type="slide" range="0 1e9"/><geom size="1"/></body>',
            "<joint name='s'> range 1e+09",
        ),
    ],
)
def test_other_mjcf_numbers_beyond_the_limits_name_their_element(tmp_path: Path, body: str, fragment: str) -> None:
    root = write(tmp_path / "robot.xml", f"<mujoco><worldbody>{body}</worldbody></mujoco>")
    with pytest.raises(InputError) as info:
        load_description(make_bundle(root, display_root=tmp_path))
    assert fragment in str(info.value) and str(info.value).startswith("robot.xml")


def test_sdf_and_urdf_sizes_beyond_the_limits_are_refused_or_findings(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    sdf = write(tmp_path / "model.sdf", HUGE["sdf"].format(size="1e308 1 1"))
    with pytest.raises(InputError, match=r"model\.sdf:1: <size> '1e308 1 1' is beyond the limit of 100000"):
        load_description(make_bundle(sdf, display_root=tmp_path))
    urdf = write(tmp_path / "robot.urdf", HUGE["urdf"].format(size="1e308 1 1"))
    assert main(["check", str(urdf), "--no-untrusted", "--no-cache", "--format", "json"]) == 1
    found = [
        (d["code"], d["about"]) for d in json.loads(capsys.readouterr().out)["diagnostics"] if d["code"] == "GC126"
    ]
    assert found == [("GC126", "collision[0].box.size")]


def frame_chain(frames: int) -> str:
    """A model whose link ``tip`` hangs at the end of ``frames`` frames, each 1 mm along and
    1 mrad about z from the one before."""
    chain = "".join(
        f'<frame name="f{i}" attached_to="{"base" if i == 0 else f"f{i - 1}"}">'
        f'<pose relative_to="{"base" if i == 0 else f"f{i - 1}"}">0.001 0 0 0 0 0.001</pose></frame>'
        for i in range(frames)
    )
    return (
        f'<sdf version="1.7"><model name="chain"><link name="base"/>{chain}'
        f'<link name="tip"><pose relative_to="f{frames - 1}"/></link>'
        f'<joint name="j" type="fixed"><parent>f{frames - 1}</parent><child>tip</child></joint></model></sdf>'
    )


def test_a_legal_chain_of_900_frames_loads(tmp_path: Path) -> None:
    # was: "the check recursed too deeply (an endlessly recursive macro?)"
    root = write(tmp_path / "chain.sdf", frame_chain(900))
    started = time.monotonic()
    robot = load_description(make_bundle(root, display_root=tmp_path)).robot
    assert time.monotonic() - started < 10
    (joint,) = robot.joints
    assert (joint.parent, joint.child) == ("base", "tip")  # the chain is attached to the base
    x = sum(0.001 * math.cos(0.001 * k) for k in range(900))
    y = sum(0.001 * math.sin(0.001 * k) for k in range(900))
    assert joint.origin.xyz == pytest.approx((x, y, 0.0), abs=1e-12)
    assert joint.origin.rpy[2] == pytest.approx(0.9, abs=1e-12)


def test_a_fan_out_of_sdformat_includes_is_refused_before_it_is_built(tmp_path: Path) -> None:
    # each level includes the next ten times: 111,111 models and links from 3 KB of files
    for level in range(5):
        includes = "".join(
            f"<include><uri>../m{level + 1}/model.sdf</uri><name>c{i}</name></include>" for i in range(10)
        )
        write(
            tmp_path / f"m{level}" / "model.sdf",
            f'<sdf version="1.7"><model name="m{level}"><link name="l"/>{includes}</model></sdf>',
        )
    write(tmp_path / "m5" / "model.sdf", '<sdf version="1.7"><model name="leaf"><link name="l"/></model></sdf>')
    started = time.monotonic()
    with pytest.raises(LimitExceeded, match=r"<include> of \.\./m\d/model\.sdf makes the model \d+ links, joints"):
        load_description(make_bundle(tmp_path / "m0" / "model.sdf", display_root=tmp_path))
    assert time.monotonic() - started < 10  # was: 234 s, then the memory limit
    small = load_description(make_bundle(tmp_path / "m3" / "model.sdf", display_root=tmp_path)).robot
    assert len(small.links) == 1 + 10 + 100  # m3, its ten m4s and their hundred leaves
