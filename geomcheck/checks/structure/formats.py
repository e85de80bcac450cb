"""What each description format defines, as the structure family judges a robot by it."""

from __future__ import annotations

from geomcheck.model import JOINT_TYPES, SDF_JOINT_TYPES

# the joint types each format defines (an MJCF joint is mapped onto URDF's types, a ball kept)
FORMAT_JOINT_TYPES = {"urdf": JOINT_TYPES, "sdf": SDF_JOINT_TYPES, "mjcf": (*JOINT_TYPES, "ball")}
# the format's own parser, named by a finding on a file it loads as written (``accepted_by``)
REFERENCE_PARSER = {"urdf": "urdfdom", "sdf": "libsdformat", "mjcf": "MuJoCo"}
