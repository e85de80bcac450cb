"""Poses of URDF elements: ``<origin xyz rpy>``, and URDF 1.1's ``<origin quat_xyzw>`` read
as urdfdom reads it."""

from __future__ import annotations

import math
from collections.abc import Sequence

from lxml import etree

from geomcheck.diagnostics import Severity
from geomcheck.load.locations import LocationResolver
from geomcheck.load.urdf_findings import Subject, shorten
from geomcheck.load.urdf_numbers import UrdfNumbers
from geomcheck.load.urdf_spec import FIRST_CAPSULE_VERSION
from geomcheck.model import Pose, Vec3
from geomcheck.rules.structure import INVALID_NUMBER, UNKNOWN_ATTRIBUTE


def quaternion_rpy(quat: Sequence[float]) -> Vec3:
    """URDF ``rpy`` [rad] of the rotation ``quat_xyzw`` (x, y, z, w), normalised as urdfdom
    normalises it (identity for a zero quaternion)."""
    import numpy as np

    from geomcheck.model import rpy_from_matrix

    x, y, z, w = quat
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if norm == 0.0:
        return (0.0, 0.0, 0.0)
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
    return rpy_from_matrix(rotation)


class UrdfPoses(UrdfNumbers):
    """Reader of ``<origin>``, which depends on the document's URDF version."""

    def __init__(self, root: etree._Element, resolver: LocationResolver) -> None:
        super().__init__(root, resolver)
        self.version: tuple[int, int] = (1, 0)

    def origin(self, parent: etree._Element, subject: Subject, about: str) -> Pose:
        element = self.child(parent, "origin")
        if element is None:
            return Pose()
        about = f"{about}.origin" if about else "origin"
        self.check_element(element, "origin", subject, about)
        xyz = self.vec3(element, "xyz", subject, about, (0.0, 0.0, 0.0))
        if element.get("quat_xyzw") is not None and self.version < FIRST_CAPSULE_VERSION:
            version = ".".join(str(v) for v in self.version)
            self.report(
                UNKNOWN_ATTRIBUTE,
                f'<origin quat_xyzw> is URDF 1.1, this file is URDF {version} (write <robot version="1.1">): '
                "urdfdom ignores the rotation it writes",
                element,
                subject,
                f"{about}@quat_xyzw",
                severity=Severity.WARNING,
                element="origin",
                attributes=["quat_xyzw"],
                suggestions={},
            )
        if element.get("quat_xyzw") is None or self.version < FIRST_CAPSULE_VERSION:
            return Pose(xyz, self.vec3(element, "rpy", subject, about, (0.0, 0.0, 0.0)))
        if element.get("rpy") is not None:
            self.report(
                INVALID_NUMBER,
                "<origin> writes both rpy and quat_xyzw: urdfdom refuses an origin with two rotations",
                element,
                subject,
                f"{about}.quat_xyzw",
                element="origin",
                attribute="quat_xyzw",
                value=shorten(element.get("quat_xyzw") or ""),
                expected=4,
            )
            return Pose(xyz)
        quat = self.numbers(element, "quat_xyzw", 4, subject, about, (0.0, 0.0, 0.0, 1.0))
        assert quat is not None
        return Pose(xyz, quaternion_rpy(quat))


__all__ = ["UrdfPoses", "quaternion_rpy"]
