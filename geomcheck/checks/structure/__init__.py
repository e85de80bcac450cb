"""GC1xx checks on the parsed model: names, the kinematic tree, joint types, axes, limits, mimics.

Parse-time GC1xx findings (malformed XML, xacro, unknown elements, numbers) come from the
loader; this family looks at the robot as a graph, as the description's format defines it
(URDF, SDFormat, MJCF: which joint types exist, which trees the format's own parser accepts).
Joints and links the loader adds (an MJCF body's weld, an anchor frame, an SDFormat universal
joint's second axis) are part of the graph but never named: a finding names the file's joint
they realise, or the link they hang.

The family's modules, one job each:

- :mod:`~geomcheck.checks.structure.graph`: every finding in a stable order, grouped by source line, and ``run``;
- :mod:`~geomcheck.checks.structure.tree`: GC110-GC117, names, links, roots and loops;
- :mod:`~geomcheck.checks.structure.joints`: GC118-GC123, GC125, GC130, joints and mimics;
- :mod:`~geomcheck.checks.structure.formats`: the joint types and the parser of each format.
"""

from __future__ import annotations

from geomcheck.checks.structure.graph import check_robot, group_by_source_line, run
from geomcheck.checks.structure.tree import cycles

__all__ = ["check_robot", "cycles", "group_by_source_line", "run"]
