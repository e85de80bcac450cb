"""Helpers of the SDFormat loader tests: write and load a model, rotations, link poses."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import geomcheck.load.loader  # noqa: F401  (the loaders declare their formats)
from geomcheck.kinematics import Kinematics
from geomcheck.load import LoadedDescription, load_description, make_bundle
from geomcheck.model import Robot

TOL = 1e-9


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def load(tmp_path: Path, text: str, name: str = "model.sdf", **bundle: object) -> LoadedDescription:
    root = write(tmp_path / name, text)
    return load_description(make_bundle(root, display_root=tmp_path, **bundle))  # type: ignore[arg-type]


def rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rx(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def world(robot: Robot, q: dict[str, float] | None = None) -> dict[str, np.ndarray]:
    """World-from-link transforms of every link at the configuration ``q`` (zero elsewhere)."""
    kin = Kinematics(robot)
    config = np.zeros((1, len(kin.joints)))
    for name, value in (q or {}).items():
        config[0, kin.index(name)] = value
    frames = kin.link_transforms(config)[0]
    return dict(zip(kin.link_names, frames, strict=True))


def assert_pose(transform: np.ndarray, translation: tuple[float, ...], rotation: np.ndarray, tol: float = TOL) -> None:
    np.testing.assert_allclose(transform[:3, 3], translation, atol=tol)
    np.testing.assert_allclose(transform[:3, :3], rotation, atol=tol)


ARM = """<?xml version="1.0"?>
<sdf version="1.9">
  <model name="arm" canonical_link="base">
    <pose>1 2 3 0 0 0.5</pose>
    <frame name="mount" attached_to="base">
      <pose degrees="true">0 0 0.1 0 0 90</pose>
    </frame>
    <link name="base">
      <inertial>
        <mass>2</mass>
        <pose>0 0 0.05 0 0 0</pose>
        <inertia><ixx>0.1</ixx><iyy>0.2</iyy><izz>0.3</izz><ixy>0.01</ixy></inertia>
      </inertial>
      <collision name="base_box"><geometry><box><size>0.2 0.2 0.1</size></box></geometry></collision>
    </link>
    <link name="upper">
      <pose relative_to="mount">0 0 0.2 0 0 0</pose>
      <collision name="upper_cyl">
        <pose relative_to="__model__">0 0 0.5 0 0 0</pose>
        <geometry><cylinder><radius>0.03</radius><length>0.4</length></cylinder></geometry>
      </collision>
      <visual name="upper_capsule">
        <pose degrees="true">0 0 0 90 0 0</pose>
        <geometry><capsule><radius>0.02</radius><length>0.3</length></capsule></geometry>
      </visual>
      <visual name="ground"><geometry><plane><normal>0 0 1</normal></plane></geometry></visual>
    </link>
    <joint name="shoulder" type="revolute">
      <pose>0 0 -0.1 0 0 0</pose>
      <parent>base</parent>
      <child>upper</child>
      <axis>
        <xyz expressed_in="__model__">0 2 0</xyz>
        <limit><lower>-1</lower><upper>1</upper><effort>5</effort><velocity>-1</velocity></limit>
      </axis>
    </joint>
    <model name="hand">
      <pose relative_to="upper">0 0 0.4 0 0 0</pose>
      <link name="palm">
        <collision name="palm_ball"><geometry><sphere><radius>0.05</radius></sphere></geometry></collision>
      </link>
      <link name="finger">
        <pose>0.05 0 0 0 0 0</pose>
        <collision name="tip"><geometry><ellipsoid><radii>0.01 0.01 0.03</radii></ellipsoid></geometry></collision>
      </link>
      <joint name="slide" type="prismatic">
        <parent>palm</parent>
        <child>finger</child>
        <axis><xyz>1 0 0</xyz></axis>
      </joint>
    </model>
    <joint name="wrist" type="fixed">
      <parent>upper</parent>
      <child>hand::palm</child>
    </joint>
  </model>
</sdf>
"""
