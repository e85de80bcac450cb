"""Robots made for the fix tests, outside the corpus: URDF packages with STL meshes whose
collision geometry and inertias are off the way hand-written descriptions are (boxes too small
or shifted, spheres too big, tensors copied between parts), so that ``fix --unsafe-fixes`` has
work to do next to parts it must not disturb.

* :func:`quadruped`: a trunk, four legs of hip, thigh and calf, and a spherical foot fixed at
  each calf's end; proportions and defects from its parameters;
* :func:`arm_with_gripper`: a six-joint arm, a wrist, a palm and two parallel fingers on
  prismatic joints close to the palm and the wrist;
* :func:`variation`: a corpus robot's expanded URDF with every collision primitive resized and
  moved and every inertia scaled by seeded random factors.
"""

from __future__ import annotations

import math
import random
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import trimesh
from lxml import etree

Vector = tuple[float, float, float]


def _f(values: Vector | tuple[float, ...]) -> str:
    return " ".join(f"{v:.6g}" for v in values)


def _stl(mesh: trimesh.Trimesh, path: Path) -> str:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(mesh.export(file_type="stl"))
    return f"package://made/meshes/{path.name}"


def _box_inertia(mass: float, size: Vector) -> tuple[float, float, float]:
    x, y, z = size
    return mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12


def _inertial(mass: float, com: Vector, moments: tuple[float, float, float]) -> str:
    ixx, iyy, izz = moments
    return (
        f'<inertial><origin xyz="{_f(com)}"/><mass value="{mass:.6g}"/>'
        f'<inertia ixx="{ixx:.6g}" ixy="0" ixz="0" iyy="{iyy:.6g}" iyz="0" izz="{izz:.6g}"/></inertial>'
    )


def _link(name: str, mesh: str, collision: str, inertial: str, visual_xyz: Vector = (0, 0, 0)) -> str:
    return (
        f'<link name="{name}">{inertial}'
        f'<visual><origin xyz="{_f(visual_xyz)}"/><geometry><mesh filename="{mesh}"/></geometry></visual>'
        f"<collision>{collision}</collision></link>"
    )


def _joint(name: str, kind: str, parent: str, child: str, xyz: Vector, axis: Vector = (0, 1, 0)) -> str:
    limits = '<limit lower="-1.5" upper="1.5" effort="30" velocity="10"/>' if kind == "revolute" else ""
    if kind == "prismatic":
        limits = '<limit lower="0" upper="0.03" effort="20" velocity="0.1"/>'
    return (
        f'<joint name="{name}" type="{kind}"><origin xyz="{_f(xyz)}"/><parent link="{parent}"/>'
        f'<child link="{child}"/><axis xyz="{_f(axis)}"/>{limits}</joint>'
    )


def _write(folder: Path, name: str, links: list[str], joints: list[str]) -> Path:
    (folder / "package.xml").write_text("<package><name>made</name></package>\n")
    root = folder / "urdf" / f"{name}.urdf"
    root.parent.mkdir(parents=True, exist_ok=True)
    body = "\n  ".join([*links, *joints])
    root.write_text(f'<?xml version="1.0"?>\n<robot name="{name}">\n  {body}\n</robot>\n')
    return root


@dataclass(frozen=True)
class Legs:
    """A quadruped's proportions [m] and defects (factors on the right size or offset)."""

    trunk: Vector = (0.6, 0.3, 0.15)
    hip_radius: float = 0.05
    thigh: float = 0.25
    calf: float = 0.25
    foot_radius: float = 0.03
    trunk_box_scale: float = 0.8  # the trunk's collision box against its mesh
    trunk_box_shift: float = 0.04  # and how far it is moved forward [m]
    foot_sphere_scale: float = 1.6  # the feet's collision spheres against theirs
    calf_radius_scale: float = 0.5  # the calves' collision cylinders
    foot_inertia_scale: float = 40.0  # the feet's tensors against a solid sphere's


