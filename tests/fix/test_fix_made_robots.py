"""``geomcheck fix --unsafe-fixes`` on robots made for the test, outside the corpus: two
quadrupeds with spherical feet, an arm with a parallel gripper, and seeded variations of corpus
robots (their collision primitives resized and moved, their tensors scaled, their meshes read
from the corpus by absolute path). Fixing adds no finding and a second run changes nothing
(:func:`tests.fix.test_fix_every_robot.fix_and_check`), whatever the robot; a fix that cannot
be checked is not written."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.fix import scratch
from geomcheck.fix import verify as verification
from geomcheck.fix.run import fix_bundle
from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from tests.corpus_robots import corpus_robot, expanded_urdf
from tests.fix.robotmakers import Legs, arm_with_gripper, quadruped, variation
from tests.fix.test_fix_every_robot import Copy, fix_and_check

pytestmark = pytest.mark.long

# a second quadruped: smaller, an oversized trunk box behind it, feet spheres too small,
# calves too thick, feet's tensors eighty times too large
SMALL_DOG = Legs(
    trunk=(0.45, 0.22, 0.12),
    thigh=0.2,
    calf=0.2,
    foot_radius=0.025,
    trunk_box_scale=1.3,
    trunk_box_shift=-0.03,
    foot_sphere_scale=0.6,
    calf_radius_scale=2.5,
    foot_inertia_scale=80.0,
)


def made(root: Path, tmp: Path) -> Copy:
    return Copy(root=root, packages={}, srdf=None, args={}, display_root=tmp)


def fix_twice(copy: Copy) -> None:
    before = {d.fingerprint for d in run_check(copy.bundle(), copy.options()).diagnostics}
    assert before, "the robot has findings to fix"
    verified, _ = fix_and_check(copy, before, unsafe=True)
    assert verified.verified and verified.applied  # fixes were applied, each checked on a copy


@pytest.mark.parametrize(
    "make",
    [
        pytest.param(lambda tmp: quadruped(tmp / "dog", "dog"), id="quadruped"),
        pytest.param(lambda tmp: quadruped(tmp / "small_dog", "small_dog", SMALL_DOG), id="small-quadruped"),
        pytest.param(lambda tmp: arm_with_gripper(tmp / "arm"), id="arm-with-gripper"),
    ],
)
def test_fixing_a_made_robot_adds_nothing_and_is_a_fixed_point(make, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    fix_twice(made(make(tmp_path), tmp_path))


@pytest.mark.corpus
@pytest.mark.parametrize(
    ("name", "seed"),
    [
        pytest.param("unitree_a2", 3, marks=pytest.mark.campaign),  # wrote a new GC505 while its fixes went unchecked
        pytest.param("unitree_aliengo", 1, marks=pytest.mark.campaign),
        pytest.param("unitree_aliengo", 9, marks=pytest.mark.campaign),
        pytest.param("pr2_2009_base", 5, marks=pytest.mark.campaign),
        pytest.param("locobot_wx250s", 8, marks=pytest.mark.campaign),
        pytest.param("summit_xl", 4, marks=pytest.mark.campaign),
        pytest.param("husky", 5),
        pytest.param("jackal", 7),
        pytest.param("create2", 11),
    ],
)
def test_fixing_a_variation_of_a_corpus_robot_adds_nothing_and_is_a_fixed_point(
    corpus: Path, name: str, seed: int, tmp_path: Path
) -> None:
    robot = corpus_robot(corpus, name)
    root = variation(expanded_urdf(robot), tmp_path / "made", f"{name}_{seed}", seed, robot.packages)
    fix_twice(made(root, tmp_path))


def test_meshes_named_by_an_absolute_path_are_read_in_place(tmp_path: Path) -> None:
    """A description whose meshes lie far away (an absolute path, another package): the copy
    holds its own folder only, so its fixes are checked instead of written unchecked."""
    elsewhere = quadruped(tmp_path / "elsewhere", "dog")
    text = elsewhere.read_text().replace("package://made/meshes/", f"{elsewhere.parent.parent / 'meshes'}/")
    root = tmp_path / "far" / "robot" / "dog.urdf"
    root.parent.mkdir(parents=True)
    root.write_text(text)
    result = fix_bundle(make_bundle(root, display_root=tmp_path), CheckOptions(), unsafe=True)
    assert scratch.description_folder(result.loaded, None) == root.parent


def test_a_fix_that_cannot_be_checked_is_not_written(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    root = quadruped(tmp_path / "dog", "dog")
    monkeypatch.setattr(scratch, "MAX_SCRATCH_FILES", 0)
    options = CheckOptions()
    verified = verification.verify(fix_bundle(make_bundle(root, display_root=tmp_path), options, unsafe=True), options)
    assert not verified.verified and verified.diff == "" and not verified.applied
    assert {p.reason for p in verified.refused} == {verification.TOO_LARGE}


def test_no_fixed_point_within_the_bound_applies_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Held to four rounds, the dog's verification (which takes five: the last one confirms that
    nothing is left to change) cannot see whether its kept fixes are a fixed point: it applies
    none rather than leave files a second run might change."""
    assert (verification.rounds_bound(3), verification.rounds_bound(10), verification.rounds_bound(500)) == (
        12,
        32,
        200,
    )
    root = quadruped(tmp_path / "dog", "dog")
    options = CheckOptions()
    unbounded = verification.verify(fix_bundle(make_bundle(root, display_root=tmp_path), options, unsafe=True), options)
    monkeypatch.setattr(verification, "rounds_bound", lambda fixes: 4)
    verified = verification.verify(fix_bundle(make_bundle(root, display_root=tmp_path), options, unsafe=True), options)
    assert verified.diff == "" and not verified.applied
    held = [p for p in verified.refused if p.reason.startswith("the fixes reach no fixed point within 4 rounds")]
    # the fixes the rounds had kept when the bound stopped them are held back, none written: they are
    # fixes the unbounded rounds go on to apply
    assert held and {p.fingerprint for p in held} <= {p.fingerprint for p in unbounded.applied}
