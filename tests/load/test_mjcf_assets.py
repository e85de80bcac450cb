"""What MuJoCo reads of an MJCF model is read by geomcheck, confined, and handed to MuJoCo in
memory: MuJoCo opens no file itself (geomcheck.load.mjcf_assets)."""

from __future__ import annotations

import os
import re
import struct
import time
import zlib
from pathlib import Path

import numpy as np
import pytest

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.errors import InputError, LimitExceeded, SandboxViolation
from geomcheck.load import load_description, make_bundle
from geomcheck.load.mjcf import compile_model
from geomcheck.load.mjcf_assets import VFS_ROOT, stage_model, start_tags
from geomcheck.thresholds import LoadLimits

mujoco = pytest.importorskip("mujoco")

TETRAHEDRON = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TETRAHEDRON_FACES = ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3))


def stl(scale: float = 1.0, offset: float = 0.0) -> bytes:
    """A binary STL of a tetrahedron ``scale`` across, moved by ``offset`` along x."""
    vertices = TETRAHEDRON * scale + (offset, 0.0, 0.0)
    out = bytearray(b"\0" * 80 + struct.pack("<I", len(TETRAHEDRON_FACES)))
    for face in TETRAHEDRON_FACES:
        out += struct.pack("<3f", 0, 0, 0) + vertices[list(face)].astype("<f4").tobytes() + b"\0\0"
    return bytes(out)


def png(width: int, height: int, seed: int = 0) -> bytes:
    """An 8-bit RGB PNG of ``width`` x ``height`` pixels (noise from ``seed``)."""
    pixels = np.random.default_rng(seed).integers(0, 256, (height, width, 3), dtype=np.uint8)
    raw = b"".join(b"\0" + row.tobytes() for row in pixels)

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def put(path: Path, data: bytes | str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    path.write_bytes(data)
    return path


ROOT = """<mujoco model="everything">
  <compiler assetdir="assets" meshdir="meshes" angle="radian"/>
  <include file="parts/defaults.xml"/>
  <asset>
    <mesh file="base.stl"/>
    <mesh name="arm" file="arm/arm.stl" scale="0.5 0.5 0.5"/>
    <texture name="grid" type="2d" file="grid.png"/>
    <texture name="sky" type="skybox" fileright="r.png" fileleft="l.png" fileup="u.png"
             filedown="d.png" filefront="f.png" fileback="b.png"/>
    <material name="grid" texture="grid"/>
    <hfield name="floor" file="floor.png" size="1 1 0.1 0.1"/>
    <model name="hand" file="hand/hand.xml"/>
  </asset>
  <worldbody>
    <geom type="hfield" hfield="floor"/>
    <body name="base" pos="0 0 1">
      <freejoint/>
      <geom type="mesh" mesh="base" material="grid"/>
      <include file="parts/arm.xml"/>
      <attach model="hand" body="palm" prefix="h_"/>
    </body>
    <flexcomp name="cloth" type="mesh" file="cloth.stl" dim="2" pos="0 0 3" radius="0.01"/>
  </worldbody>
</mujoco>
"""
DEFAULTS = '<mujoco>\n  <default><geom rgba="1 0 0 1"/></default>\n  <include file="parts/more.xml"/>\n</mujoco>\n'
MORE = '<mujoco><asset><mesh name="extra" file="extra.stl"/></asset></mujoco>\n'
ARM = """<mujoco>
  <body name="arm" pos="0 0 0.2">
    <joint name="shoulder" axis="0 1 0"/>
    <geom type="mesh" mesh="arm"/>
    <geom type="mesh" mesh="extra" pos="0 0 0.3"/>
  </body>
</mujoco>
"""
HAND = """<mujoco model="hand">
  <compiler meshdir="hand_meshes"/>
  <include file="fingers.xml"/>
  <asset><mesh name="palm" file="palm.stl"/></asset>
  <worldbody>
    <body name="palm"><geom type="mesh" mesh="palm"/><body name="finger"><joint axis="1 0 0"/>
      <geom type="mesh" mesh="finger"/></body></body>
  </worldbody>
</mujoco>
"""
FINGERS = '<mujoco><asset><mesh name="finger" file="finger.stl"/></asset></mujoco>\n'


def everything(folder: Path) -> Path:
    """A model naming a file in every place MuJoCo reads one (each mesh a different size)."""
    put(folder / "parts" / "defaults.xml", DEFAULTS)
    put(folder / "parts" / "more.xml", MORE)
    put(folder / "parts" / "arm.xml", ARM)
    put(folder / "meshes" / "base.stl", stl(1.0))
    put(folder / "meshes" / "arm" / "arm.stl", stl(2.0))
    put(folder / "meshes" / "extra.stl", stl(3.0))
    put(folder / "meshes" / "cloth.stl", stl(0.5))
    put(folder / "assets" / "grid.png", png(8, 8, 1))
    for face, seed in zip("rludfb", range(6), strict=True):
        put(folder / "assets" / f"{face}.png", png(4, 4, 10 + seed))
    put(folder / "meshes" / "floor.png", png(5, 7, 2))
    put(folder / "hand" / "hand.xml", HAND)
    put(folder / "hand" / "fingers.xml", FINGERS)
    put(folder / "hand" / "hand_meshes" / "palm.stl", stl(4.0))
    put(folder / "hand" / "hand_meshes" / "finger.stl", stl(5.0))
    return put(folder / "robot.xml", ROOT)


def staged_model(root: Path, confined: bool = False, limits: LoadLimits | None = None) -> tuple[object, object]:
    bundle = make_bundle(root, display_root=root.parent, confined=confined)
    staged = stage_model(bundle, limits or LoadLimits(), root.read_bytes())
    return staged, compile_model(bundle, staged, "robot.xml")  # MuJoCo's warnings kept from MUJOCO_LOG.TXT


def test_the_staged_model_is_the_model_mujoco_reads_from_the_disk(tmp_path: Path) -> None:
    root = everything(tmp_path / "robot")
    staged, model = staged_model(root)
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(lambda text: None)  # the cloth's warning, kept from MUJOCO_LOG.TXT
    try:
        disk = mujoco.MjModel.from_xml_path(str(root))
    finally:
        mujoco.set_mju_user_warning(previous)
    assert (model.nmesh, model.ntex, model.nhfield, model.nflex, model.nbody) == (5, 2, 1, 1, 9)
    for name in ("mesh_vert", "mesh_vertnum", "mesh_scale", "tex_data", "tex_height", "hfield_data", "flex_vert"):
        assert np.array_equal(getattr(model, name), getattr(disk, name)), name
    for name in ("body_pos", "body_mass", "geom_size", "geom_rbound", "jnt_axis"):
        assert np.array_equal(getattr(model, name), getattr(disk, name)), name
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_MESH, m) for m in range(model.nmesh)]
    assert names == [mujoco.mj_id2name(disk, mujoco.mjtObj.mjOBJ_MESH, m) for m in range(disk.nmesh)]
    assert "base" in names and "h_palm" in names  # unnamed meshes are named after their files
    # every file MuJoCo read came from the VFS, named in it after the file it holds
    assert all(name.startswith(VFS_ROOT) for name in staged.files)
    shown = sorted(staged.displays[n] for n in staged.files if n.endswith(".stl"))
    assert shown == [
        "hand/hand_meshes/finger.stl",
        "hand/hand_meshes/palm.stl",
        "meshes/arm/arm.stl",
        "meshes/base.stl",
        "meshes/cloth.stl",
        "meshes/extra.stl",
    ]


