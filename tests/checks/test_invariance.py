"""Order and formatting invariance: benign rewrites of the corpus robots give the same findings.

The robots are those of the corpus's ``robots.toml`` in URDF or xacro (tests/corpus_robots.py: a
robot added there is rewritten too), each expanded once (xacro, with its args) into a URDF in a
temporary folder, mesh filenames relative to its root made absolute; that copy's findings are the
reference. Hypothesis rewrites each without changing its meaning: the top-level
``<link>``/``<joint>``/``<material>`` elements permuted, the children of every link interleaved
differently (``<collision>`` before ``<visual>`` and so on; elements of one kind keep their order,
since ``collision[i]`` is the index ROS tools use), comments and whitespace added, every number
spelt another way (``0.1``, ``1e-1``, ``0.10``, ``+0.1``) and rpy angles moved by a whole turn.
Every rule must then report the same findings: same fingerprints, severities and messages.

The checks run without the continuous-joint sweep, on one example per robot (two for a URDF under
``SMALL_ROBOT_BYTES``): the suite stays within about three minutes on a two-core machine.
"""

from __future__ import annotations

import math
import random
import re
import shutil
from collections.abc import Mapping
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st
from lxml import etree

from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from tests.corpus_robots import corpus_robot, expanded_urdf, robot_params

pytestmark = [pytest.mark.corpus, pytest.mark.long]

NUMERIC_ATTRIBUTES = frozenset(
    [
        "xyz",
        "rpy",
        "size",
        "radius",
        "length",
        "mass",
        "value",
        "ixx",
        "ixy",
        "ixz",
        "iyy",
        "iyz",
        "izz",
        "scale",
        "lower",
        "upper",
        "effort",
        "velocity",
        "damping",
        "friction",
    ]
)
SMALL_ROBOT_BYTES = 100_000  # an expanded URDF below this gets two rewrites, a larger one one [bytes]
Finding = tuple[str, str, str, str]


def spellings(value: float) -> list[str]:
    """Ways of writing ``value`` that parse to exactly the same double."""
    text = repr(value)
    out = [text, f"{value:.17e}", text if text.startswith("-") else f"+{text}"]  # -0.0 is >= 0 but signed
    if "e" not in text and "." in text:
        out.append(text + "0")
    if value == 0.0:
        out.append("0.000")
    return out


def rewrite(source: bytes, seed: int, turns: bool) -> bytes:
    """A benign rewrite of the URDF ``source`` chosen by ``seed``; ``turns`` adds a whole turn
    to rpy angles."""
    rng = random.Random(seed)
    root = etree.fromstring(source, etree.XMLParser(remove_comments=True, remove_blank_text=True))
    top = list(root)
    rng.shuffle(top)
    for child in top:
        root.remove(child)
    for child in top:
        root.append(child)
    for link in root.iter("link"):
        children = list(link)
        kinds = [c.tag for c in children]
        rng.shuffle(kinds)
        queues: dict[object, list[etree._Element]] = {}
        for c in children:
            queues.setdefault(c.tag, []).append(c)
        for c in children:
            link.remove(c)
        for tag in kinds:
            link.append(queues[tag].pop(0))
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        for key, text in list(element.attrib.items()):
            if key not in NUMERIC_ATTRIBUTES:
                continue
            try:
                values = [float(v) for v in text.split()]
            except ValueError:
                continue
            if key == "rpy" and turns:
                values = [v + rng.choice((-1, 0, 1)) * 2.0 * math.pi for v in values]
            element.set(key, " ".join(rng.choice(spellings(v)) for v in values))
    for element in list(root.iter()):
        if isinstance(element.tag, str) and rng.random() < 0.2:
            element.addprevious(etree.Comment(f" rewritten {rng.randrange(10**6)} <not/> a link "))
    etree.indent(root, space=" " * rng.choice((1, 2, 4)))
    return etree.tostring(root, xml_declaration=True, encoding="utf-8")


def findings(path: Path, packages: Mapping[str, Path]) -> set[Finding]:
    report = run_check(make_bundle(path, packages=packages), CheckOptions(sweep=False))
    return {(d.fingerprint, d.code, d.severity.value, d.message) for d in report.diagnostics}


