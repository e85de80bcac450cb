"""Recall on defects robot maintainers fixed themselves (``../shared/corpus/history``, read by
``scripts/history_cases.py``): the version before each fix is flagged on the element the fix
changed, the flag clears after the fix, and a fixed version's new finding is a defect the fix left.

The whole suite is a campaign (``pytest -m campaign``; ``benchmarks/history_recall.py`` prints the
same figures); the default run checks one case of each rule the suite first asked for.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.corpustools import script

pytestmark = pytest.mark.corpus
MIN_FLAGGED = 0.80  # of the cases, flagged before the fix
MIN_CLEARED = 0.90  # of the flagged cases, cleared after it
# a fixed version that still gets, or newly gets, an error or warning on a changed element: the defect the fix left,
# as docs/precision.md explains (a judgement of the fix, not of geomcheck's result)
REMAINING_AFTER_FIX = {
    "sr_lfmetacarpal_collision": "the moved box sits on the link's z axis, 31 mm beside the 55-degree tilted part",
    "sr_forearm_lite_scale": "the muscle variant keeps the 0.37 m forearm's collision on the 0.155 m lite mesh",
    "turtlebot_xtion_scale": "the added scale=0.001 shrinks a mesh that already declares millimetres, for RViz",
    "robotiq_smodel_palm_inertial": "the tensor moved into the palm breaks the triangle inequality",
    "robotiq_140_mimic_limits": "the outer knuckle's new limits stop 0.05 rad short of the finger joint's range",
}
# a case per rule the history first asked for: (case, the rule that must flag its version before the fix)
FIRST_ASKED = {
    "baxter_null_gripper_mass": "GC502",  # a zero mass carrying a tensor
    "robotiq_140_mimic_limits": "GC130",  # mimic joints that cannot follow their leader
    "robotiq_smodel_palm_inertial": "GC105",  # an <inertial> after its </link>
    "hector_geiger_collision_missing": "GC305",  # a root body's part without collision geometry
    "hector_camera360_visual_size": "GC302",  # a collision sphere standing off its part
    "fanuc_r2000ib_j6_axis": "GC420",  # a flange turned about another axis than its own
    "sr_lfmetacarpal_com": "GC506",  # a light link's centre of mass outside it, kept at warning
}


def history(corpus: Path) -> Any:
    module = script("history_cases")
    if module.history_dir(corpus) is None:
        pytest.skip("the corpus has no history/ folder")
    return module


def case_outcome(module: Any, case: Any) -> Any:
    return module.outcome(case, module.check_side(case, "before"), module.check_side(case, "after"))


@pytest.mark.parametrize("name", sorted(FIRST_ASKED))
def test_a_maintainers_fix_is_flagged_before_and_cleared_after(corpus: Path, name: str) -> None:
    module = history(corpus)
    [case] = [c for c in module.cases(corpus) if c.name == name]
    found = case_outcome(module, case)
    assert FIRST_ASKED[name] in found.flagged_codes, [d["message"] for d in found.before]
    if name not in REMAINING_AFTER_FIX:
        assert found.cleared, [d["message"] for d in found.after]


@pytest.mark.campaign
def test_recall_on_every_maintainers_fix(corpus: Path) -> None:
    module = history(corpus)
    outcomes = [case_outcome(module, c) for c in module.cases(corpus)]
    flagged = [o for o in outcomes if o.flagged]
    cleared = [o for o in flagged if o.cleared]
    assert len(flagged) >= MIN_FLAGGED * len(outcomes), module.table(outcomes)
    assert len(cleared) >= MIN_CLEARED * len(flagged), module.table(outcomes)
    unexplained = {o.case.name: sorted(o.new_after) for o in outcomes if o.new_after}.keys() - REMAINING_AFTER_FIX
    assert not unexplained, f"a fixed version gets a new finding: {sorted(unexplained)}"