def test_the_loaded_robot_names_the_mesh_files_not_the_vfs(tmp_path: Path) -> None:
    root = everything(tmp_path / "robot")
    robot = load_description(make_bundle(root, display_root=root.parent, confined=True)).robot
    files = sorted(
        {s.geometry.filename for link in robot.links for s in link.collisions if hasattr(s.geometry, "filename")}
    )
    assert files == [
        "hand/hand_meshes/finger.stl",
        "hand/hand_meshes/palm.stl",
        "meshes/arm/arm.stl",
        "meshes/base.stl",
        "meshes/extra.stl",
    ]


def test_copies_keep_every_line_and_only_rewrite_file_names(tmp_path: Path) -> None:
    root = everything(tmp_path / "robot")
    staged, _ = staged_model(root)
    copy = staged.files[staged.root].decode()
    assert copy.count("\n") == ROOT.count("\n")
    assert 'assetdir="" meshdir=""' in copy and 'angle="radian"' in copy
    assert 'file="base.stl"' not in copy and f'file="{VFS_ROOT}' in copy
    lines = copy.splitlines()
    for number, line in enumerate(ROOT.splitlines()):
        if "file" not in line and "compiler" not in line:
            assert lines[number] == line


def test_start_tags_skip_comments_cdata_and_instructions() -> None:
    data = b'<?xml version="1.0"?>\n<!-- <geom file="x"/> -->\n<a b=">"><![CDATA[<c>]]><d/></a>'
    assert [data[s:e] for s, e in start_tags(data)] == [b'<a b=">">', b"<d/>"]


