"""GC1xx: syntax and structure of the description (XML, xacro, URDF elements, kinematic tree).

Checks live in :mod:`geomcheck.checks.structure` and in the loaders (:mod:`geomcheck.load`). The
rules are declared by sub-family, one module each; importing this package registers them all:

- :mod:`~geomcheck.rules.structure.documents`: GC101-GC104, the document as XML and as xacro;
- :mod:`~geomcheck.rules.structure.elements`: GC105-GC109, GC126, GC127, GC129, URDF elements, attributes, numbers;
- :mod:`~geomcheck.rules.structure.tree`: GC110-GC117, unique names and one kinematic tree;
- :mod:`~geomcheck.rules.structure.joint_elements`: GC118-GC123, GC125, a joint's type, axis, limits, mimic;
- :mod:`~geomcheck.rules.structure.materials`: GC124, GC128, materials;
- :mod:`~geomcheck.rules.structure.metrics`: the data keys several of them share.

GC13x (joints that cannot move as written) is :mod:`geomcheck.rules.joints`.
"""

from __future__ import annotations

from geomcheck.rules.structure.documents import (
    LEGACY_XACRO,
    MALFORMED_XML,
    NON_CONFORMING_XML,
    XACRO_ERROR,
    XACRO_NS,
    XACRO_WARNING,
    XML_VERSION,
)
from geomcheck.rules.structure.elements import (
    INVALID_NUMBER,
    MISSING_ATTRIBUTE,
    MISSING_ELEMENT,
    NUMBER_OUT_OF_RANGE,
    UNKNOWN_ATTRIBUTE,
    UNKNOWN_ELEMENT,
    UNKNOWN_GEOMETRY,
    URDF_VERSION,
)
from geomcheck.rules.structure.joint_elements import (
    INVERTED_LIMITS,
    MIMIC_CYCLE,
    MIMIC_MISSING_JOINT,
    MISSING_LIMITS,
    NON_UNIT_AXIS,
    UNKNOWN_JOINT_TYPE,
    ZERO_AXIS,
)
from geomcheck.rules.structure.materials import (
    DUPLICATE_MATERIAL,
    UNDEFINED_MATERIAL,
)
from geomcheck.rules.structure.tree import (
    CYCLE,
    DUPLICATE_JOINT,
    DUPLICATE_LINK,
    JOINT_MISSING_LINK,
    MULTIPLE_PARENTS,
    MULTIPLE_ROOTS,
    NO_ROOT,
    WORLD_LINK,
)

__all__ = [
    "CYCLE",
    "DUPLICATE_JOINT",
    "DUPLICATE_LINK",
    "DUPLICATE_MATERIAL",
    "INVALID_NUMBER",
    "INVERTED_LIMITS",
    "JOINT_MISSING_LINK",
    "LEGACY_XACRO",
    "MALFORMED_XML",
    "MIMIC_CYCLE",
    "MIMIC_MISSING_JOINT",
    "MISSING_ATTRIBUTE",
    "MISSING_ELEMENT",
    "MISSING_LIMITS",
    "MULTIPLE_PARENTS",
    "MULTIPLE_ROOTS",
    "NON_CONFORMING_XML",
    "NON_UNIT_AXIS",
    "NO_ROOT",
    "NUMBER_OUT_OF_RANGE",
    "UNDEFINED_MATERIAL",
    "UNKNOWN_ATTRIBUTE",
    "UNKNOWN_ELEMENT",
    "UNKNOWN_GEOMETRY",
    "UNKNOWN_JOINT_TYPE",
    "URDF_VERSION",
    "WORLD_LINK",
    "XACRO_ERROR",
    "XACRO_NS",
    "XACRO_WARNING",
    "XML_VERSION",
    "ZERO_AXIS",
]
