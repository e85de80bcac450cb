"""GC5xx: each link's mass and inertia, on their own and against the link's geometry.

Writes the ``inertia`` report section: one entry per link with an ``<inertial>``, in
document order (docs/report-schema.md).

The family's modules, one job each:

- :mod:`~geomcheck.checks.inertia.link`: one link's checks, its section entry, and ``run``;
- :mod:`~geomcheck.checks.inertia.mass`: GC501, GC502, GC508 (mass and density);
- :mod:`~geomcheck.checks.inertia.tensor`: GC503, GC504, GC507 (the tensor alone, copied tensors);
- :mod:`~geomcheck.checks.inertia.bounds`: GC505, moments beyond what the geometry allows;
- :mod:`~geomcheck.checks.inertia.com`: GC506, GC511 (the centre of mass against the part);
- :mod:`~geomcheck.checks.inertia.counterparts`: GC510, left and right inertials not mirrored;
- :mod:`~geomcheck.checks.inertia.weigher`: the severity policy, findings lowered by their consequence;
- :mod:`~geomcheck.checks.inertia.bodies`: the rigid bodies consumers simulate (links merged across fixed joints);
- :mod:`~geomcheck.checks.inertia.placeholders`: values typed for "unknown";
- :mod:`~geomcheck.checks.inertia.points`: each link's geometry points and hulls, read once;
- :mod:`~geomcheck.checks.inertia.values`: reported numbers rounded to what they mean.
"""

from __future__ import annotations

from geomcheck.checks.inertia.link import check_link, run

__all__ = ["check_link", "run"]
