"""A small URDF document the URDF parser tests vary, and where its text stands."""

from __future__ import annotations

URDF = """<?xml version="1.0"?>
<robot name="demo" xmlns:drake="http://drake.mit.edu">
  <material name="blue"><color rgba="0 0 0.8 1"/></material>
  <link name="base">
    <inertial>
      <origin xyz="0.1 0 0.2" rpy="0 0 1.5707963"/>
      <mass value="2.5"/>
      <inertia ixx="0.1" ixy="0.01" ixz="0" iyy="0.2" iyz="0" izz="0.3"/>
    </inertial>
    <visual name="shell">
      <origin xyz="0 0 0.05"/>
      <geometry><mesh filename="package://demo/meshes/base.stl" scale="0.001 0.001 0.001"/></geometry>
      <material name="blue"/>
    </visual>
    <visual><geometry><sphere radius="0.02"/></geometry><material name="red"><color rgba="1 0 0 1"/></material></visual>
    <collision><geometry><box size="0.6 0.6 0.2"/></geometry><drake:proximity_properties/></collision>
    <collision><geometry><cylinder radius="0.1" length="0.3"/></geometry></collision>
  </link>
  <link name="wheel"/>
  <joint name="wheel_joint" type="continuous">
    <origin xyz="0 0.3 0" rpy="1.5707963 0 0"/>
    <parent link="base"/>
    <child link="wheel"/>
    <axis xyz="0 0 1"/>
    <limit effort="10" velocity="5"/>
    <dynamics damping="0.1" friction="0.01"/>
    <safety_controller k_velocity="10"/>
  </joint>
  <gazebo reference="wheel"><mu1>1.0</mu1><material>Gazebo/Black</material></gazebo>
  <transmission name="t"><joint name="wheel_joint"/></transmission>
  <sensor name="laser" type="ray"><parent link="base"/></sensor>
</robot>
"""


def line_of(text: str, needle: str) -> int:
    return text.count("\n", 0, text.index(needle)) + 1