OUTSIDE_PLACES = {
    # (where the outside file is named, the files written inside the bundle)
    "mesh in an attached sub-model": {
        "robot.xml": '<mujoco><asset><model name="s" file="sub.xml"/></asset><worldbody><body name="b">'
        '<attach model="s" body="p" prefix="s_"/></body></worldbody></mujoco>',
        "sub.xml": '<mujoco><asset><mesh name="m" file="../outside.stl"/></asset><worldbody><body name="p">'
        '<geom type="mesh" mesh="m"/></body></worldbody></mujoco>',
    },
    "flexcomp through meshdir": {
        "robot.xml": '<mujoco><compiler meshdir=".."/><worldbody><flexcomp name="f" type="mesh" '
        'file="outside.stl" dim="2"/></worldbody></mujoco>',
    },
    "sub-model file": {
        "robot.xml": '<mujoco><asset><model name="s" file="../outside.xml"/></asset></mujoco>',
    },
    "include": {"robot.xml": '<mujoco><include file="../outside.xml"/></mujoco>'},
    "texture cube face": {
        "robot.xml": '<mujoco><asset><texture type="skybox" fileright="/etc/hostname"/></asset></mujoco>',
    },
    "height field through assetdir": {
        "robot.xml": '<mujoco><compiler assetdir="/etc"/><asset><hfield name="h" file="hostname" '
        'size="1 1 1 1"/></asset></mujoco>',
    },
    "skin": {"robot.xml": '<mujoco><asset><skin file="/etc/passwd"/></asset></mujoco>'},
    "a link inside pointing out": {
        "robot.xml": '<mujoco><asset><mesh name="m" file="link.stl"/></asset><worldbody><body>'
        '<geom type="mesh" mesh="m"/></body></worldbody></mujoco>',
    },
}


@pytest.mark.parametrize("place", sorted(OUTSIDE_PLACES))
def test_a_file_outside_the_bundle_is_refused_wherever_it_is_named(tmp_path: Path, place: str) -> None:
    put(tmp_path / "outside.stl", stl())
    put(tmp_path / "outside.xml", "<mujoco/>")
    for name, text in OUTSIDE_PLACES[place].items():
        put(tmp_path / "robot" / name, text)
    (tmp_path / "robot" / "link.stl").symlink_to(tmp_path / "outside.stl")
    root = tmp_path / "robot" / "robot.xml"
    with pytest.raises(SandboxViolation, match="access outside the uploaded bundle refused"):
        load_description(make_bundle(root, display_root=root.parent, confined=True))


def test_a_fifo_is_never_opened(tmp_path: Path) -> None:
    folder = tmp_path / "robot"
    folder.mkdir()
    os.mkfifo(folder / "m.stl")  # opening it for reading would block until a writer comes: for ever
    put(folder / "robot.xml", '<mujoco><asset><mesh name="m" file="m.stl"/></asset></mujoco>')
    started = time.monotonic()
    for confined in (True, False):
        with pytest.raises(InputError, match=r"not a regular file: m\.stl"):
            load_description(make_bundle(folder / "robot.xml", display_root=folder, confined=confined))
    assert time.monotonic() - started < 5


def test_mujocos_messages_name_the_files_not_the_vfs(tmp_path: Path) -> None:
    put(tmp_path / "meshes" / "broken.stl", b"solid nothing here\n")
    root = put(
        tmp_path / "robot.xml",
        '<mujoco><compiler meshdir="meshes"/><asset><mesh file="broken.stl"/><mesh file="gone.stl"/></asset>'
        '<worldbody><body><geom type="mesh" mesh="broken"/><geom type="mesh" mesh="gone"/></body></worldbody>'
        "</mujoco>",
    )
    with pytest.raises(InputError) as info:
        load_description(make_bundle(root, display_root=tmp_path))
    assert "meshes/broken.stl" in str(info.value) and VFS_ROOT not in str(info.value)
    put(tmp_path / "meshes" / "broken.stl", stl())
    with pytest.raises(InputError, match=r"Error opening file 'meshes/gone\.stl'") as info:
        load_description(make_bundle(root, display_root=tmp_path))
    assert VFS_ROOT not in str(info.value)


def test_a_file_attribute_mjcf_does_not_have_is_refused(tmp_path: Path) -> None:
    root = put(
        tmp_path / "robot.xml",
        '<mujoco><worldbody><body><geom file="/etc/passwd" size="1"/></body></worldbody></mujoco>',
    )
    with pytest.raises(InputError, match=r"robot\.xml:1: <geom file>: MJCF names no file there"):
        load_description(make_bundle(root, display_root=tmp_path))


def test_a_sub_model_attaching_itself_is_refused(tmp_path: Path) -> None:
    root = put(tmp_path / "robot.xml", '<mujoco><asset><model name="me" file="robot.xml"/></asset></mujoco>')
    with pytest.raises(InputError, match=r"<model> of robot\.xml attaches itself"):
        load_description(make_bundle(root, display_root=tmp_path))


