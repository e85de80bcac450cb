"""Property-based fuzzing of the loader and the CLI with structure-aware mutations of robot
descriptions: elements deleted and duplicated, garbage, NaN, inf and 1e308 in attributes,
Unicode names, deep nesting and huge counts, over the corpus's URDF and xacro files and a
small built-in robot.

Whatever the input, loading ends with a description or a :class:`GeomcheckError`, and the
CLI with exit 0 or 1 and a JSON report (validated against the schema by the suite's hook) or
exit 2 and one line on stderr: never a traceback, never more than 10 s. Examples are derived
from a fixed seed (``derandomize``) so CI runs the same inputs every time.
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, example, given, note
from hypothesis import strategies as st
from lxml import etree

from geomcheck.cli import main
from geomcheck.errors import GeomcheckError
from geomcheck.load import load_description, make_bundle
from tests.conftest import corpus_dir
from tests.load.fuzztools import bounded, fuzz_settings

pytestmark = pytest.mark.long

COPIES = 100  # copies made by one "copies" mutation (unjoined links, duplicate joints) [count]
NEST_LEVELS = 300  # wrappers added by one "nest" mutation: deeper than the nesting limit [levels]
MAX_ELEMENTS = 20_000  # a mutated document stays below this many elements [count]
# too_slow: drawing an index into a large corpus document and up to five mutations with text
# values takes longer than hypothesis's generation budget at times; the inputs are what we want
FUZZ = fuzz_settings(150, HealthCheck.too_slow)  # GEOMCHECK_FUZZ_EXAMPLES=2000 for a long campaign

SMALL_ROBOT = """<?xml version="1.0"?>
<robot name="fuzz" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="r" value="0.05"/>
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base_link">
    <visual><geometry><box size="0.4 0.3 0.1"/></geometry><material name="grey"/></visual>
    <collision><origin xyz="0 0 0.01" rpy="0 0 0"/><geometry><box size="0.4 0.3 0.12"/></geometry></collision>
    <inertial><mass value="3.0"/><inertia ixx="0.03" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.06"/></inertial>
  </link>
  <link name="arm">
    <visual><geometry><cylinder radius="${r}" length="0.4"/></geometry></visual>
    <collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="${r}" length="0.4"/></geometry></collision>
    <inertial><origin xyz="0 0 0.2"/><mass value="0.5"/>
      <inertia ixx="0.007" ixy="0" ixz="0" iyy="0.007" iyz="0" izz="0.0006"/></inertial>
  </link>
  <link name="wheel">
    <collision><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="arm"/><origin xyz="0 0 0.06"/><axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="1"/>
  </joint>
  <joint name="spin" type="continuous">
    <parent link="base_link"/><child link="wheel"/><origin xyz="0.25 0 -0.05"/><axis xyz="0 1 0"/>
  </joint>
