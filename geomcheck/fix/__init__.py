"""``geomcheck fix``: findings' fixes as data, planned against the description's source
files (URDF and xacro, MJCF, SDFormat: each in its own syntax) and applied preserving every
untouched character.

:func:`geomcheck.fix.derive.suggested_fix` gives a finding's fix (``derive_mjcf``,
``derive_sdf`` for those formats), :func:`plan_fixes` turns fixes into edits of the sources
(``plan_formats`` for what MJCF and SDFormat text needs), :mod:`geomcheck.fix.apply` makes
them and writes the diff, :mod:`geomcheck.fix.verify` checks them on a copy first.
"""

from __future__ import annotations

from geomcheck.fix.model import Applicability, Edit, PlannedFix, SuggestedFix

__all__ = ["Applicability", "Edit", "PlannedFix", "SuggestedFix"]
