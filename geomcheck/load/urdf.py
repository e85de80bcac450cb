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
    Capsule,
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
    DUPLICATE_MATERIAL,
    INVALID_NUMBER,
    MISSING_ATTRIBUTE,
    MISSING_ELEMENT,
    NUMBER_OUT_OF_RANGE,
    UNDEFINED_MATERIAL,
    UNKNOWN_ATTRIBUTE,
    UNKNOWN_ELEMENT,
    UNKNOWN_GEOMETRY,
    URDF_VERSION,
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
    ("capsule", "radius"): _LENGTH,
    ("capsule", "length"): _LENGTH,
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
    ("capsule", "radius"): _SIZE,
    ("capsule", "length"): _SIZE,
    ("mesh", "scale"): (_LIMITS.min_mesh_scale, ""),
}


# The versions urdfdom reads (``<robot version>``; absent is 1.0): 1.1 brought capsules and
# ``<origin quat_xyzw>``, 1.2 acceleration, deceleration and jerk limits
URDF_VERSIONS = ((1, 0), (1, 1), (1, 2))
FIRST_CAPSULE_VERSION = (1, 1)
REFERENCE = "urdfdom"  # the parser a finding's ``accepted_by`` names when it loads the file as written
# findings of a link's elements that urdfdom answers by leaving the element out, not by
# refusing the robot (parseLink's failure is logged; the link is kept without the element)
LINK_PARSE_RULES = (INVALID_NUMBER, MISSING_ATTRIBUTE, MISSING_ELEMENT)

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


