"""Parse an expanded URDF document into :mod:`geomcheck.model`, with parse-time GC1xx findings.

Unknown extension elements are skipped quietly; unknown elements and attributes inside the
URDF core (GC105/GC106, :mod:`~geomcheck.load.urdf_markup`), unparseable numbers (GC107,
:mod:`~geomcheck.load.urdf_numbers`), missing required attributes (GC108) and elements (GC109),
and references to undefined materials (GC124) become diagnostics, and parsing goes on with the
element's default value. Joints are read by :mod:`~geomcheck.load.urdf_joint`. Lengths [m],
angles [rad], masses [kg], inertias [kg m^2].
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

from lxml import etree

from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError
from geomcheck.load.locations import LocationResolver
from geomcheck.load.urdf_findings import REFERENCE, Subject, shorten, tag_of
from geomcheck.load.urdf_joint import UrdfJoints
from geomcheck.load.urdf_spec import (
    FIRST_CAPSULE_VERSION,
    SPEC,
    TOP_LEVEL_CORE,
    TOP_LEVEL_SIMILARITY,
    URDF_VERSIONS,
    closest,
    did_you_mean,
    urdf_version,
)
from geomcheck.model import (
    Box,
    Capsule,
    Cylinder,
    Geometry,
    Inertial,
    Joint,
    Link,
    Mesh,
    Robot,
    Shape,
    SourceLocation,
    Sphere,
)
from geomcheck.rules.structure import (
    DUPLICATE_MATERIAL,
    INVALID_NUMBER,
    MISSING_ATTRIBUTE,
    MISSING_ELEMENT,
    UNDEFINED_MATERIAL,
    UNKNOWN_ELEMENT,
    UNKNOWN_GEOMETRY,
    URDF_VERSION,
)


@dataclass(frozen=True)
class _MaterialUse:
    name: str
    subject: Subject
    about: str
    location: SourceLocation


LINK_ONLY = frozenset({"inertial", "visual", "collision"})  # elements URDF reads only inside a <link>


class UrdfParser(UrdfJoints):
    """One parse of one document; collects findings in :attr:`diagnostics`."""

    def __init__(self, root: etree._Element, resolver: LocationResolver) -> None:
        super().__init__(root, resolver)
        self.material_uses: list[_MaterialUse] = []
        self.defined_materials: set[str] = set()
        self.colors: dict[str, tuple[float, float, float, float]] = {}
        self.top_level_seen: Counter[str] = Counter()
        self.top_level_materials: dict[str, etree._Element] = {}
        self.material_repeats: Counter[str] = Counter()

    # elements --------------------------------------------------------------------------

    def geometry(self, parent: etree._Element, subject: Subject, about: str) -> Geometry | None:
        element = self.child(parent, "geometry")
        if element is None:
            kind = tag_of(parent)
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
        kind = tag_of(shape)
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
        kind = tag_of(parent)
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

    def robot(self) -> Robot:
        root = self.root
        if tag_of(root) != "robot":
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
            tag = tag_of(child)
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
            f'<robot version="{shorten(text)}"> is not a version urdfdom reads ({reason}): urdfdom refuses the robot',
            root,
            Subject(),
            "version",
            version=shorten(text),
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
