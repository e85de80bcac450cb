"""The analyses a run shares: each rule family, run alone on the bundled example, computes
only the products :data:`FAMILY_NEEDS` declares for it and what they depend on; the
structure rules read no mesh."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest

from geomcheck.checks import FAMILY_MODULES, CheckContext
from geomcheck.checks.analyses import DEPENDENCIES, FAMILY_NEEDS, closure, reads_meshes
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.options import CheckOptions

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"


def context(**options: object) -> CheckContext:
    bundle = make_bundle(EXAMPLE)
    loaded = load_description(bundle)
    return CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions(**options))  # type: ignore[arg-type]


def test_every_family_and_product_is_declared() -> None:
    assert set(FAMILY_NEEDS) == set(FAMILY_MODULES)
    for name, parents in DEPENDENCIES.items():
        assert set(parents) <= set(DEPENDENCIES), name
        assert name not in closure(list(parents)), f"{name} depends on itself"
    assert closure(["matrix"]) == {
        "matrix",
        "kinematics",
        "default_configuration",
        "srdf",
        "collision_scene",
        "meshes",
        "model",
    }


def test_only_the_structure_rules_read_no_mesh() -> None:
    assert not reads_meshes(["structure"])
    assert all(reads_meshes([name]) for name in FAMILY_MODULES if name != "structure")


@pytest.mark.parametrize("family", FAMILY_MODULES)
def test_a_family_alone_computes_what_it_declares(family: str) -> None:
    ctx = context(sweep=False, matrix=True, samples=64)
    result = importlib.import_module(f"geomcheck.checks.{family}").run(ctx)
    computed = ctx.analyses.computed()
    assert computed <= closure(FAMILY_NEEDS[family]), sorted(computed - closure(FAMILY_NEEDS[family]))
    if family == "structure":
        assert computed == {"model"}
        assert ctx.meshes.files_read == 0
        assert result.diagnostics == []
    else:
        assert computed - {"model"}


def test_products_are_computed_once() -> None:
    ctx = context(sweep=False)
    first = ctx.analyses.kinematics
    assert ctx.analyses.kinematics is first
    q = ctx.analyses.default_configuration
    assert q.shape == (len(first.joints),)
    assert ctx.analyses.computed() == {
        "model",
        "kinematics",
        "default_configuration",
    }  # no SRDF read without a pose name
    assert ctx.analyses.collision_scene() is ctx.analyses.collision_scene("coal")
    assert "collision_scene" in ctx.analyses.computed()
