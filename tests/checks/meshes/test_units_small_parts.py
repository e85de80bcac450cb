"""GC205 and a small part: a mesh a unit factor too small must, scaled back up about its file's
origin, still lie on the robot; a small part drawn far from its file's origin is just small."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh

from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions, Selection
from geomcheck.pipeline import run_check

LINK = """  <link name="{name}">
    <visual><geometry><box size="0.06 0.06 0.06"/></geometry></visual>{extra}
  </link>
"""
JOINT = """  <joint name="j{i}" type="fixed"><parent link="l{parent}"/><child link="l{i}"/>
    <origin xyz="0.1 0 0"/></joint>
"""


def gc205(tmp_path: Path, offset: float) -> list[tuple[str | None, float]]:
    part = trimesh.creation.box(extents=(0.0026, 0.0026, 0.0026))
    part.apply_translation((offset, 0.0, 0.0))
    part.export(tmp_path / "part.stl")
    extra = '\n    <visual><geometry><mesh filename="part.stl"/></geometry></visual>'
    links = "".join(LINK.format(name=f"l{i}", extra=extra if i == 0 else "") for i in range(4))
    joints = "".join(JOINT.format(i=i, parent=i - 1) for i in range(1, 4))
    (tmp_path / "r.urdf").write_text(f'<robot name="r">\n{links}{joints}</robot>\n')
    options = CheckOptions(selection=Selection(select=("GC2",)), workers=1)
    report = run_check(make_bundle(tmp_path / "r.urdf", display_root=tmp_path), options)
    return [(d.link, float(d.data["factor"])) for d in report.diagnostics if d.code == "GC205"]


@pytest.mark.parametrize(("offset", "found"), [(0.0, True), (0.169, False)], ids=["at-origin", "far"])
def test_a_small_mesh_is_in_another_unit_only_if_scaled_up_it_stays_on_the_robot(
    tmp_path: Path, offset: float, found: bool
) -> None:
    # 2.6 mm against 60 mm boxes: a ratio of 1/23, near 1/25.4 (millimetres scaled as inches);
    # the robot spans 0.3 m of joints and 60 mm parts: scaled up 25.4x, the far part would lie
    # 4.3 m away, the part at the origin within its link
    expected = [("l0", pytest.approx(1 / 25.4, rel=1e-4))] if found else []  # the factor to 6 digits
    assert gc205(tmp_path, offset) == expected