def quadruped(folder: Path, name: str, legs: Legs = Legs()) -> Path:
    """A quadruped package under ``folder``; its root URDF."""
    meshes = folder / "meshes"
    tx, ty, tz = legs.trunk
    trunk = _stl(trimesh.creation.box(extents=legs.trunk), meshes / "trunk.stl")
    hip_mesh = trimesh.creation.cylinder(radius=legs.hip_radius, height=0.08, sections=24)
    hip_mesh.apply_transform(trimesh.transformations.rotation_matrix(math.pi / 2, (0, 1, 0)))
    hip = _stl(hip_mesh, meshes / "hip.stl")
    thigh_mesh = trimesh.creation.box(extents=(0.05, 0.05, legs.thigh))
    thigh_mesh.apply_translation((0, 0, -legs.thigh / 2))
    thigh = _stl(thigh_mesh, meshes / "thigh.stl")
    calf_mesh = trimesh.creation.capsule(radius=0.02, height=legs.calf - 0.04, count=(16, 16))
    calf_mesh.apply_translation((0, 0, -legs.calf / 2))
    calf = _stl(calf_mesh, meshes / "calf.stl")
    foot = _stl(trimesh.creation.icosphere(subdivisions=2, radius=legs.foot_radius), meshes / "foot.stl")

    box = (tx * legs.trunk_box_scale, ty * legs.trunk_box_scale, tz * legs.trunk_box_scale)
    trunk_collision = f'<origin xyz="{legs.trunk_box_shift:.6g} 0 0"/><geometry><box size="{_f(box)}"/></geometry>'
    links = [_link("trunk", trunk, trunk_collision, _inertial(8.0, (0, 0, 0), _box_inertia(8.0, legs.trunk)))]
    joints = []
    foot_moments = 0.4 * 0.1 * legs.foot_radius**2 * legs.foot_inertia_scale
    for leg, (sx, sy) in {"fl": (1, 1), "fr": (1, -1), "rl": (-1, 1), "rr": (-1, -1)}.items():
        hip_collision = (
            f'<origin rpy="0 1.5708 0"/><geometry><cylinder radius="{legs.hip_radius:.6g}" length="0.08"/></geometry>'
        )
        links.append(_link(f"{leg}_hip", hip, hip_collision, _inertial(0.6, (0, 0, 0), (4e-4, 6e-4, 6e-4))))
        joints.append(
            _joint(f"{leg}_hip_joint", "revolute", "trunk", f"{leg}_hip", (sx * tx / 2, sy * ty / 2, 0), (1, 0, 0))
        )
        thigh_collision = (
            f'<origin xyz="0 0 {-legs.thigh / 2:.6g}"/><geometry><box size="0.05 0.05 {legs.thigh:.6g}"/></geometry>'
        )
        thigh_moments = _box_inertia(1.0, (0.05, 0.05, legs.thigh))
        links.append(
            _link(f"{leg}_thigh", thigh, thigh_collision, _inertial(1.0, (0, 0, -legs.thigh / 2), thigh_moments))
        )
        joints.append(_joint(f"{leg}_thigh_joint", "revolute", f"{leg}_hip", f"{leg}_thigh", (0, sy * 0.09, 0)))
        radius = 0.02 * legs.calf_radius_scale
        calf_collision = (
            f'<origin xyz="0 0 {-legs.calf / 2:.6g}"/>'
            f'<geometry><cylinder radius="{radius:.6g}" length="{legs.calf:.6g}"/></geometry>'
        )
        calf_moments = _box_inertia(0.3, (0.04, 0.04, legs.calf))
        links.append(_link(f"{leg}_calf", calf, calf_collision, _inertial(0.3, (0, 0, -legs.calf / 2), calf_moments)))
        joints.append(_joint(f"{leg}_calf_joint", "revolute", f"{leg}_thigh", f"{leg}_calf", (0, 0, -legs.thigh)))
        sphere = legs.foot_radius * legs.foot_sphere_scale
        foot_collision = f'<geometry><sphere radius="{sphere:.6g}"/></geometry>'
        foot_inertial = _inertial(0.1, (0, 0, 0), (foot_moments, foot_moments, foot_moments))
        links.append(_link(f"{leg}_foot", foot, foot_collision, foot_inertial))
        joints.append(_joint(f"{leg}_foot_fixed", "fixed", f"{leg}_calf", f"{leg}_foot", (0, 0, -legs.calf)))
    return _write(folder, name, links, joints)


