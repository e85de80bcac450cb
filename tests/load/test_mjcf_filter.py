"""MuJoCo's collision filter read as disabled pairs: the sweep follows it."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.load import make_bundle
from tests.load.test_mjcf import caster_mjcf, write


@pytest.mark.parametrize("free_base", [True, False])
def test_sweep_follows_mujocos_parent_filter(tmp_path: Path, free_base: bool) -> None:
    from geomcheck.options import CheckOptions, Selection
    from geomcheck.pipeline import run_check

    root = write(tmp_path / "caster.xml", caster_mjcf(free_base))
    report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(selection=Selection(select=("GC4",))))
    found = [(d.code, d.joint, d.links) for d in report.diagnostics if d.code == "GC401"]
    if free_base:
        assert found == []  # MuJoCo never collides a body with its parent: the arm passes through the post
    else:
        # a body welded to the world is the exception: MuJoCo collides it with its children
        assert found == [("GC401", "caster_joint", ("base_link", "caster_link"))]


@pytest.mark.parametrize("flag", ["contact", "constraint"])
def test_a_model_that_turns_contacts_off_collides_no_pair(tmp_path: Path, flag: str) -> None:
    """``<flag contact="disable"/>`` (or ``constraint``, every constraint): MuJoCo computes no
    contact, so the caster clipping the post (a GC401 error with contacts on) is no finding."""
    from geomcheck.load import load_description
    from geomcheck.options import CheckOptions, Selection
    from geomcheck.pipeline import run_check

    text = caster_mjcf(free_base=False).replace("<worldbody>", f'<option><flag {flag}="disable"/></option><worldbody>')
    root = write(tmp_path / "caster.xml", text)
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    declared = loaded.declared_collision_filter
    assert declared is not None
    assert [(p.link1, p.link2, p.reason) for p in declared.disabled] == [
        ("base_link", "caster_link", "contacts-disabled")
    ]
    report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(selection=Selection(select=("GC4",))))
    assert not [d for d in report.diagnostics if d.code in ("GC401", "GC403")]
