"""Acceptance of ``geomcheck fix --unsafe-fixes`` on every corpus robot and the bundled example.

Each description is copied to a temporary folder, fixed (verified fixes written), and
checked again: every fixed finding is gone and no finding is added (``ADDED_ALLOWED`` names
the exceptions, with their reasons: none); changed lines differ from the original only inside
attribute values, or are a collision element replaced by the boxes refitted clear of other
links, and every other line is byte-identical; the fixed description still loads, in yourdfpy
too; and fixing again changes nothing. All corpus robots but a quadruped are in the
whole-corpus ``campaign`` (``pytest -m campaign``).
"""

from __future__ import annotations

import difflib
import re
import shutil
from pathlib import Path

import pytest

from geomcheck.errors import InputError
from geomcheck.fix.run import fix_bundle
from geomcheck.fix.verify import Verified, verify
from geomcheck.load import load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.patch.apply import write_sources
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report

REPO = Path(__file__).resolve().parents[2]
ERD = "example-robot-data/robots"
PR2 = "pr2_2009/pr2_description"
# (folder copied, root file inside it); the example is in the repository, the rest in the corpus
ROBOTS = [
    *(
        (f"{ERD}/{name}_description", f"{sub}/{file}.urdf")
        for name, sub, file in [
            ("allegro_hand", "urdf", "allegro_left_hand"),
            ("allegro_hand", "urdf", "allegro_right_hand"),
            ("double_pendulum", "urdf", "double_pendulum"),
            ("double_pendulum", "urdf", "double_pendulum_continuous"),
            ("double_pendulum", "urdf", "double_pendulum_simple"),
            ("laikago", "urdf", "laikago"),
            ("panda", "urdf", "panda"),
            ("panda", "urdf", "panda_collision"),
            ("quadruped", "urdf", "quadruped"),
            ("solo", "robots", "solo"),
            ("solo", "robots", "solo12"),
        ]
    ),
    *(
        (PR2, f"robots/{name}.urdf.xacro")
        for name in [
            "pr2",
            "pr2_base",
            "caster",
            "caster_hub",
            "gripper",
            "head",
            "laser_tilt",
            "shoulder",
            "torso",
            "upperarm",
            "upperarm_wrist",
            "wrist",
            "wrist_gripper",
        ]
    ),
]
EXAMPLE = ("examples/pr2_base", "robots/pr2_base.urdf.xacro")
OPTIONS = CheckOptions()
VALUE = re.compile(r"\"[^\"]*\"|'[^']*'")
ATTRIBUTE = re.compile(r' \w+=""')
INSERTED = re.compile(r"^\s*(<origin( \w+=\"[^\"]*\")+/>|<!--.*-->)\n?$")  # an origin, or why boxes replace a primitive
# the lines of a collision element (a box refitted clear of other links replaces one)
ATTRIBUTES = r"( \w+=\"[^\"]*\")"
COLLISION_LINE = re.compile(
    rf"^\s*(<!--.*-->|</?(collision|geometry){ATTRIBUTES}*>|<geometry>.*</geometry>|<(origin|box|cylinder|sphere){ATTRIBUTES}+\s*/>)\s*$"
)


def fix_copy(source: Path, folder: str, root: str, tmp_path: Path) -> tuple[Path, Report, Verified, Report]:
    """Copy ``source`` (the folder ``folder``) to ``tmp_path``, fix it; (root file, before, verified, after)."""
    shutil.copytree(source, tmp_path / folder)
    root_file = tmp_path / folder / root
    bundle = make_bundle(root_file, display_root=tmp_path)
    try:
        result = fix_bundle(bundle, OPTIONS, unsafe=True)
    except InputError as err:
        pytest.skip(f"{folder}/{root} does not load as it is in the corpus: {err}")
    verified = verify(result, OPTIONS)
    if not verified.final:  # nothing to write: the description and its report stay as they are
        assert verified.applied == ()
        return root_file, result.report, verified, result.report
    write_sources(bundle, verified.original, verified.final)
    after = run_check(make_bundle(root_file, display_root=tmp_path), OPTIONS)
    return root_file, result.report, verified, after


# Findings a fix may add, by (code, subject) and the reason: none. A fix that would add one
# is withdrawn by the verification (docs/fix.md).
ADDED_ALLOWED: dict[tuple[str, str], str] = {}


def assert_fixed(before: Report, verified: Verified, after: Report) -> None:
    remaining = {d.fingerprint for d in after.diagnostics}
    assert [p.code for p in verified.applied if p.fingerprint in remaining] == []
    known = {d.fingerprint for d in before.diagnostics}
    added = [(d.code, d.subject) for d in after.diagnostics if d.fingerprint not in known]
    assert [a for a in added if a not in ADDED_ALLOWED] == []


def same_but_values(before: str, after: str) -> bool:
    """Whether two lines differ only in attribute values and attributes ``after`` adds (tags
    compared without the ``xacro:`` prefix GC103's fix gives legacy instructions)."""

    def plain(line: str) -> str:  # without what GC103's fix writes: prefixes and the namespace
        line = re.sub(r'\s+xmlns:xacro\s*=\s*"[^"]*"', "", line)
        return VALUE.sub('""', line).replace("<xacro:", "<").replace("</xacro:", "</")

    old, new = plain(before), plain(after)
    added = set(ATTRIBUTE.findall(new)) - set(ATTRIBUTE.findall(old))
    return ATTRIBUTE.sub(lambda m: "" if m.group() in added else m.group(), new) == old


