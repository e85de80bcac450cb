"""Parse an expanded URDF document into :mod:`geomcheck.model`, with parse-time GC1xx findings.

Unknown extension elements are skipped quietly; unknown elements and attributes inside the
URDF core (GC105/GC106), unparseable numbers (GC107), missing required attributes (GC108)
and elements (GC109), and references to undefined materials (GC124) become diagnostics,
and parsing goes on with the element's default value. Lengths [m], angles [rad], masses
[kg], inertias [kg m^2].
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

from lxml import etree

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.errors import InputError
from geomcheck.load.locations import LocationResolver
from geomcheck.load.urdf_spec import (
    SPEC,
    TOP_LEVEL_CORE,
    TOP_LEVEL_SIMILARITY,
    closest,
    did_you_mean,
    extension_attributes,
)
from geomcheck.model import (
    Box,
    Cylinder,
    Geometry,
    Inertial,
    Joint,
    Limit,
    Link,
    Mesh,
    Mimic,
    Pose,
    Robot,
    Shape,
    SourceLocation,
    Sphere,
    Vec3,
)
from geomcheck.rules import Rule
from geomcheck.rules.structure import (
    INVALID_NUMBER,
    MISSING_ATTRIBUTE,
    MISSING_ELEMENT,
    NUMBER_OUT_OF_RANGE,
    UNDEFINED_MATERIAL,
    UNKNOWN_ATTRIBUTE,
    UNKNOWN_ELEMENT,
)
from geomcheck.thresholds import LoadLimits

_LIMITS = LoadLimits()
_LENGTH = (_LIMITS.max_length_m, "m")
# (element, attribute) -> largest magnitude and its unit; numbers beyond it are GC126
MAGNITUDE_LIMITS: dict[tuple[str, str], tuple[float, str]] = {
    ("origin", "xyz"): _LENGTH,
    ("origin", "rpy"): (_LIMITS.max_length_m, "rad"),
    ("box", "size"): _LENGTH,
    ("cylinder", "radius"): _LENGTH,
    ("cylinder", "length"): _LENGTH,
    ("sphere", "radius"): _LENGTH,
    ("mesh", "scale"): (_LIMITS.max_mesh_scale, ""),
    ("axis", "xyz"): _LENGTH,
    ("mass", "value"): (_LIMITS.max_mass_kg, "kg"),
    **{("inertia", k): (_LIMITS.max_inertia_kg_m2, "kg m^2") for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")},
}
_SIZE = (_LIMITS.min_size_m, "m")
# (element, attribute) -> smallest nonzero magnitude and its unit; sizes below it are GC126
SIZE_FLOORS: dict[tuple[str, str], tuple[float, str]] = {
    ("box", "size"): _SIZE,
    ("cylinder", "radius"): _SIZE,
    ("cylinder", "length"): _SIZE,
    ("sphere", "radius"): _SIZE,
    ("mesh", "scale"): (_LIMITS.min_mesh_scale, ""),
}


# Joint bounds are judged where a consumer reads them: urdfdom, MoveIt, pinocchio and Gazebo use
# <limit lower/upper> of revolute and prismatic joints only (urdfdom still parses the numbers of
# every <limit>, so an unparseable one stays GC107 on any joint type)
BOUNDED_JOINT_TYPES = ("revolute", "prismatic")


@dataclass(frozen=True)
class Subject:
    """Who a finding is about: a link, a joint, or the robot (both ``None``)."""

    link: str | None = None
    joint: str | None = None


@dataclass(frozen=True)
class _MaterialUse:
    name: str
    subject: Subject
    about: str
    location: SourceLocation


MAX_QUOTED_CHARACTERS = 80  # an attribute value quoted in a message [characters]
LINK_ONLY = frozenset({"inertial", "visual", "collision"})  # elements URDF reads only inside a <link>


def _shorten(text: str) -> str:
    """``text`` cut to :data:`MAX_QUOTED_CHARACTERS` (a message never carries a whole hostile value)."""
    return text if len(text) <= MAX_QUOTED_CHARACTERS else f"{text[:MAX_QUOTED_CHARACTERS]}..."


def _tag(element: etree._Element) -> str | None:
    """Local name of a core-candidate element; ``None`` for comments and namespaced extensions."""
    tag = element.tag
    if not isinstance(tag, str) or tag.startswith("{"):
        return None
    return tag


def _ignored_misplaced(child: etree._Element, tag: str, kind: str) -> str | None:
    """Why a core element in the wrong place loses nothing (``None`` when it may: the author's
    pose, geometry or inertia is then silently dropped by every consumer)."""
    if tag == "material" and kind == "collision":
        return "a collision element has no appearance: every consumer ignores it"
    if tag == "origin" and all(_zero(child.get(a)) for a in ("xyz", "rpy")):
        return "an identity pose: it would change nothing where it belongs"
    return None


def _member_order(d: Diagnostic) -> tuple[str, str, str, int]:
    """Order of the members of a group of findings: by subject name, then place."""
    loc = d.location
    return (d.link or d.joint or "", d.about, loc.file if loc else "", (loc.line or 0) if loc else 0)


def _zero(text: str | None) -> bool:
    """Whether an xyz or rpy value is absent or all zeros."""
    try:
        return text is None or all(float(v) == 0.0 for v in text.split())
    except ValueError:
        return False


class UrdfParser:
    """One parse of one document; collects findings in :attr:`diagnostics`."""

    def __init__(self, root: etree._Element, resolver: LocationResolver) -> None:
        self.root = root
        self.resolver = resolver
        self.elements = [e for e in root.iter() if isinstance(e.tag, str)]
        self.index = {e: i for i, e in enumerate(self.elements)}
        self.diagnostics: list[Diagnostic] = []
        self.seen: dict[tuple[object, ...], int] = {}
        self.repeats: dict[int, list[Diagnostic]] = {}
        self.material_uses: list[_MaterialUse] = []
        self.defined_materials: set[str] = set()
        self.colors: dict[str, tuple[float, float, float, float]] = {}
        self.top_level_seen: Counter[str] = Counter()

    # helpers ---------------------------------------------------------------------------

    def location(self, element: etree._Element, name: str | None = None) -> SourceLocation:
        tag = _tag(element) or "robot"
        return self.resolver.locate(self.index.get(element, -1), element.sourceline, tag, name)

    def report(
        self,
        rule: Rule,
        message: str,
        node: etree._Element,
        subject: Subject,
        about: str,
        severity: Severity | None = None,
        group: tuple[str, ...] | None = None,
        **data: Any,
    ) -> None:
        self.add(
            rule.diagnose(
                message,
                link=subject.link,
                joint=subject.joint,
                about=about,
                location=self.location(node),
                data=data,
                severity=severity,
            ),
            group,
        )

    def add(self, diagnostic: Diagnostic, group: tuple[str, ...] | None = None) -> None:
        """Keep ``diagnostic`` unless the same finding at the same source line (or, given a
        ``group``, the same kind of finding anywhere in the robot) was kept already.

        A typo inside a xacro macro is one mistake however often the macro is expanded: the
        first expansion is reported and names the other subjects. Extension markup that no
        consumer reads is one fact about the robot: one finding per kind, naming the others.
        """
        loc = diagnostic.location
        key: tuple[object, ...]
        if group is not None:
            key = (diagnostic.code, "robot-wide", *group)
        elif loc is None or loc.line is None:
            self.diagnostics.append(diagnostic)
            return
        else:
            key = (diagnostic.code, loc.file, loc.line, diagnostic.about, diagnostic.message)
        if key in self.seen:
            if diagnostic.link or diagnostic.joint:
                self.repeats.setdefault(self.seen[key], []).append(diagnostic)
            return
        self.seen[key] = len(self.diagnostics)
        self.diagnostics.append(diagnostic)

    def findings(self) -> list[Diagnostic]:
        """The diagnostics, each group of repeats as one finding: its member with the first
        subject name (not the first in document order, which reordering the file would
        change) naming the other subjects, sorted."""
        out = list(self.diagnostics)
        for index, others in self.repeats.items():
            members = [out[index], *others]
            d = min(members, key=_member_order)
            names = sorted({m.link or m.joint or "" for m in members if m is not d})
            listed = ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")
            out[index] = replace(d, message=f"{d.message} (also in {listed})", data={**d.data, "also": names})
        return out

    def check_element(self, element: etree._Element, kind: str, subject: Subject, about: str) -> None:
        """GC106 for unknown attributes and GC105 for unknown children of a core element.

        Every URDF consumer skips what it does not know, so what matters is what the author
        meant: a near-miss of a name valid at that place (did you mean) or a core element
        whose content is lost where it stands is a warning; extension markup that no consumer
        reads there is info, once per kind for the whole robot."""
        spec = SPEC[kind]
        extensions = extension_attributes(kind)  # a tool's own attributes: not typos
        known = spec.attributes | spec.tolerated_attributes | extensions
        unknown = [a for a in element.attrib if not a.startswith("{") and a not in known]
        if unknown:
            suggestions = {a: closest(a, spec.attributes | extensions) for a in unknown}
            described = ", ".join(
                f"{a!r} (did you mean {suggestions[a]!r}?)" if suggestions[a] else repr(a) for a in unknown
            )
            noun = "attribute" if len(unknown) == 1 else "attributes"
            valid = ", ".join(sorted(spec.attributes)) or "none"
            misspelt = any(suggestions.values())
            self.report(
                UNKNOWN_ATTRIBUTE,
                f"unknown {noun} {described} on <{kind}> (URDF defines: {valid})"
                + ("" if misspelt else ": extension markup no URDF consumer reads"),
                element,
                subject,
                f"{about}@{','.join(unknown)}",
                severity=None if misspelt else Severity.INFO,
                group=None if misspelt else (kind, *sorted(unknown)),
                element=kind,
                attributes=unknown,
                suggestions={a: s for a, s in suggestions.items() if s},
            )
        for child in element if kind != "robot" else ():  # top level: see top_level_extension
            tag = _tag(child)
            if tag is None or tag in spec.children or tag in spec.tolerated:
                continue
            self.unknown_child(child, tag, kind, subject, about)

    def unknown_child(self, child: etree._Element, tag: str, kind: str, subject: Subject, about: str) -> None:
        """GC105 for ``<tag>`` inside a core ``<kind>``, with its severity by consequence."""
        spec = SPEC[kind]
        suggestion = closest(tag, spec.children) if spec.children else None
        where = f"inside <{kind}>" if spec.children else f"inside <{kind}>, which has no child elements in URDF"
        homes = sorted(parent for parent, other in SPEC.items() if tag in other.children)
        if suggestion is not None:
            hint, severity, group = f"; did you mean {suggestion!r}?", None, None
        elif homes:
            ignored = _ignored_misplaced(child, tag, kind)
            hint = f"; <{tag}> belongs in " + " or ".join(f"<{h}>" for h in homes)
            if ignored:
                hint += f" ({ignored})"
            severity = Severity.INFO if ignored else None
            group = (kind, tag) if ignored else None
        else:
            hint = ": extension markup no URDF consumer reads there"
            severity, group = Severity.INFO, (kind, tag)
        self.report(
            UNKNOWN_ELEMENT,
            f"unknown element <{tag}> {where}{hint}",
            child,
            subject,
            f"{about}/{tag}",
            severity=severity,
            group=group,
            element=tag,
            parent=kind,
            suggestion=suggestion,
        )

    def children(self, element: etree._Element, tag: str) -> list[etree._Element]:
        return [c for c in element if _tag(c) == tag]

    def child(self, element: etree._Element, tag: str) -> etree._Element | None:
        found = self.children(element, tag)
        return found[0] if found else None

    def numbers(
        self,
        element: etree._Element,
        attribute: str,
        count: int,
        subject: Subject,
        about: str,
        default: Sequence[float] | None,
        required: bool = False,
        magnitude: bool = True,
    ) -> tuple[float, ...] | None:
        """``count`` finite numbers from ``attribute``; the default (and GC107/GC108) otherwise.
        ``magnitude=False`` leaves the size of the numbers to the caller (GC126)."""
        text = element.get(attribute)
        kind = _tag(element)
        if text is None or not text.strip():
            if required:
                self.report(
                    MISSING_ATTRIBUTE,
                    f"<{kind}> has no {attribute} attribute",
                    element,
                    subject,
                    f"{about}.{attribute}",
                    element=kind,
                    attribute=attribute,
                )
            return tuple(default) if default is not None else None
        parts = text.split()
        values: list[float] = []
        bad = None
        for part in parts:
            try:
                value = float(part)
            except ValueError:
                bad = part
                break
            if not math.isfinite(value):
                bad = part
                break
            values.append(value)
        bound = MAGNITUDE_LIMITS.get((kind or "", attribute)) if magnitude else None
        if bad is None and bound is not None and len(values) == count:
            largest = max(values, key=abs)
            if abs(largest) > bound[0]:
                unit = f" {bound[1]}" if bound[1] else ""
                self.report(
                    NUMBER_OUT_OF_RANGE,
                    f'<{kind} {attribute}="{_shorten(text)}">: {largest:g}{unit} is beyond the limit of '
                    f"{bound[0]:g}{unit}",
                    element,
                    subject,
                    f"{about}.{attribute}",
                    element=kind,
                    attribute=attribute,
                    value=largest,
                    limit=bound[0],
                )
                return tuple(default) if default is not None else None
        floor = SIZE_FLOORS.get((kind or "", attribute))
        tiny = [v for v in values if 0.0 < abs(v) < floor[0]] if floor is not None and bad is None else []
        if tiny and len(values) == count:
            assert floor is not None
            unit = f" {floor[1]}" if floor[1] else ""
            self.report(
                NUMBER_OUT_OF_RANGE,
                f'<{kind} {attribute}="{_shorten(text)}">: {tiny[0]:g}{unit} is below the smallest size of '
                f"{floor[0]:g}{unit}",
                element,
                subject,
                f"{about}.{attribute}",
                element=kind,
                attribute=attribute,
                value=tiny[0],
                limit=floor[0],
            )
            return tuple(default) if default is not None else None
        if bad is not None or len(values) != count:
            reason = f"{bad!r} is not a finite number" if bad is not None else f"expected {count}, got {len(parts)}"
            noun = "a number" if count == 1 else f"{count} numbers"
            self.report(
                INVALID_NUMBER,
                f'<{kind} {attribute}="{_shorten(text)}"> is not {noun}: {reason}',
                element,
                subject,
                f"{about}.{attribute}",
                element=kind,
                attribute=attribute,
                value=_shorten(text),
                expected=count,
            )
            return tuple(default) if default is not None else None
        return tuple(values)

    def number(
        self,
        element: etree._Element,
        attribute: str,
        subject: Subject,
        about: str,
        default: float | None,
        required: bool = False,
        magnitude: bool = True,
    ) -> float | None:
        values = self.numbers(
            element, attribute, 1, subject, about, None if default is None else (default,), required, magnitude
        )
        return values[0] if values else None

    def vec3(self, element: etree._Element, attribute: str, subject: Subject, about: str, default: Vec3) -> Vec3:
        values = self.numbers(element, attribute, 3, subject, about, default)
        assert values is not None
        return (values[0], values[1], values[2])

    def name_of(self, element: etree._Element, subject: Subject, about: str) -> str:
        name = (element.get("name") or "").strip()
        if not name:
            kind = _tag(element)
            self.report(MISSING_ATTRIBUTE, f"<{kind}> has no name", element, subject, f"{about}.name", element=kind)
        return name

    # elements --------------------------------------------------------------------------

    def origin(self, parent: etree._Element, subject: Subject, about: str) -> Pose:
        element = self.child(parent, "origin")
        if element is None:
            return Pose()
        about = f"{about}.origin" if about else "origin"
        self.check_element(element, "origin", subject, about)
        return Pose(
            self.vec3(element, "xyz", subject, about, (0.0, 0.0, 0.0)),
            self.vec3(element, "rpy", subject, about, (0.0, 0.0, 0.0)),
        )

    def geometry(self, parent: etree._Element, subject: Subject, about: str) -> Geometry | None:
        element = self.child(parent, "geometry")
        if element is None:
            kind = _tag(parent)
            self.report(MISSING_ELEMENT, f"<{kind}> has no <geometry>", parent, subject, about, element="geometry")
            return None
        self.check_element(element, "geometry", subject, f"{about}.geometry")
        shapes = [c for c in element if _tag(c) in SPEC["geometry"].children]
        if not shapes:
            if not any(_tag(c) for c in element):  # unknown children were reported by check_element
                self.report(
                    MISSING_ELEMENT,
                    "<geometry> has no <box>, <cylinder>, <sphere> or <mesh>",
                    element,
                    subject,
                    f"{about}.geometry",
                    element="box|cylinder|sphere|mesh",
                )
            return None
        shape = shapes[0]
        kind = _tag(shape)
        assert kind is not None
        about = f"{about}.{kind}"
        self.check_element(shape, kind, subject, about)
        if kind == "box":
            size = self.numbers(shape, "size", 3, subject, about, None, required=True)
            return Box((size[0], size[1], size[2])) if size else None
        if kind == "cylinder":
            radius = self.number(shape, "radius", subject, about, None, required=True)
            length = self.number(shape, "length", subject, about, None, required=True)
            return Cylinder(radius, length) if radius is not None and length is not None else None
        if kind == "sphere":
            radius = self.number(shape, "radius", subject, about, None, required=True)
            return Sphere(radius) if radius is not None else None
        filename = (shape.get("filename") or "").strip()
        if not filename:
            self.report(MISSING_ATTRIBUTE, "<mesh> has no filename", shape, subject, f"{about}.filename")
            return None
        return Mesh(filename, self.vec3(shape, "scale", subject, about, (1.0, 1.0, 1.0)))

    def material(self, element: etree._Element, subject: Subject, about: str) -> None:
        """Record a material definition (color or texture) or a reference by name."""
        self.check_element(element, "material", subject, about)
        name = (element.get("name") or "").strip()
        color = self.child(element, "color")
        texture = self.child(element, "texture")
        rgba = None
        if color is not None:
            self.check_element(color, "color", subject, f"{about}.color")
            rgba = self.numbers(color, "rgba", 4, subject, f"{about}.color", None, required=True)
        if texture is not None:
            self.check_element(texture, "texture", subject, f"{about}.texture")
        if color is not None or texture is not None:
            if name:
                self.defined_materials.add(name)
                if rgba is not None:
                    self.colors.setdefault(name, (rgba[0], rgba[1], rgba[2], rgba[3]))
        elif name:
            self.material_uses.append(_MaterialUse(name, subject, about, self.location(element)))
        elif subject.link is None:
            self.report(MISSING_ATTRIBUTE, "<material> has no name", element, subject, about, element="material")

    def shape(self, element: etree._Element, kind: str, index: int, subject: Subject) -> Shape | None:
        about = f"{kind}[{index}]"
        self.check_element(element, kind, subject, about)
        origin = self.origin(element, subject, about)
        geometry = self.geometry(element, subject, about)
        if kind == "visual":
            material = self.child(element, "material")
            if material is not None:
                self.material(material, subject, f"{about}.material")
        if geometry is None:
            return None
        name = element.get("name")
        return Shape(kind, index, geometry, origin, name, self.location(element))  # type: ignore[arg-type]

    def inertial(self, element: etree._Element, subject: Subject) -> Inertial:
        about = "inertial"
        self.check_element(element, "inertial", subject, about)
        origin = self.origin(element, subject, about)
        mass_element = self.child(element, "mass")
        mass = 0.0
        if mass_element is None:
            self.report(MISSING_ELEMENT, "<inertial> has no <mass>", element, subject, about, element="mass")
        else:
            self.check_element(mass_element, "mass", subject, f"{about}.mass")
            mass = self.number(mass_element, "value", subject, f"{about}.mass", 0.0, required=True) or 0.0
        moments = dict.fromkeys(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), 0.0)
        inertia = self.child(element, "inertia")
        if inertia is None:
            self.report(MISSING_ELEMENT, "<inertial> has no <inertia>", element, subject, about, element="inertia")
        else:
            self.check_element(inertia, "inertia", subject, f"{about}.inertia")
            for key in moments:
                moments[key] = self.number(inertia, key, subject, f"{about}.inertia", 0.0, required=True) or 0.0
        m = moments
        return Inertial(
            mass, origin, m["ixx"], m["ixy"], m["ixz"], m["iyy"], m["iyz"], m["izz"], location=self.location(element)
        )

    def link(self, element: etree._Element) -> Link:
        name = (element.get("name") or "").strip()
        subject = Subject(link=name or None)
        self.name_of(element, subject, "link")
        self.check_element(element, "link", subject, "")
        inertials = self.children(element, "inertial")
        inertial = self.inertial(inertials[0], subject) if inertials else None
        shapes: dict[str, list[Shape]] = {"visual": [], "collision": []}
        for kind, found in shapes.items():
            for index, child in enumerate(self.children(element, kind)):
                shape = self.shape(child, kind, index, subject)
                if shape is not None:
                    found.append(shape)
        return Link(name, inertial, tuple(shapes["visual"]), tuple(shapes["collision"]), self.location(element, name))

    def joint(self, element: etree._Element) -> Joint:
        name = (element.get("name") or "").strip()
        subject = Subject(joint=name or None)
        self.name_of(element, subject, "joint")
        self.check_element(element, "joint", subject, "")
        kind = (element.get("type") or "").strip()
        if not kind:
            self.report(MISSING_ATTRIBUTE, "<joint> has no type", element, subject, "type", element="joint")
        links = {}
        for role in ("parent", "child"):
            child = self.child(element, role)
            links[role] = ""
            if child is not None:
                self.check_element(child, role, subject, role)
                links[role] = (child.get("link") or "").strip()
        axis: Vec3 = (1.0, 0.0, 0.0)
        axis_element = self.child(element, "axis")
        if axis_element is not None:
            self.check_element(axis_element, "axis", subject, "axis")
            axis = self.vec3(axis_element, "xyz", subject, "axis", axis)
        limit = None
        limit_element = self.child(element, "limit")
        if limit_element is not None:
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
            limit = Limit(**values, unlimited=unlimited)
        mimic = None
        mimic_element = self.child(element, "mimic")
        if mimic_element is not None:
            self.check_element(mimic_element, "mimic", subject, "mimic")
            target = (mimic_element.get("joint") or "").strip()
            if not target:
                self.report(MISSING_ATTRIBUTE, "<mimic> has no joint", mimic_element, subject, "mimic.joint")
            else:
                mimic = Mimic(
                    target,
                    self.number(mimic_element, "multiplier", subject, "mimic", 1.0) or 0.0,
                    self.number(mimic_element, "offset", subject, "mimic", 0.0) or 0.0,
                )
        for optional in ("calibration", "dynamics", "safety_controller"):
            for child in self.children(element, optional):
                self.check_element(child, optional, subject, optional)
                for attribute in SPEC[optional].attributes:
                    self.number(child, attribute, subject, optional, None)
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

    def joint_bound(
        self, element: etree._Element, key: str, value: float, kind: str, subject: Subject
    ) -> tuple[float | None, bool]:
        """A revolute or prismatic ``<limit lower|upper>`` as the model keeps it, and whether it
        was SDFormat's "no limit" sentinel. Bounds other joint types carry are read by no
        consumer and are not judged at all."""
        unit = "m" if kind == "prismatic" else "rad"
        text = _shorten(element.get(key) or "")
        data: dict[str, Any] = {"element": "limit", "attribute": key, "value": value}
        if abs(value) >= _LIMITS.unlimited_joint_bound:
            self.report(
                NUMBER_OUT_OF_RANGE,
                f'<limit {key}="{text}">: SDFormat\'s "no limit" value, read by Gazebo as unlimited; urdfdom, '
                f"MoveIt and pinocchio take it as written (geomcheck takes the {kind} joint as unbounded on that side)",
                element,
                subject,
                f"limit.{key}",
                severity=Severity.INFO,
                limit=_LIMITS.unlimited_joint_bound,
                **data,
            )
            return None, True
        if abs(value) > _LIMITS.max_length_m:
            self.report(
                NUMBER_OUT_OF_RANGE,
                f'<limit {key}="{text}">: {value:g} {unit} is beyond the limit of {_LIMITS.max_length_m:g} {unit}',
                element,
                subject,
                f"limit.{key}",
                limit=_LIMITS.max_length_m,
                **data,
            )
            return None, False
        return value, False

    def robot(self) -> Robot:
        root = self.root
        if _tag(root) != "robot":
            location = self.location(root)
            diagnostic = MISSING_ELEMENT.diagnose(
                f"the root element is <{root.tag}>, not <robot>: this is not a URDF document", location=location
            )
            raise InputError(
                f"{location}: GC109 missing-urdf-element: root element is <{root.tag}>, not <robot>", diagnostic
            )
        robot_subject = Subject()
        name = self.name_of(root, robot_subject, "robot")
        self.check_element(root, "robot", robot_subject, "robot")
        links: list[Link] = []
        joints: list[Joint] = []
        for child in root:
            tag = _tag(child)
            if tag == "link":
                links.append(self.link(child))
            elif tag == "joint":
                joints.append(self.joint(child))
            elif tag == "material":
                self.material(child, robot_subject, f"material {child.get('name') or ''}".strip())
            elif tag in LINK_ONLY and links:
                self.outside_link(child, tag, links[-1].name)
            elif tag is not None and tag not in SPEC["robot"].children:
                self.top_level_extension(child, tag)
        self.check_materials()
        return Robot(name, tuple(links), tuple(joints), self.location(root, name), dict(self.colors))

    def outside_link(self, element: etree._Element, tag: str, before: str) -> None:
        """GC105 for a link's own element written as a child of ``<robot>`` after link ``before``
        closed (a ``</link>`` one line too early): urdfdom reads only ``<robot>``'s ``<link>``,
        ``<joint>`` and ``<material>``, so the element is dropped without a word."""
        self.report(
            UNKNOWN_ELEMENT,
            UNKNOWN_ELEMENT.message("outside_link", tag=tag, link=before),
            element,
            Subject(link=before),
            f"robot/{tag}",
            element=tag,
            parent="robot",
            suggestion=None,
        )

    def top_level_extension(self, element: etree._Element, tag: str) -> None:
        """Top-level extensions are fine; one that looks like a misspelt core element is reported."""
        match = closest(tag, TOP_LEVEL_CORE, TOP_LEVEL_SIMILARITY)
        self.top_level_seen[tag] += 1
        if match is not None:
            self.report(
                UNKNOWN_ELEMENT,
                f"unknown top-level element <{tag}>; did you mean {match!r}?",
                element,
                Subject(),
                f"robot/{tag}#{self.top_level_seen[tag]}",
                element=tag,
                parent="robot",
                suggestion=match,
            )

    def check_materials(self) -> None:
        for use in self.material_uses:
            if use.name in self.defined_materials:
                continue
            hint = did_you_mean(use.name, self.defined_materials)
            self.add(
                UNDEFINED_MATERIAL.diagnose(
                    f"material {use.name!r} is not defined with a color or texture{hint}",
                    link=use.subject.link,
                    joint=use.subject.joint,
                    about=use.about,
                    location=use.location,
                    data={"material": use.name},
                )
            )


def parse_urdf(root: etree._Element, resolver: LocationResolver) -> tuple[Robot, list[Diagnostic]]:
    """The robot of an expanded URDF document and the parse-time findings."""
    parser = UrdfParser(root, resolver)
    robot = parser.robot()
    return robot, parser.findings()
