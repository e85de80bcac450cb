"""URDF ``<joint>``: its links, axis, limits, mimic and the optional elements urdfdom reads,
with the bounds of revolute and prismatic joints judged where consumers read them."""

from __future__ import annotations

from typing import Any

from lxml import etree

from geomcheck.diagnostics import Severity
from geomcheck.load.urdf_findings import Subject, shorten
from geomcheck.load.urdf_numbers import LIMITS
from geomcheck.load.urdf_pose import UrdfPoses
from geomcheck.load.urdf_spec import SPEC
from geomcheck.model import Joint, Limit, Mimic, Vec3
from geomcheck.rules.structure import MISSING_ATTRIBUTE, NUMBER_OUT_OF_RANGE

# Joint bounds are judged where a consumer reads them: urdfdom, MoveIt, pinocchio and Gazebo use
# <limit lower/upper> of revolute and prismatic joints only (urdfdom still parses the numbers of
# every <limit>, so an unparseable one stays GC107 on any joint type)
BOUNDED_JOINT_TYPES = ("revolute", "prismatic")


class UrdfJoints(UrdfPoses):
    """Reader of ``<joint>`` elements."""

    def joint(self, element: etree._Element) -> Joint:
        name = (element.get("name") or "").strip()
        subject = Subject(joint=name or None)
        self.name_of(element, subject, "joint")
        self.check_element(element, "joint", subject, "")
        kind = (element.get("type") or "").strip()
        if not kind:
            self.report(MISSING_ATTRIBUTE, "<joint> has no type", element, subject, "type", element="joint")
        links = {role: self.joint_link(element, role, subject) for role in ("parent", "child")}
        axis = self.axis(element, subject)
        limit = self.limit(element, kind, subject)
        mimic = self.mimic(element, subject)
        self.optional_elements(element, subject)
        return Joint(
            name,
            kind,
            links["parent"],
            links["child"],
            self.origin(element, subject, ""),
            axis,
            limit,
            mimic,
            self.location(element, name),
        )

    def joint_link(self, element: etree._Element, role: str, subject: Subject) -> str:
        """The link named by the joint's ``<parent>`` or ``<child>`` (``""`` without one)."""
        child = self.child(element, role)
        if child is None:
            return ""
        self.check_element(child, role, subject, role)
        return (child.get("link") or "").strip()

    def axis(self, element: etree._Element, subject: Subject) -> Vec3:
        """The joint's ``<axis xyz>``; URDF's default is x."""
        axis_element = self.child(element, "axis")
        if axis_element is None:
            return (1.0, 0.0, 0.0)
        self.check_element(axis_element, "axis", subject, "axis")
        return self.vec3(axis_element, "xyz", subject, "axis", (1.0, 0.0, 0.0))

    def limit(self, element: etree._Element, kind: str, subject: Subject) -> Limit | None:
        """The joint's ``<limit>``: every number parsed, the bounds judged on bounded joints only."""
        limit_element = self.child(element, "limit")
        if limit_element is None:
            return None
        self.check_element(limit_element, "limit", subject, "limit")
        values = {
            key: self.number(
                limit_element, key, subject, "limit", None, required=key in ("effort", "velocity"), magnitude=False
            )
            for key in ("lower", "upper", "effort", "velocity")
        }
        unlimited = False
        if kind in BOUNDED_JOINT_TYPES:
            for key in ("lower", "upper"):
                bound = values[key]
                if bound is not None:
                    values[key], sentinel = self.joint_bound(limit_element, key, bound, kind, subject)
                    unlimited = unlimited or sentinel
        return Limit(**values, unlimited=unlimited)

    def mimic(self, element: etree._Element, subject: Subject) -> Mimic | None:
        """The joint's ``<mimic>``, ``None`` without one or without the joint it follows."""
        mimic_element = self.child(element, "mimic")
        if mimic_element is None:
            return None
        self.check_element(mimic_element, "mimic", subject, "mimic")
        target = (mimic_element.get("joint") or "").strip()
        if not target:
            self.report(MISSING_ATTRIBUTE, "<mimic> has no joint", mimic_element, subject, "mimic.joint")
            return None
        return Mimic(
            target,
            self.number(mimic_element, "multiplier", subject, "mimic", 1.0) or 0.0,
            self.number(mimic_element, "offset", subject, "mimic", 0.0) or 0.0,
        )

    def optional_elements(self, element: etree._Element, subject: Subject) -> None:
        """``<calibration>``, ``<dynamics>`` and ``<safety_controller>``: geomcheck keeps none of
        them, but urdfdom parses their numbers and refuses some of them."""
        for optional in ("calibration", "dynamics", "safety_controller"):
            for child in self.children(element, optional):
                self.check_element(child, optional, subject, optional)
                for attribute in SPEC[optional].attributes:
                    self.number(child, attribute, subject, optional, None)
                self.required_of(child, optional, subject)

    def required_of(self, element: etree._Element, kind: str, subject: Subject) -> None:
        """GC108 where urdfdom refuses the joint: a ``<dynamics>`` with neither damping nor
        friction, a ``<safety_controller>`` without ``k_velocity``."""
        if kind == "dynamics" and element.get("damping") is None and element.get("friction") is None:
            self.report(
                MISSING_ATTRIBUTE,
                "<dynamics> has neither damping nor friction: urdfdom refuses the robot "
                "('joint dynamics element specified with no damping and no friction')",
                element,
                subject,
                "dynamics.damping",
                element="dynamics",
                attribute="damping",
            )
        if kind == "safety_controller" and element.get("k_velocity") is None:
            self.report(
                MISSING_ATTRIBUTE,
                "<safety_controller> has no k_velocity: urdfdom refuses the robot",
                element,
                subject,
                "safety_controller.k_velocity",
                element="safety_controller",
                attribute="k_velocity",
            )

    def joint_bound(
        self, element: etree._Element, key: str, value: float, kind: str, subject: Subject
    ) -> tuple[float | None, bool]:
        """A revolute or prismatic ``<limit lower|upper>`` as the model keeps it, and whether it
        was SDFormat's "no limit" sentinel. Bounds other joint types carry are read by no
        consumer and are not judged at all."""
        unit = "m" if kind == "prismatic" else "rad"
        text = shorten(element.get(key) or "")
        data: dict[str, Any] = {"element": "limit", "attribute": key, "value": value}
        outward = value < 0 if key == "lower" else value > 0
        sentinel = abs(value) >= LIMITS.unlimited_joint_bound
        if sentinel or (outward and abs(value) > LIMITS.max_length_m):
            if sentinel:
                said = 'SDFormat\'s "no limit" value, read by Gazebo as unlimited'
            else:  # 999999, 1e9: no joint travels that far, the author wrote "no limit" as a large number
                said = f'{value:g} {unit}, a large value written for "no limit" (no {kind} joint travels that far)'
            self.report(
                NUMBER_OUT_OF_RANGE,
                f'<limit {key}="{text}">: {said}; urdfdom, '
                f"MoveIt and pinocchio take it as written (geomcheck takes the {kind} joint as unbounded on that side)",
                element,
                subject,
                f"limit.{key}",
                severity=Severity.INFO,
                limit=LIMITS.unlimited_joint_bound if sentinel else LIMITS.max_length_m,
                **data,
            )
            return None, True
        if abs(value) > LIMITS.max_length_m:
            self.report(
                NUMBER_OUT_OF_RANGE,
                f'<limit {key}="{text}">: {value:g} {unit} is beyond the limit of {LIMITS.max_length_m:g} {unit}',
                element,
                subject,
                f"limit.{key}",
                limit=LIMITS.max_length_m,
                **data,
            )
            return None, False
        return value, False


__all__ = ["BOUNDED_JOINT_TYPES", "UrdfJoints"]