def assert_only_values_changed(verified: Verified) -> None:
    for file, original in verified.original.items():
        old, new = original.splitlines(keepends=True), verified.final[file].splitlines(keepends=True)
        for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(None, old, new, autojunk=False).get_opcodes():
            if tag == "equal":
                continue
            inserted = new[j1:j2]
            if all(COLLISION_LINE.match(line) for line in (*old[i1:i2], *inserted)) and any(
                "<collision>" in line for line in inserted
            ):
                continue
            if tag == "insert":
                assert all(INSERTED.match(line) for line in inserted), inserted
                continue
            assert tag == "replace" and i2 - i1 == j2 - j1, (file, old[i1:i2], inserted)
            for before, after in zip(old[i1:i2], inserted, strict=True):
                assert same_but_values(before, after), (file, before, after)


def yourdfpy_links(text: str, tmp_path: Path) -> int | None:
    """Links yourdfpy reads from the URDF ``text``, ``None`` when it refuses it."""
    yourdfpy = pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (pip install yourdfpy)")
    path = tmp_path / "expanded.urdf"
    path.write_text(text)
    try:
        robot = yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=False)
    except Exception:  # yourdfpy raises what its parser meets: a refusal of the original is not ours
        return None
    return len(robot.robot.links)


def check_robot(source: Path, folder: str, root: str, tmp_path: Path) -> tuple[Report, Verified, Report]:
    root_file, before, verified, after = fix_copy(source, folder, root, tmp_path)
    original_text = load_description(make_bundle(source / root, display_root=source.parent)).document.text
    assert_fixed(before, verified, after)
    assert_only_values_changed(verified)
    fixed = load_description(make_bundle(root_file, display_root=tmp_path))
    assert len(fixed.robot.links) == after.robot.links == before.robot.links
    if yourdfpy_links(original_text, tmp_path) is not None:
        assert yourdfpy_links(fixed.document.text, tmp_path) == len(fixed.robot.links)
    if verified.final:
        again = verify(fix_bundle(make_bundle(root_file, display_root=tmp_path), OPTIONS, unsafe=True), OPTIONS)
        assert (again.applied, again.final) == ((), {})
    return before, verified, after


# run by default: a quadruped; the rest in the whole-corpus campaign
DEFAULT_RUN = {"quadruped.urdf"}
PARAMS = [
    pytest.param(
        f, r, id=f"{f.split('/')[-1]}:{Path(r).name}", marks=() if Path(r).name in DEFAULT_RUN else pytest.mark.campaign
    )
    for f, r in ROBOTS
]


@pytest.mark.parametrize(("folder", "root"), PARAMS)
def test_fixing_a_corpus_robot(corpus: Path, folder: str, root: str, tmp_path: Path) -> None:
    check_robot(corpus / folder, folder, root, tmp_path / "work")


def test_fixing_the_example(tmp_path: Path) -> None:
    folder, root = EXAMPLE
    before, verified, after = check_robot(REPO / folder, "pr2_base", root, tmp_path / "work")
    # one macro line written for four casters and eight wheels: one finding each (grouped)
    assert sorted((p.code, p.subject) for p in verified.applied) == sorted(
        [
            *(("GC103", "robot") for _ in range(4)),  # the four legacy xacro files modernised
            ("GC301", "link base_link"),
            ("GC301", "link bl_caster_rotation_link"),
            ("GC505", "link base_laser_link"),
            ("GC505", "link bl_caster_l_wheel_link"),
        ]
    )
    assert verified.refused == ()
    # the base's box refitted clear of the wheels: a box per part of the shell
    base = next(p for p in verified.applied if p.subject == "link base_link")
    assert base.fix.title.startswith("replace the box by ") and "fl_caster_l_wheel_link" in base.fix.title
    # ... and says why it is not the one box the finding's help suggests
    assert verified.refitted == (base,)
    assert re.search(r": the fitted box would overlap them by up to \d+ mm$", base.fix.title), base.fix.title
    written = "".join(verified.final.values())
    assert f"<!-- {base.fix.title.removeprefix('replace the box by ')} -->" in written
    # the caster's fix is the box its help suggests; the help says why it is taller than the
    # part of the mesh the message measures (it takes over what the wheels' geometry covers)
    caster = next(d for d in before.diagnostics if d.code == "GC301" and d.link == "bl_caster_rotation_link")
    assert "the mesh spans 0.134 m (z 0.0343 to 0.168 m)" in caster.message
    assert "a fitted box (z -0.025 to 0.168 m, past the part of the mesh measured above" in caster.help
    assert caster.help.endswith('<geometry><box size="0.187 0.15 0.193"/></geometry>')
    fixed_caster = next(p for p in verified.applied if p.subject == "link bl_caster_rotation_link")
    assert fixed_caster.fix == caster.fix and 'geometry/box size="0.187 0.15 0.193"' in [
        c.describe() for c in fixed_caster.fix.changes
    ]
    assert [d for d in after.diagnostics if d.fingerprint not in {b.fingerprint for b in before.diagnostics}] == []
    # the wheels' copied-inertia findings go with the copied tensor
    assert [d for d in after.diagnostics if d.code in ("GC505", "GC507")] == []
