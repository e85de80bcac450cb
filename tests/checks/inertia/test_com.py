"""GC511 (geomcheck.checks.inertia.com): a centre of mass inside its part but where no real part has it."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.model import Box, Link, Pose, Shape
from tests.checks.inertia.test_link import (
    bundle_dir,
    check,
    codes_of,
    inertial,
    only,
)
from tests.checks.inertia.test_weigher import base_box, on_base

__all__ = ["bundle_dir"]  # the fixture, used by name


def plate(xyz: tuple[float, float, float], com: tuple[float, float, float]) -> Link:
    """A 0.3 x 0.3 x 0.05 m plate drawn at ``xyz`` in its link frame, centre of mass at ``com``."""
    drawn = Shape("visual", 0, Box((0.3, 0.3, 0.05)), Pose(xyz))
    return Link("wheel", inertial=inertial(1.0, (0.01, 0.0, 0.0, 0.01, 0.0, 0.02), xyz=com), visuals=(drawn,))


def test_a_centre_of_mass_left_at_the_link_origin(bundle_dir: Path) -> None:
    d = only(
        check(bundle_dir, on_base(base_box(10.0), plate((0.12, 0.0, 0.0), (0.0, 0.0, 0.0)), "continuous")), "GC511"
    )
    assert (d.link, d.about, d.data["swapped"]) == ("wheel", "com", None)
    assert d.data["distance"] == pytest.approx(0.12) and d.data["size"] == pytest.approx(0.3)
    assert d.message == (
        "centre of mass is written at the link origin (0, 0, 0), as templates leave it, while the part's geometry "
        "centres at (0.12, 0, 0) m, 120 mm away (40% of the part's extent)"
    )


def test_centre_of_mass_coordinates_swapped(bundle_dir: Path) -> None:
    d = only(
        check(bundle_dir, on_base(base_box(10.0), plate((0.08, 0.0, 0.0), (0.0, 0.08, 0.0)), "continuous")), "GC511"
    )
    assert d.data["swapped"] == "xy"
    assert "with its x and y coordinates exchanged, at (0.08, 0, 0) m: they look swapped" in d.message
    fine = check(bundle_dir, on_base(base_box(10.0), plate((0.08, 0.0, 0.0), (0.08, 0.0, 0.0)), "continuous"))
    assert "GC511" not in codes_of(fine)
