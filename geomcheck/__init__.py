"""geomcheck: collision and geometry verification for robot descriptions (URDF and xacro).

The library is a pipeline: ``load`` (bundle, packages, xacro, URDF, meshes) builds the
typed ``model``; ``kinematics``, ``collision`` and ``geometry`` compute; ``checks`` turn
results into diagnostics of the rules in ``rules``; ``report`` renders one report model.

From Python: ``geomcheck.check(path, **options) -> Report``; ``geomcheck.facade`` also has
``diff(old, new)`` and ``fix(path)``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from geomcheck.version import __version__

if TYPE_CHECKING:
    from geomcheck.facade import check
    from geomcheck.report.model import Report

__all__ = ["Report", "__version__", "check"]


def __getattr__(name: str) -> Any:
    """``geomcheck.check`` and ``Report`` imported on first use, so that
    ``geomcheck --version`` and ``geomcheck rules`` stay as fast as they were."""
    if name == "check":
        from geomcheck import facade

        return getattr(facade, name)
    if name == "Report":
        from geomcheck.report.model import Report

        return Report
    raise AttributeError(f"module 'geomcheck' has no attribute {name!r}")