def urdf_version(text: str) -> tuple[int, int] | str:
    """``(major, minor)`` of a ``<robot version>``, read as urdfdom reads it, or urdfdom's
    reason to refuse it (its own words)."""
    parts = text.split(".")
    if parts[-1] == "":  # urdfdom's split keeps no empty field after the last dot
        parts.pop()
    if len(parts) != 2:
        return "The version attribute should be in the form 'x.y'"
    out = []
    for part in parts:
        if not part:
            return "One of the fields of the version attribute is blank"
        digits = len(part) - len(part.lstrip("+-"))
        body = part[digits:]
        head = len(body) - len(body.lstrip("0123456789"))
        if head == 0 or digits > 1:
            return "Version attribute is not an integer"
        if head < len(body):
            return "Extra characters after the version number"
        value = int(part[: digits + head])
        if value < 0:
            return "Version number must be positive"
        out.append(value)
    return out[0], out[1]


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
        self.version: tuple[int, int] = (1, 0)
        self.top_level_materials: dict[str, etree._Element] = {}
        self.material_repeats: Counter[str] = Counter()

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
        if rule in LINK_PARSE_RULES and subject.link is not None and severity is None:
            # urdfdom gives up on the element (a visual, a collision, an inertial) and keeps the
            # link and the robot: the element is missing in every consumer, the file loads
            message += "; urdfdom logs an error and loads the link without this element"
            data = {**data, "accepted_by": REFERENCE}
        elif rule is NUMBER_OUT_OF_RANGE:  # urdfdom never judges a magnitude
            if severity is None:
                message += "; urdfdom loads it as written, geomcheck does not use it"
            data = {**data, "accepted_by": REFERENCE}
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
        # the shape of a <geometry> is its first element, whatever it is (an unknown one is GC129)
        shape = next((c for c in element if isinstance(c.tag, str)), None) if kind == "geometry" else None
        for child in element if kind != "robot" else ():  # top level: see top_level_extension
            tag = _tag(child)
            if tag is None or tag in spec.children or tag in spec.tolerated or child is shape:
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
                value=_shorten(element.get("quat_xyzw") or ""),
                expected=4,
            )
            return Pose(xyz)
        quat = self.numbers(element, "quat_xyzw", 4, subject, about, (0.0, 0.0, 0.0, 1.0))
        assert quat is not None
        return Pose(xyz, quaternion_rpy(quat))

    def geometry(self, parent: etree._Element, subject: Subject, about: str) -> Geometry | None:
        element = self.child(parent, "geometry")
        if element is None:
            kind = _tag(parent)
            self.report(MISSING_ELEMENT, f"<{kind}> has no <geometry>", parent, subject, about, element="geometry")
            return None
        self.check_element(element, "geometry", subject, f"{about}.geometry")
        # urdfdom reads the first element inside <geometry>, whatever it is
        shape = next((c for c in element if isinstance(c.tag, str)), None)
        if shape is None:
            self.report(
                MISSING_ELEMENT,
                "<geometry> has no <box>, <cylinder>, <sphere> or <mesh>",
                element,
                subject,
                f"{about}.geometry",
                element="box|cylinder|sphere|mesh",
            )
            return None
        kind = _tag(shape)
        if (
            kind is None
            or kind not in SPEC["geometry"].children
            or (kind == "capsule" and self.version < FIRST_CAPSULE_VERSION)
        ):
            self.unknown_geometry(parent, shape, subject, about)
            return None
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
        if kind == "capsule":
            return self.capsule(shape, subject, about)
        filename = (shape.get("filename") or "").strip()
        if not filename:
            self.report(MISSING_ATTRIBUTE, "<mesh> has no filename", shape, subject, f"{about}.filename")
            return None
        return Mesh(filename, self.vec3(shape, "scale", subject, about, (1.0, 1.0, 1.0)))

    def unknown_geometry(self, parent: etree._Element, shape: etree._Element, subject: Subject, about: str) -> None:
        """GC129: a shape urdfdom does not read in this file's version; it drops the element."""
        tag = shape.tag if isinstance(shape.tag, str) else "?"
        kind = _tag(parent)
        version = ".".join(str(v) for v in self.version)
        if tag == "capsule":
            reason = f'<capsule> is URDF 1.1, this file is URDF {version} (write <robot version="1.1">)'
        else:
            reason = f"<{tag}> is no URDF {version} shape (box, cylinder, sphere, mesh)"
        self.report(
            UNKNOWN_GEOMETRY,
            f"{reason}: urdfdom logs an error and loads the robot without this <{kind}>",
            shape,
            subject,
            f"{about}.geometry",
            element=tag,
            accepted_by=REFERENCE,
        )

    def capsule(self, shape: etree._Element, subject: Subject, about: str) -> Capsule | None:
        """A URDF 1.1 ``<capsule radius length>`` (``length`` its cylindrical part, as SDFormat's),
        measured as the cylinder that encloses it; urdfdom drops one with a negative size."""
        radius = self.number(shape, "radius", subject, about, None, required=True)
        length = self.number(shape, "length", subject, about, None, required=True)
        if radius is None or length is None:
            return None
        if radius < 0.0 or length < 0.0:
            self.report(
                INVALID_NUMBER,
                f"<capsule radius={radius:g} length={length:g}>: a capsule of negative size",
                shape,
                subject,
                about,
                element="capsule",
                attribute="radius" if radius < 0.0 else "length",
                value=f"{min(radius, length):g}",
                expected=1,
            )
            return None
        return Capsule(radius, length + 2.0 * radius)

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
                self.required_of(child, optional, subject)
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
        self.read_version(root)
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
                self.unique_material(child)
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

    def read_version(self, root: etree._Element) -> None:
        """``<robot version>`` as urdfdom reads it (GC127 when it refuses it); absent is 1.0."""
        text = root.get("version")
        if text is None:
            return
        read = urdf_version(text)
        if isinstance(read, tuple) and read in URDF_VERSIONS:
            self.version = read
            return
        readable = ", ".join(f"{a}.{b}" for a, b in URDF_VERSIONS)
        reason = read if isinstance(read, str) else f"urdfdom reads versions {readable}"
        self.report(
            URDF_VERSION,
            f'<robot version="{_shorten(text)}"> is not a version urdfdom reads ({reason}): urdfdom refuses the robot',
            root,
            Subject(),
            "version",
            version=_shorten(text),
        )

    def unique_material(self, element: etree._Element) -> None:
        """GC128 for a top-level material whose name an earlier top-level one took."""
        name = (element.get("name") or "").strip()
        if not name:
            return
        first = self.top_level_materials.setdefault(name, element)
        if first is element:
            return
        where = self.location(first)
        self.material_repeats[name] += 1
        self.report(
            DUPLICATE_MATERIAL,
            f"material {name!r} is already defined at {where}: urdfdom refuses the robot ('material {name} is "
            "not unique')",
            element,
            Subject(),
            f"material {name} occurrence {self.material_repeats[name] + 1}",
            material=name,
            first=str(where),
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