def test_an_image_of_gigapixels_is_refused_before_mujoco_decodes_it(tmp_path: Path) -> None:
    header = png(1, 1)
    bomb = header[:16] + struct.pack(">II", 100_000, 100_000) + header[24:]  # declares 1e10 pixels
    put(tmp_path / "t.png", bomb)
    root = put(tmp_path / "robot.xml", '<mujoco><asset><texture name="t" type="2d" file="t.png"/></asset></mujoco>')
    with pytest.raises(LimitExceeded, match=r"robot\.xml:1: <texture> image of 100000 x 100000 pixels exceeds"):
        load_description(make_bundle(root, display_root=tmp_path))


NESTED_REPLICATE = (
    '<mujoco><worldbody><replicate count="20" offset="1 0 0"><replicate count="20" offset="0 1 0">'
    '<replicate count="20" offset="0 0 1"><replicate count="20" offset="1 1 0"><body><geom size=".1"/></body>'
    "</replicate></replicate></replicate></replicate></worldbody></mujoco>"
)


def test_nested_replicates_are_refused_before_mujoco_expands_them(tmp_path: Path) -> None:
    root = put(tmp_path / "robot.xml", NESTED_REPLICATE)
    assert len(NESTED_REPLICATE) < 400  # was: 35-50 s and 2 GiB, once a SIGSEGV
    started = time.monotonic()
    expected = r"robot\.xml:1: <replicate> expands to \d+ elements \(<replicate>s\), beyond the limit of 10000"
    with pytest.raises(LimitExceeded, match=expected + r" \(max_mjcf_elements\)"):
        load_description(make_bundle(root, display_root=tmp_path))
    assert time.monotonic() - started < 1.0
    small = NESTED_REPLICATE.replace('count="20"', 'count="3"')
    robot = load_description(make_bundle(put(tmp_path / "small.xml", small), display_root=tmp_path)).robot
    assert len([link for link in robot.links if link.name != "world"]) == 3**4


def test_attached_sub_models_count_in_the_expansion(tmp_path: Path) -> None:
    put(tmp_path / "sub.xml", "<mujoco><worldbody>" + '<body><geom size=".1"/></body>' * 60 + "</worldbody></mujoco>")
    attach = '<replicate count="100" offset="1 0 0"><attach model="s" prefix="p"/></replicate>'
    root = put(
        tmp_path / "robot.xml",
        f'<mujoco><asset><model name="s" file="sub.xml"/></asset><worldbody>{attach}</worldbody></mujoco>',
    )
    with pytest.raises(LimitExceeded, match=r"<replicate> expands to 12\d\d\d elements"):
        load_description(make_bundle(root, display_root=tmp_path))


def test_strippath_keeps_the_file_name_alone_as_mujoco_does(tmp_path: Path) -> None:
    put(tmp_path / "meshes" / "part.stl", stl(2.0))
    text = (
        '<mujoco><compiler meshdir="meshes" strippath="true"/><asset><mesh file="C:\\\\cad\\\\export/part.stl"/>'
        '</asset><worldbody><body><geom type="mesh" mesh="part"/></body></worldbody></mujoco>'
    )
    root = put(tmp_path / "robot.xml", text)
    staged, model = staged_model(root)
    disk = mujoco.MjModel.from_xml_path(str(root))
    assert model.nmesh == 1 and np.array_equal(model.mesh_vert, disk.mesh_vert)
    assert sorted(staged.displays.values()) == ["meshes/part.stl", "robot.xml"]


@pytest.mark.parametrize(
    ("asset", "fragment"),
    [
        # was: 2.3 GiB in 2 s from 200 bytes
        (
            '<texture name="t" type="2d" builtin="checker" width="20000" height="20000"/>',
            "<texture> makes 400000000 pixels",
        ),
        (
            '<texture name="t" type="skybox" builtin="flat" width="4000" height="4000"/>',
            "<texture> makes 96000000 pixels",
        ),
        ('<hfield name="h" nrow="20000" ncol="20000" size="1 1 1 1"/>', "<hfield> makes 400000000 points"),
        # was: 9 million vertices and 73 s
        ('<mesh name="m" builtin="plate" params="3000 3000"/>', "<mesh> makes 9000000 vertices"),
        ('<mesh name="m" builtin="supersphere" params="3000 1 1"/>', "<mesh> makes 9000000 vertices"),
        # was: 7.5 s, then "Caught an unknown exception!" (4 GiB of user numbers for 5000 geoms)
        ('</asset><size nuser_geom="100000"/><asset>', "<size> makes 100000 entries per object"),
    ],
)
def test_assets_mujoco_would_generate_beyond_the_limits_are_refused(tmp_path: Path, asset: str, fragment: str) -> None:
    root = put(tmp_path / "robot.xml", f"<mujoco><asset>{asset}</asset></mujoco>")
    started = time.monotonic()
    with pytest.raises(LimitExceeded, match=rf"robot\.xml:1: {re.escape(fragment)}, beyond the limit"):
        load_description(make_bundle(root, display_root=tmp_path))
    assert time.monotonic() - started < 1.0
