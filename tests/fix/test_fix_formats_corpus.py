"""``geomcheck fix --unsafe-fixes`` on an MJCF and an SDFormat corpus robot with GC301
findings, each copied to a temporary folder (the corpus is never written): the fixes are in
the file's own syntax, the fixed file loads with the format's loader, every fixed finding is
gone and none is added."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from geomcheck.fix.run import fix_bundle
from geomcheck.fix.verify import verify
from geomcheck.load import load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.patch.apply import write_sources
from geomcheck.pipeline import run_check
from tests.corpus_robots import corpus_robot

pytestmark = pytest.mark.long

# (robot of robots.toml, a line the fixed file must have: the format's own syntax)
ROBOTS = [
    ("mjcf_ufactory_xarm7", ' quat="'),  # a fitted finger pad: <geom ... type="box" size="..." quat="...">
    ("sdf_mpl_right_arm", "<radius>"),  # a fitted link cylinder: <cylinder><radius>...</radius>
]


@pytest.mark.corpus
@pytest.mark.parametrize(("name", "syntax"), ROBOTS, ids=[n for n, _ in ROBOTS])
def test_fixing_an_mjcf_and_an_sdf_corpus_robot(corpus: Path, name: str, syntax: str, tmp_path: Path) -> None:
    robot = corpus_robot(corpus, name)
    top = corpus / robot.root.relative_to(corpus).parts[0] / robot.root.relative_to(corpus).parts[1]
    folder = Path(os.path.commonpath([str(p) for p in (top, *robot.packages.values())]))
    copy = tmp_path / folder.name
    original = robot.root.read_bytes()
    shutil.copytree(folder, copy, symlinks=True)

    def inside(path: Path) -> Path:
        return copy / path.relative_to(folder)

    bundle = make_bundle(inside(robot.root), {n: inside(p) for n, p in robot.packages.items()}, display_root=tmp_path)
    options = CheckOptions(args=dict(robot.args))
    result = fix_bundle(bundle, options, unsafe=True)
    assert "GC301" in {d.code for d in result.report.diagnostics}
    verified = verify(result, options)
    assert "GC301" in {p.code for p in verified.applied}
    write_sources(bundle, verified.original, verified.final)
    for file, text in verified.final.items():
        added = [line for line in text.splitlines() if line not in verified.original[file].splitlines()]
        assert any(syntax in line for line in added), file
    # the format's own loader reads the fixed files; the fixed findings are gone, none is added
    fixed = load_description(bundle, options.args, options.thresholds.limits)
    assert fixed.format == result.loaded.format
    after = run_check(bundle, options)
    remaining = {d.fingerprint for d in after.diagnostics}
    assert [p.code for p in verified.applied if p.fingerprint in remaining] == []
    known = {d.fingerprint for d in result.report.diagnostics}
    assert [(d.code, d.subject) for d in after.diagnostics if d.fingerprint not in known] == []
    assert robot.root.read_bytes() == original != inside(robot.root).read_bytes()  # the copy was fixed, not the corpus