def arm_with_gripper(folder: Path, name: str = "gripper_arm", finger_box_scale: float = 0.4) -> Path:
    """A six-joint arm ending in a wrist, a palm and two parallel fingers: the fingers' collision
    boxes are ``finger_box_scale`` of their meshes, close to the palm and to each other."""
    meshes = folder / "meshes"
    links, joints = [], []
    parent, height = "base", 0.1
    base_mesh = trimesh.creation.cylinder(radius=0.08, height=0.1, sections=32)
    base_mesh.apply_translation((0, 0, 0.05))
    base = _stl(base_mesh, meshes / "base.stl")
    base_collision = '<origin xyz="0 0 0.05"/><geometry><cylinder radius="0.08" length="0.1"/></geometry>'
    links.append(_link("base", base, base_collision, _inertial(3.0, (0, 0, 0.05), (0.006, 0.006, 0.0096))))
    lengths = (0.12, 0.3, 0.25, 0.1, 0.1, 0.06)
    axes: tuple[Vector, ...] = ((0, 0, 1), (0, 1, 0), (0, 1, 0), (0, 0, 1), (0, 1, 0), (0, 0, 1))
    for index, (length, axis) in enumerate(zip(lengths, axes, strict=True), start=1):
        radius = 0.05 - 0.005 * index
        mesh = trimesh.creation.cylinder(radius=radius, height=length, sections=24)
        mesh.apply_translation((0, 0, length / 2))
        path = _stl(mesh, meshes / f"link{index}.stl")
        # the upper links' boxes are shifted a little off their meshes: fixes to refit
        shift = 0.012 if index in (2, 3) else 0.0
        collision = (
            f'<origin xyz="{shift:.6g} 0 {length / 2:.6g}"/>'
            f'<geometry><cylinder radius="{radius:.6g}" length="{length:.6g}"/></geometry>'
        )
        mass = 2.0 - 0.25 * index
        moments = _box_inertia(mass, (2 * radius, 2 * radius, length))
        links.append(_link(f"link{index}", path, collision, _inertial(mass, (0, 0, length / 2), moments)))
        joints.append(_joint(f"joint{index}", "revolute", parent, f"link{index}", (0, 0, height), axis))
        parent, height = f"link{index}", length
    palm_mesh = trimesh.creation.box(extents=(0.1, 0.06, 0.04))
    palm_mesh.apply_translation((0, 0, 0.02))
    palm = _stl(palm_mesh, meshes / "palm.stl")
    palm_collision = '<origin xyz="0 0 0.02"/><geometry><box size="0.1 0.06 0.04"/></geometry>'
    links.append(
        _link("palm", palm, palm_collision, _inertial(0.4, (0, 0, 0.02), _box_inertia(0.4, (0.1, 0.06, 0.04))))
    )
    joints.append(_joint("palm_fixed", "fixed", parent, "palm", (0, 0, height)))
    finger_mesh = trimesh.creation.box(extents=(0.02, 0.015, 0.06))
    finger_mesh.apply_translation((0, 0, 0.03))
    finger = _stl(finger_mesh, meshes / "finger.stl")
    small = (0.02 * finger_box_scale, 0.015 * finger_box_scale, 0.06 * finger_box_scale)
    for side, sign in (("left", 1), ("right", -1)):
        collision = f'<origin xyz="0 0 0.03"/><geometry><box size="{_f(small)}"/></geometry>'
        inertial = _inertial(0.05, (0, 0, 0.03), _box_inertia(0.05, (0.02, 0.015, 0.06)))
        links.append(_link(f"{side}_finger", finger, collision, inertial))
        joints.append(
            _joint(f"{side}_finger_joint", "prismatic", "palm", f"{side}_finger", (0, sign * 0.012, 0.04), (0, sign, 0))
        )
    return _write(folder, name, links, joints)


def variation(urdf: bytes, folder: Path, name: str, seed: int, packages: Mapping[str, Path] | None = None) -> Path:
    """``urdf`` (an expanded corpus robot, mesh paths absolute) with every collision primitive
    resized by 0.7-1.4, moved by up to 2 cm, and every inertia tensor scaled by 0.5-3, seeded;
    its ``package://`` meshes of ``packages`` named by their absolute paths."""
    rng = random.Random(seed)
    root = etree.fromstring(urdf)
    root.set("name", name)
    for mesh in root.iter("mesh"):
        filename = mesh.get("filename") or ""
        package, _, rest = filename.removeprefix("package://").partition("/")
        if filename.startswith("package://") and packages and package in packages:
            mesh.set("filename", str(packages[package] / rest))
    for collision in root.iter("collision"):
        origin = collision.find("origin")
        if origin is None:
            origin = etree.SubElement(collision, "origin")
        xyz = [float(v) for v in (origin.get("xyz") or "0 0 0").split()]
        origin.set("xyz", _f(tuple(v + rng.uniform(-0.02, 0.02) for v in xyz)))
        for shape in collision.iter("box", "cylinder", "sphere"):
            factor = rng.uniform(0.7, 1.4)
            for attribute in ("size", "radius", "length"):
                if shape.get(attribute):
                    shape.set(attribute, _f(tuple(float(v) * factor for v in shape.get(attribute, "").split())))
    for inertia in root.iter("inertia"):
        factor = rng.uniform(0.5, 3.0)
        for attribute in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"):
            if inertia.get(attribute):
                inertia.set(attribute, f"{float(inertia.get(attribute, '0')) * factor:.6g}")
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text("<package><name>made</name></package>\n")
    path = folder / f"{name}.urdf"
    path.write_bytes(etree.tostring(root, xml_declaration=True, encoding="utf-8"))
    return path
