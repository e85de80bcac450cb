"""Small robot packages built in memory, for tests that need a description with meshes but
not the size of the bundled example."""

from __future__ import annotations

from pathlib import Path

MESH_PACKAGE_ROOT = "urdf/boxed.urdf"


def box_stl(size: tuple[float, float, float]) -> bytes:
    """A binary STL of a box of ``size`` [m] centred on the origin (trimesh's 12 triangles)."""
    import trimesh

    return bytes(trimesh.creation.box(extents=size).export(file_type="stl"))


def mesh_package() -> dict[str, bytes]:
    """A small package with meshes: a URDF whose two links have STL visuals and collision
    boxes that miss them (a GC301 and a GC303 finding, each with a fix), and a wheel on a
    continuous joint (swept against the base)."""
    urdf = b"""<?xml version="1.0"?>
<robot name="boxed">
  <link name="base_link">
    <inertial><mass value="2.0"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
    <visual><geometry><mesh filename="../meshes/base.stl"/></geometry></visual>
    <collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.0002"/></inertial>
    <visual><geometry><mesh filename="../meshes/arm.stl"/></geometry></visual>
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.05 0.05 0.2"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="arm"/><origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="wheel">
    <inertial><mass value="0.3"/><inertia ixx="0.0003" ixy="0" ixz="0" iyy="0.00054" iyz="0" izz="0.0003"/></inertial>
    <collision><origin rpy="1.5708 0 0"/><geometry><cylinder radius="0.06" length="0.03"/></geometry></collision>
  </link>
  <joint name="wheel_joint" type="continuous">
    <parent link="base_link"/><child link="wheel"/><origin xyz="0.1 0.2 -0.1"/><axis xyz="0 1 0"/>
  </joint>
</robot>
"""
    return {
        MESH_PACKAGE_ROOT: urdf,
        "meshes/base.stl": box_stl((0.3, 0.3, 0.2)),
        "meshes/arm.stl": box_stl((0.05, 0.05, 0.2)),
    }


def write_package(folder: Path, files: dict[str, bytes]) -> Path:
    """``files`` (relative name: bytes) written under ``folder``; ``folder``."""
    for name, data in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_bytes(data)
    return folder
