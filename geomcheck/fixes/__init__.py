"""What a fix is: the change a finding's fix makes, as data, derived from the finding alone.

The foundations floor, beside the findings (:mod:`geomcheck.diagnostics`) and the rules, as
ruff keeps its ``Fix`` and ``Edit`` below the linter that applies them: a finding's fix is
part of what the finding says, so the findings, the reports and the rule documentation read
it without importing the machinery that plans, applies or verifies fixes.

* :mod:`geomcheck.fixes.model`: :class:`SuggestedFix` and its changes (set an attribute,
  replace an element...), :class:`Edit` (a byte span of a source file and its new text),
  :class:`PlannedFix` (a fix and what became of it);
* :mod:`geomcheck.fixes.derive`: :func:`suggested_fix`, each rule's fix from the numbers its
  finding carries (URDF and xacro), with :mod:`~geomcheck.fixes.derive_mjcf` and
  :mod:`~geomcheck.fixes.derive_sdf` for those formats and :mod:`~geomcheck.fixes.values`
  for the numbers written;
* :mod:`geomcheck.fixes.help_syntax`: a finding's help text in its description's syntax.

A fix as text (planned against the source files, applied) is :mod:`geomcheck.patch`; a fix
checked again before it is written is :mod:`geomcheck.fix`.
"""

from __future__ import annotations

from geomcheck.fixes.derive import rule_fix_note, suggested_fix
from geomcheck.fixes.model import Applicability, Edit, PlannedFix, SuggestedFix

__all__ = ["Applicability", "Edit", "PlannedFix", "SuggestedFix", "rule_fix_note", "suggested_fix"]
