"""``geomcheck fix``: findings' fixes as data, planned against the description's source
files (URDF and xacro) and applied preserving every untouched character.

:func:`geomcheck.fix.derive.suggested_fix` gives a finding's fix, :func:`plan_fixes` turns
fixes into edits of the sources, :mod:`geomcheck.fix.apply` makes them and writes the diff.
"""

from __future__ import annotations

from geomcheck.fix.model import Applicability, Edit, PlannedFix, SuggestedFix

__all__ = ["Applicability", "Edit", "PlannedFix", "SuggestedFix"]