</robot>
"""

NASTY_VALUES = [
    "nan",
    "NaN NaN NaN",
    "inf",
    "-inf 0 0",
    "1e308",
    "1e308 1e308 1e308",
    "-1e308 0 0",
    "1e-320",
    "0",
    "0 0 0",
    "-1",
    "",
    "   ",
    "1 2",
    "1 2 3 4 5",
    "0x10",
    "1,5",
    "${1/0}",
    "${10**10**10}",
    "$(env HOME)",
    "$(find nowhere)",
    "bäse_łink",
    "ロボット",
    "\u202eknil",
    "a" * 5000,
    "package://../../etc/passwd",
    "/dev/zero",
    "file:///etc/shadow",
]
URDF_ATTRIBUTES = [
    "name",
    "xyz",
    "rpy",
    "size",
    "radius",
    "length",
    "value",
    "ixx",
    "lower",
    "upper",
    "filename",
    "scale",
    "type",
    "link",
    "rgba",
]


def corpus_files() -> list[Path]:
    root = corpus_dir()
    if root is None:
        return []
    found = sorted(root.rglob("*.urdf")) + sorted(p for p in root.rglob("*.urdf.xacro") if p.stat().st_size < 20_000)
    return [p for p in found if p.stat().st_size < 200_000]


@st.composite
def mutation(draw: st.DrawFn) -> tuple[str, int, str, str]:
    kind = draw(st.sampled_from(["delete", "duplicate", "attribute", "rename", "nest", "copies", "text"]))
    index = draw(st.integers(min_value=0, max_value=10_000))
    attribute = draw(st.sampled_from(URDF_ATTRIBUTES))
    value = draw(st.one_of(st.sampled_from(NASTY_VALUES), st.text(max_size=40)))
    return kind, index, attribute, value


def xml_safe(text: str) -> str:
    return "".join(c for c in text if c in "\t\n\r" or (" " <= c <= "\ud7ff") or ("\ue000" <= c <= "\ufffd"))


def mutate(data: bytes, mutations: list[tuple[str, int, str, str]]) -> bytes:
    """``data`` (an XML document) with ``mutations`` applied to its elements."""
    root = etree.fromstring(data, etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False))
    for kind, index, attribute, value in mutations:
        elements = [e for e in root.iter() if isinstance(e.tag, str)]
        target = elements[index % len(elements)]
        parent = target.getparent()
        grows = {"duplicate": 1, "copies": COPIES, "nest": 1}.get(kind, 0) * sum(1 for _ in target.iter())
        if len(elements) + grows + (NEST_LEVELS if kind == "nest" else 0) > MAX_ELEMENTS:
            continue  # mutations compound: keep the document (and the fuzzer) bounded
        if kind == "delete" and parent is not None:
            parent.remove(target)
        elif kind == "duplicate" and parent is not None:
            parent.insert(parent.index(target), copy.deepcopy(target))
        elif kind == "attribute":
            target.set(attribute, xml_safe(value))
        elif kind == "rename":
            with contextlib.suppress(ValueError):  # a value that is no XML name leaves the tag alone
                target.tag = xml_safe(value).strip().replace(" ", "_").replace(":", "_") or "x"
        elif kind == "nest" and parent is not None:
            holder = target  # appending moves it out of its parent
            for _ in range(NEST_LEVELS):
                wrapper = etree.Element("link")
                wrapper.append(holder)
                holder = wrapper
            parent.append(holder)
        elif kind == "copies" and parent is not None:
            for n in range(COPIES):
                clone = copy.deepcopy(target)
                if clone.get("name") is not None:
                    clone.set("name", f"{clone.get('name')}_{n}")
                parent.append(clone)
        elif kind == "text":
            target.text = xml_safe(value)
    return etree.tostring(root, xml_declaration=True, encoding="utf-8")


def assert_loads_or_refuses(path: Path, display_root: Path, search: list[Path]) -> None:
    with bounded():
        try:
            loaded = load_description(make_bundle(path, search=search, display_root=display_root, confined=True))
        except GeomcheckError as err:
            assert "\n" not in str(err), "a tool failure is one line"
            event(f"refused: {type(err).__name__}")
        else:
            assert loaded.robot is not None
            event("loaded")


@pytest.fixture(scope="module", autouse=True)
def _warm() -> None:
    """One untimed run first: the time limit is about the input, not about importing numpy."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "warm.urdf.xacro"
        path.write_text(SMALL_ROBOT, encoding="utf-8")
        _run_cli(path)


@FUZZ
@example(mutations=[("text", 11, "name", "${10**10**10}")])  # ran for hours in a trusted run (docs/robustness.md)
@given(mutations=st.lists(mutation(), min_size=1, max_size=4))
def test_mutated_small_robot_through_the_cli(mutations: list[tuple[str, int, str, str]]) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "fuzz.urdf.xacro"
        path.write_bytes(mutate(SMALL_ROBOT.encode(), mutations))
        note(path.read_text(encoding="utf-8", errors="replace"))  # printed with a failure: the input to reproduce
        with bounded():
            status = _run_cli(path)
        event(f"exit {status}")  # the outcomes' spread, shown by --hypothesis-show-statistics


def _run_cli(path: Path) -> int:
    """The exit status of ``geomcheck check path``, after checking that it ends as promised."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(["check", str(path), "--format", "json", "--no-sweep", "--no-untrusted"])
    text, message = out.getvalue(), err.getvalue()
    assert "Traceback" not in message and "internal error" not in message, message
    if status == 2:
        assert text == "" and message.count("\n") == 1 and message.startswith("geomcheck: error: "), message
    else:
        assert status in (0, 1)
        assert message == "", f"library output leaked to stderr: {message[:300]}"
        assert json.loads(text)["schema"] == "geomcheck.report/1"
    return status


CORPUS = corpus_files()


@pytest.mark.skipif(not CORPUS, reason="shared robot corpus not available: set GEOMCHECK_CORPUS to ../shared/corpus")
@FUZZ
@given(
    index=st.integers(min_value=0, max_value=len(CORPUS) - 1 if CORPUS else 0),
    mutations=st.lists(mutation(), min_size=1, max_size=5),
)
def test_mutated_corpus_descriptions_load_or_are_refused(
    index: int, mutations: list[tuple[str, int, str, str]]
) -> None:
    source = CORPUS[index]
    corpus = corpus_dir()
    assert corpus is not None
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / source.name
        path.write_bytes(mutate(source.read_bytes(), mutations))
        note(f"{source.name}, mutated by {mutations!r}")  # printed with a failure: the input to reproduce
        assert_loads_or_refuses(path, Path(folder), [corpus])
