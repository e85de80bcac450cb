"""A fix as text: findings' fixes planned against the description's source files (URDF and
xacro, MJCF, SDFormat: each in its own syntax) and applied preserving every untouched
character.

The floor below the pipeline: it reads the loaded description's text and the findings,
never runs a check, so a report can carry its planned patches (:mod:`~geomcheck.patch.section`).

* :mod:`geomcheck.patch.plan`: :func:`plan_fixes`, every finding's
  :class:`~geomcheck.fixes.SuggestedFix` turned into :class:`~geomcheck.fixes.Edit` s of the
  sources, together (an element written once for several links, conflicting edits);
  :mod:`~geomcheck.patch.planner` plans one fix, finding its element by line and tag
  (:mod:`~geomcheck.patch.xmltext`) and following xacro properties
  (:mod:`~geomcheck.patch.xacro_values`); :mod:`~geomcheck.patch.plan_formats` for what MJCF
  and SDFormat text needs; :mod:`~geomcheck.patch.modernise` for legacy xacro syntax;
* :mod:`geomcheck.patch.apply`: the edits made, the files written, the unified diff;
* :mod:`geomcheck.patch.section`: the ``fixes`` section of a report.

What a fix is lies below, in :mod:`geomcheck.fixes`; checking fixes again before they are
written lies above the pipeline, in :mod:`geomcheck.fix`.
"""

from __future__ import annotations

from geomcheck.patch.apply import fixed_sources, unified_diff, write_sources
from geomcheck.patch.plan import FixPlan, plan_fixes

__all__ = ["FixPlan", "fixed_sources", "plan_fixes", "unified_diff", "write_sources"]