@pytest.mark.parametrize("name", robot_params())
def test_benign_rewrites_keep_every_finding(corpus: Path, tmp_path_factory: pytest.TempPathFactory, name: str) -> None:
    robot = corpus_robot(corpus, name)
    source = expanded_urdf(robot)
    clean = tmp_path_factory.mktemp("clean") / f"{name}.urdf"
    clean.write_bytes(source)
    expected = findings(clean, robot.packages)

    @settings(
        max_examples=2 if len(source) < SMALL_ROBOT_BYTES else 1,
        deadline=None,
        derandomize=True,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
        database=None,
        phases=(Phase.explicit, Phase.generate),  # a seed is its own minimal example: shrinking only costs time
    )
    @given(seed=st.integers(0, 2**32 - 1), turns=st.booleans())
    def check(seed: int, turns: bool) -> None:
        folder = tmp_path_factory.mktemp("rewritten")
        path = folder / f"{name}.urdf"
        rewritten = rewrite(source, seed, turns)
        assert rewritten != source
        path.write_bytes(rewritten)
        got = findings(path, robot.packages)
        assert (sorted(got - expected), sorted(expected - got)) == ([], []), f"seed {seed}, turns {turns}"

    check()


def copied_tensor_robot(order: list[int]) -> str:
    """A hub (3.47 kg) and two wheels (0.44 kg) with the hub's tensor, links in ``order``."""
    tensor = 'ixx="0.0123" ixy="0" ixz="0" iyy="0.0123" iyz="0" izz="0.0154"'
    links = [
        f'<link name="{name}"><inertial><mass value="{mass}"/><inertia {tensor}/></inertial></link>'
        for name, mass in (("wheel_b", 0.44036), ("hub", 3.47308), ("wheel_a", 0.44036), ("hub_twin", 3.47308))
    ]
    joints = "".join(
        f'<joint name="j_{n}" type="revolute"><parent link="hub"/><child link="{n}"/><axis xyz="0 0 1"/>'
        f'<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for n in ("wheel_a", "wheel_b", "hub_twin")
    )
    return '<robot name="r">' + "".join(links[i] for i in order) + joints + "</robot>"


@pytest.mark.parametrize("order", [[0, 1, 2, 3], [3, 2, 1, 0], [2, 0, 3, 1]])
def test_copied_inertia_names_the_same_reference_in_any_order(tmp_path: Path, order: list[int]) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(copied_tensor_robot(order))
    report = run_check(make_bundle(path), CheckOptions(sweep=False))
    copies = {d.link: d.data["copied_from"] for d in report.diagnostics if d.code == "GC507"}
    # the heaviest links sharing the tensor are hub and hub_twin: the reference is the first by name
    assert copies == {"wheel_a": "hub", "wheel_b": "hub"}


BASE_XACRO = Path("pr2_description") / "urdf" / "base_v0" / "base.urdf.xacro"
PROPERTY = re.compile(r'<property name="(\w+)" value="([-+0-9.eE]+)"\s*/>')


def pr2_base_findings(tree: Path) -> set[Finding]:
    root = tree / "pr2_description" / "robots" / "pr2_base.urdf.xacro"
    report = run_check(make_bundle(root, search=(tree,)), CheckOptions(sweep=False))
    return {(d.fingerprint, d.code, d.severity.value, d.message) for d in report.diagnostics}


def test_inlining_a_xacro_property_keeps_every_finding(
    pr2_root: Path, tmp_path_factory: pytest.TempPathFactory
) -> None:
    # copies of the package (never written in the corpus): the clean one is the reference,
    # so that paths in messages compare alike
    clean = tmp_path_factory.mktemp("pr2_clean")
    shutil.copytree(pr2_root / "pr2_description", clean / "pr2_description")
    expected = pr2_base_findings(clean)
    text = (clean / BASE_XACRO).read_text()
    properties = [(name, value) for name, value in PROPERTY.findall(text) if f"${{{name}}}" in text]
    assert len(properties) >= 5

    @settings(max_examples=2, deadline=None, derandomize=True, database=None)
    @given(chosen=st.lists(st.sampled_from(properties), min_size=1, max_size=4, unique=True))
    def check(chosen: list[tuple[str, str]]) -> None:
        tree = tmp_path_factory.mktemp("pr2_inlined")
        shutil.copytree(clean / "pr2_description", tree / "pr2_description")
        rewritten = text
        for name, value in chosen:
            rewritten = rewritten.replace(f"${{{name}}}", value)
        assert rewritten != text
        (tree / BASE_XACRO).write_text(rewritten)
        got = pr2_base_findings(tree)
        # paths differ between the copies: compare what names the subject and the numbers
        assert {f[:3] for f in got} == {f[:3] for f in expected}, chosen
        # messages name files by paths relative to the working folder: the copy's folder name differs
        assert sorted(m.replace(tree.name, "<copy>") for *_, m in got) == sorted(
            m.replace(clean.name, "<copy>") for *_, m in expected
        ), chosen

    check()
