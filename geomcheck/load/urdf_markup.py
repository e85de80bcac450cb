"""GC105 and GC106: unknown elements and attributes inside the URDF core, with their
severity by consequence.

Every URDF consumer skips what it does not know, so what matters is what the author meant: a
near-miss of a name valid at that place (did you mean) or a core element whose content is lost
where it stands is a warning; extension markup that no consumer reads there is info, once per
kind for the whole robot.
"""

from __future__ import annotations

from lxml import etree

from geomcheck.diagnostics import Severity
from geomcheck.load.urdf_findings import Subject, UrdfFindings, tag_of
from geomcheck.load.urdf_spec import SPEC, closest, extension_attributes
from geomcheck.rules.structure import UNKNOWN_ATTRIBUTE, UNKNOWN_ELEMENT


def _ignored_misplaced(child: etree._Element, tag: str, kind: str) -> str | None:
    """Why a core element in the wrong place loses nothing (``None`` when it may: the author's
    pose, geometry or inertia is then silently dropped by every consumer)."""
    if tag == "material" and kind == "collision":
        return "a collision element has no appearance: every consumer ignores it"
    if tag == "origin" and all(_zero(child.get(a)) for a in ("xyz", "rpy")):
        return "an identity pose: it would change nothing where it belongs"
    return None


def _zero(text: str | None) -> bool:
    """Whether an xyz or rpy value is absent or all zeros."""
    try:
        return text is None or all(float(v) == 0.0 for v in text.split())
    except ValueError:
        return False


class UrdfMarkup(UrdfFindings):
    """Findings about the markup of core elements: names URDF does not define where they stand."""

    def check_element(self, element: etree._Element, kind: str, subject: Subject, about: str) -> None:
        """GC106 for unknown attributes and GC105 for unknown children of a core element."""
        self.unknown_attributes(element, kind, subject, about)
        # the shape of a <geometry> is its first element, whatever it is (an unknown one is GC129)
        shape = next((c for c in element if isinstance(c.tag, str)), None) if kind == "geometry" else None
        spec = SPEC[kind]
        for child in element if kind != "robot" else ():  # top level: see top_level_extension
            tag = tag_of(child)
            if tag is None or tag in spec.children or tag in spec.tolerated or child is shape:
                continue
            self.unknown_child(child, tag, kind, subject, about)

    def unknown_attributes(self, element: etree._Element, kind: str, subject: Subject, about: str) -> None:
        """GC106 for the attributes of a core ``<kind>`` URDF does not define, in one finding."""
        spec = SPEC[kind]
        extensions = extension_attributes(kind)  # a tool's own attributes: not typos
        known = spec.attributes | spec.tolerated_attributes | extensions
        unknown = [a for a in element.attrib if not a.startswith("{") and a not in known]
        if not unknown:
            return
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


__all__ = ["UrdfMarkup"]
