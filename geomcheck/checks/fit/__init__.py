"""GC3xx: each link's collision elements against its visual geometry, and the ``links`` section.

For later families this leaves ``ctx.analyses.fits`` (:class:`geomcheck.checks.analyses.FitTables`):
``links`` (``{link name: LinkFit}``, with each element's suggested primitive), ``visuals``
(``{link name: VisualCloud, or the reason it is unavailable, or None without visuals}``) and
``elements`` (``{link name: [CollisionElement] or a reason}``), all in link frames.
Links whose meshes are missing are skipped with a :class:`SkippedCheck` naming the mesh.
A neighbour's collision element that is the same at every position of the joint between
them (fixed joint; sphere or cylinder on a revolute axis) counts for the link too.

The family's modules, one job each:

- :mod:`~geomcheck.checks.fit.link`: fitting one link, its findings and report entry (``run``);
- :mod:`~geomcheck.checks.fit.shapes`: the link's visual cloud, collision elements and borrowed ones;
- :mod:`~geomcheck.checks.fit.tolerance`: how far a mesh may stick out, at the part's size;
- :mod:`~geomcheck.checks.fit.verdicts`: one fitted element's finding (GC301-GC304, GC306);
- :mod:`~geomcheck.checks.fit.oversize`: GC302's measure of over-coverage;
- :mod:`~geomcheck.checks.fit.lending`: elements lying on a neighbour's mesh, capsule caps;
- :mod:`~geomcheck.checks.fit.at_rest`: coverage at rest, with the neighbours, and a wheel's by its tyre;
- :mod:`~geomcheck.checks.fit.touch`: GC305, what can touch a part without collision geometry.
"""

from __future__ import annotations

from geomcheck.checks.fit.link import check_link, run
from geomcheck.checks.fit.shapes import link_elements, link_visual

__all__ = ["check_link", "link_elements", "link_visual", "run"]
